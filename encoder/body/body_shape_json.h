// The body shape as pose files carry it ("body_shape": stature, 16 segment
// lengths and girths, the neck's girth ratio), written by fvv track and fvv
// capture register and read back by the encoder, which must rebuild the very
// body the poses were fitted with.
#ifndef FVV_ENCODER_BODY_BODY_SHAPE_JSON_H_
#define FVV_ENCODER_BODY_BODY_SHAPE_JSON_H_

#include <nlohmann/json.hpp>

#include "codec/base/status.h"
#include "encoder/body/generic_body.h"

namespace fvv {

nlohmann::json BodyShapeToJson(const BodyShape& shape);

// Reads what BodyShapeToJson writes and checks it (ValidateBodyShape). Files
// written before the neck ratio existed lack it: their necks follow the head
// (ratio 1), as they did when they were fitted.
StatusOr<BodyShape> BodyShapeFromJson(const nlohmann::json& j, const std::string& what);

}  // namespace fvv

#endif  // FVV_ENCODER_BODY_BODY_SHAPE_JSON_H_
