#include "encoder/body/body_shape_json.h"

#include <array>
#include <string>

namespace fvv {

nlohmann::json BodyShapeToJson(const BodyShape& shape) {
  return {{"stature", shape.stature},
          {"length", shape.length},
          {"girth", shape.girth},
          {"neck_ratio", shape.neck_ratio}};
}

StatusOr<BodyShape> BodyShapeFromJson(const nlohmann::json& j, const std::string& what) {
  auto number = [&](const char* key, bool required, double* out) -> Status {
    if (!j.contains(key)) {
      return required ? Corrupt(what + ": body_shape has no " + key) : Status::Ok();
    }
    if (!j[key].is_number()) return Corrupt(what + ": body_shape." + key + " is not a number");
    *out = j[key].get<double>();
    return Status::Ok();
  };
  auto scales = [&](const char* key, std::array<double, kGenericSegmentCount>* out) -> Status {
    const bool ok = j.contains(key) && j[key].is_array() && j[key].size() == kGenericSegmentCount;
    if (!ok) return Corrupt(what + ": body_shape." + key + " must list 16 numbers");
    for (int s = 0; s < kGenericSegmentCount; ++s) {
      if (!j[key][s].is_number())
        return Corrupt(what + ": body_shape." + key + " holds a non-number");
      (*out)[s] = j[key][s].get<double>();
    }
    return Status::Ok();
  };
  if (!j.is_object()) return Corrupt(what + ": body_shape is not an object");
  BodyShape shape;
  FVV_RETURN_IF_ERROR(number("stature", true, &shape.stature));
  FVV_RETURN_IF_ERROR(scales("length", &shape.length));
  FVV_RETURN_IF_ERROR(scales("girth", &shape.girth));
  FVV_RETURN_IF_ERROR(number("neck_ratio", false, &shape.neck_ratio));
  const Status valid = ValidateBodyShape(shape);
  if (!valid.ok()) return Corrupt(what + ": " + valid.message());
  return shape;
}

}  // namespace fvv
