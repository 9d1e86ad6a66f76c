// Surface detail for the built-in synthetic actor: smooth bumps and hollows
// (like clothing folds and build the generic model does not have) displaced
// along the normals of the bind-pose mesh. With it, a synthetic capture's true
// surface departs from every generic-model fit by centimetres, which is what
// shape refinement must recover; the test knows the true surface.
#ifndef FVV_TOOLS_SYNTH_SURFACE_DETAIL_H_
#define FVV_TOOLS_SYNTH_SURFACE_DETAIL_H_

#include <cstdint>

#include "container/body_model.h"

namespace fvv {

// Displaces every vertex along its normal by up to `amplitude` metres outwards
// and half that inwards: a sum of Gaussian bumps (radius about 7 cm, random signs and centres on
// the body, from `seed`), so seam copies move together and the mesh stays closed. Normals are
// recomputed. amplitude 0 leaves the model as it is.
void AddSurfaceDetail(double amplitude, uint32_t seed, BodyModel* model);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_SURFACE_DETAIL_H_
