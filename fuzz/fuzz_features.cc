// Fuzz target: the feature points file of `fvv register` (features.json),
// parsed against two fixed cameras facing each other's side of a person, then
// each parsed frame triangulated as registration does, so what the parser lets
// through also reaches the least squares.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "encoder/track/features.h"

namespace {

std::vector<fvv::Camera> TwoCameras() {
  fvv::Camera a;
  a.name = "cam00";
  a.width = 640;
  a.height = 480;
  a.fx = a.fy = 600;
  a.cx = 319.5;
  a.cy = 239.5;
  a.distortion = {-0.1, 0.01, 0.001, -0.001, 0};
  a.translation = {0, -1, 3};
  fvv::Camera b = a;
  b.name = "cam01";
  b.rotation = {0, 0, -1, 0, 1, 0, 1, 0, 0};  // a quarter turn about y
  b.distortion = {};
  return {a, b};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<fvv::Camera> cameras = TwoCameras();
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto features = fvv::ParseFeatures(text, cameras, 100, "features.json");
  if (!features.ok()) return 0;
  for (const auto& frame : features->frames) (void)fvv::TriangulateFeatures(frame.second, cameras);
  return 0;
}
