// How near a stream's surface lies to a synthetic actor's true surface: per
// frame, each true vertex's distance to the surface a player draws (the
// frame's own surface where the stream carries it, else the model's), both
// posed. The truth is `fvv synth`'s truth/surface_fNNNNNN.bin (its actor's
// own mesh, so the vertex counts differ).
#ifndef FVV_TOOLS_SYNTH_SURFACE_DISTANCE_H_
#define FVV_TOOLS_SYNTH_SURFACE_DISTANCE_H_

#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

// Frames 0 .. frames - 1; metres, one vector per frame.
StatusOr<std::vector<std::vector<double>>> DistanceToTrueSurface(const std::string& stream,
                                                                 const std::string& truth_dir,
                                                                 uint32_t frames);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_SURFACE_DISTANCE_H_
