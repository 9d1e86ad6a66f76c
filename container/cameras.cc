#include "container/cameras.h"

#include <cmath>

namespace fvv {

std::array<double, 3> Camera::Centre() const {
  std::array<double, 3> c{};
  for (int i = 0; i < 3; ++i) {
    c[i] = -(rotation[0 + i] * translation[0] + rotation[3 + i] * translation[1] +
             rotation[6 + i] * translation[2]);
  }
  return c;
}

std::vector<uint8_t> WriteCamerasBox(const std::vector<Camera>& cameras) {
  ByteWriter w;
  w.U16(static_cast<uint32_t>(cameras.size()));
  for (const Camera& c : cameras) {
    w.Str(c.name);
    w.U32(c.width);
    w.U32(c.height);
    for (double v : {c.fx, c.fy, c.cx, c.cy}) w.F64(v);
    for (double v : c.distortion) w.F64(v);
    for (double v : c.rotation) w.F64(v);
    for (double v : c.translation) w.F64(v);
  }
  return MakeBox(box::kCameras, 0, kBoxFlagEssential, w.bytes());
}

namespace {

Status CheckCamera(const Camera& c, size_t index, const BoxHeader& box) {
  const std::string at =
      BoxContext(box) + "camera " + std::to_string(index) + " ('" + c.name + "'): ";
  if (c.width == 0 || c.height == 0 || c.width > 65535 || c.height > 65535) {
    return Corrupt(at + "image size " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                   " outside 1..65535");
  }
  for (double v : {c.fx, c.fy, c.cx, c.cy}) {
    if (!std::isfinite(v)) return Corrupt(at + "non-finite intrinsics");
  }
  if (!(c.fx > 0) || !(c.fy > 0)) return Corrupt(at + "focal length not positive");
  for (double v : c.distortion) {
    if (!std::isfinite(v)) return Corrupt(at + "non-finite distortion");
  }
  for (double v : c.translation) {
    if (!std::isfinite(v)) return Corrupt(at + "non-finite translation");
  }
  // R must be a rotation: orthonormal rows, determinant +1 (loose tolerance:
  // calibration files round to a few digits).
  const auto& R = c.rotation;
  for (double v : R) {
    if (!std::isfinite(v)) return Corrupt(at + "non-finite rotation");
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double d =
          R[3 * i] * R[3 * j] + R[3 * i + 1] * R[3 * j + 1] + R[3 * i + 2] * R[3 * j + 2];
      if (std::fabs(d - (i == j ? 1.0 : 0.0)) > 1e-3) {
        return Corrupt(at + "rotation matrix is not orthonormal");
      }
    }
  }
  const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                     R[2] * (R[3] * R[7] - R[4] * R[6]);
  if (det < 0) return Corrupt(at + "rotation matrix is a reflection (determinant < 0)");
  return Status::Ok();
}

}  // namespace

Status ReadCameras(const BoxHeader& box, const uint8_t* payload, uint32_t expected_count,
                   std::vector<Camera>* cameras) {
  if (box.version != 0) {
    return Unsupported(BoxContext(box) + "version " + std::to_string(box.version));
  }
  ByteReader r(payload, box.payload_bytes());
  const uint32_t count = r.U16();
  if (count != expected_count) {
    return Corrupt(BoxContext(box) + std::to_string(count) + " cameras, the header declares " +
                   std::to_string(expected_count));
  }
  // Each camera takes at least 2 + 8 + 21 * 8 bytes: check before allocating.
  if (uint64_t{count} * 178 > r.remaining()) {
    return Corrupt(BoxContext(box) + "too short for " + std::to_string(count) + " cameras");
  }
  cameras->assign(count, Camera());
  for (uint32_t i = 0; i < count; ++i) {
    Camera& c = (*cameras)[i];
    c.name = r.Str();
    c.width = r.U32();
    c.height = r.U32();
    c.fx = r.F64();
    c.fy = r.F64();
    c.cx = r.F64();
    c.cy = r.F64();
    for (double& v : c.distortion) v = r.F64();
    for (double& v : c.rotation) v = r.F64();
    for (double& v : c.translation) v = r.F64();
    if (r.overrun()) break;
    FVV_RETURN_IF_ERROR(CheckCamera(c, i, box));
  }
  return CheckFullyRead(r, box);
}

}  // namespace fvv
