// `fvv synth`: renders an animated, textured character from calibrated studio
// cameras with real OpenGL (OSMesa) and writes a capture directory plus ground
// truth (docs/capture-format.md):
//   DIR/capture.json, DIR/<camera>/NNNNNN.png, DIR/background/<camera>.png
//   DIR/truth/truth.json          poses, 3D joints, generator settings
//   DIR/truth/silhouettes/<camera>/NNNNNN.png
//   DIR/truth/texture.png         the actor's surface texture
//   DIR/truth/heldout/            held-out cameras: a capture of their own
// Deterministic for a given seed.
#ifndef FVV_TOOLS_SYNTH_SYNTH_H_
#define FVV_TOOLS_SYNTH_SYNTH_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "encoder/capture/capture.h"
#include "tools/synth/actor.h"

namespace fvv {

struct SynthOptions {
  std::string output_dir;
  uint32_t cameras = 8;
  bool overhead = false;  // one more camera looking down from above the centre
  // Instead of the ring: a dome of this many cameras (MakeDomeCameras); 0: the ring.
  uint32_t dome = 0;
  uint32_t width = 640, height = 480;
  double fps = 25;
  uint32_t frames = 50;
  uint32_t seed = 1;
  std::string motion;             // a BVH file; empty: the built-in walk
  double motion_start = 0;        // seconds into the BVH clip
  std::string actor = "builtin";  // "builtin" or a glTF 2.0 file (.glb/.gltf)
  double stature = 1.0;           // the built-in actor's size (1.0 = 1.75 m)
  double surface_detail = 0.0;    // the built-in actor's bumps off the generic shape (metres)
  double garment = 0.0;  // the built-in actor's loose shorts: their flare (metres, garment.h)
  double noise = 1.5;    // sensor noise, standard deviation in 8-bit levels
  double colour_mismatch = 0.0;   // per-camera gain spread, e.g. 0.05 for +-5 %
  bool unlit = false;             // the actor without shading: its texture's own colours
  uint32_t held_out = 2;          // extra cameras for novel-view evaluation
  bool link_silhouettes = false;  // also list the true silhouettes in capture.json
  uint32_t texture_size = 1024;
  // Conditions of real studios: no empty-studio plates; furniture and equipment
  // standing around the capture volume; a second person walking through behind
  // the actor (in the frames only: not in the truth, the plates or features).
  bool plates = true;
  bool clutter = false;
  bool bystander = false;
  // Film with a capture's cameras instead of the ring (rig.h): a capture
  // directory or capture.json. Each camera keeps its own image size.
  std::string rig;
  // With `rig`: the built-in actor moves as these poses say (a poses.json of
  // a take that rig filmed), in their fitted proportions.
  std::string rig_poses;
  // Degrees: each camera films turned by this much about an axis in its
  // image plane (a direction drawn from the seed), while capture.json
  // records it unturned: a calibration off by about focal length times
  // this angle in image shift, as real ones are.
  double calibration_error = 0;
  std::function<void(const std::string&)> progress;  // one line per update
};

struct SynthSummary {
  Capture capture;
  std::string actor;
  double seconds = 0;
};

// The studio ring: `count` cameras at equal angles (radius 3.6 m, heights
// alternating 1.3 m and 2.0 m) looking at the capture volume's centre, plus an
// overhead camera when asked. `phase` offsets the angles (held-out cameras sit
// between ring cameras).
std::vector<Camera> MakeStudioCameras(uint32_t count, uint32_t width, uint32_t height, double phase,
                                      const std::string& prefix);

// A studio dome: `count` cameras (4..256) on four rings around the capture
// volume, low (0.5 m, 3.4 m out), middle (1.4 m, 3.8 m), high (2.4 m, 3.6 m)
// and top (3.3 m, 2.6 m, looking down; the low ring looks up at 1 m, the
// others at 0.9 m), a quarter, a third, a quarter and the
// rest of them, each ring turned half a step against the one below so that no
// camera stands above another. Every fifth camera of the lower three rings is
// zoomed in (2.2 times the focal length) on the upper or the lower body, so
// it sees the actor partly, as close-ups in real domes do.
std::vector<Camera> MakeDomeCameras(uint32_t count, uint32_t width, uint32_t height);

// Builds the actor the options describe.
StatusOr<std::unique_ptr<Actor>> MakeSynthActor(const SynthOptions& options);

StatusOr<SynthSummary> RunSynth(const SynthOptions& options);

}  // namespace fvv

#endif  // FVV_TOOLS_SYNTH_SYNTH_H_
