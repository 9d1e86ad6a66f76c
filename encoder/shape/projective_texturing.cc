#include "encoder/shape/projective_texturing.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "encoder/body/kinematics.h"
#include "encoder/capture/calibration.h"
#include "encoder/shape/depth_map.h"

namespace fvv {

std::vector<std::vector<uint8_t>> VertexVisibility(
    const std::vector<std::array<uint32_t, 3>>& triangles,
    const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Vector3f>& normals,
    const std::vector<Camera>& cameras, const ProjectiveOptions& o, const ParallelRunner& runner) {
  std::vector<std::vector<uint8_t>> visible(cameras.size());
  runner(uint32_t(cameras.size()), [&](uint32_t c) {
    const Camera& camera = cameras[c];
    std::vector<uint8_t>& vis = visible[c];
    const Eigen::Vector3f centre = CameraCentre(camera).cast<float>();
    vis.assign(positions.size(), 0);
    for (size_t v = 0; v < positions.size(); ++v) {
      const Eigen::Vector3f view = centre - positions[v];
      vis[v] = normals[v].dot(view) > o.min_facing * view.norm();
    }
    // The camera and four copies moved by shift_m along its own x and y axes
    // (moving the centre by R^T d moves the translation by -d).
    const double s = o.shift_m;
    const double shifts[5][2] = {{0, 0}, {s, 0}, {-s, 0}, {0, s}, {0, -s}};
    const double pixel_angle = 1.0 / std::max(camera.fx, camera.fy);
    for (int k = 0; k < (s > 0 ? 5 : 1); ++k) {
      Camera moved = camera;
      moved.translation[0] -= shifts[k][0];
      moved.translation[1] -= shifts[k][1];
      const DepthMap depth = RenderDepthMap(triangles, positions, moved);
      const Eigen::Vector3f moved_centre = CameraCentre(moved).cast<float>();
      for (size_t v = 0; v < positions.size(); ++v) {
        if (!vis[v]) continue;
        Eigen::Vector2d pixel;
        double z = 0;
        if (!ProjectPoint(moved, positions[v].cast<double>(), &pixel, &z) ||
            !(pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() < camera.width - 0.5 &&
              pixel.y() < camera.height - 0.5)) {
          vis[v] = 0;
          continue;
        }
        // A vertex's depth and the depth map's at the nearest pixel centre
        // differ by up to half a pixel's footprint times the surface slope.
        const Eigen::Vector3f view = (moved_centre - positions[v]).normalized();
        const double facing = std::max(1e-3, double(normals[v].dot(view)));
        const double slope = std::sqrt(std::max(0.0, 1.0 - facing * facing)) / facing;
        vis[v] = z <= depth.At(pixel) + o.depth_tolerance + 0.75 * z * pixel_angle * slope;
      }
    }
  });
  return visible;
}

std::vector<float> BlendWeights(const std::vector<Eigen::Vector3f>& positions,
                                const std::vector<Eigen::Vector3f>& normals,
                                const std::vector<Camera>& cameras,
                                const std::vector<std::vector<uint8_t>>& visibility,
                                double dominance) {
  const size_t n = positions.size(), m = cameras.size();
  std::vector<float> weights(n * m, 0.0f);
  std::vector<Eigen::Vector3f> centres;
  for (const Camera& c : cameras) centres.push_back(CameraCentre(c).cast<float>());
  // Angles below this count as this: 1/theta stays finite and a camera
  // looking straight at the surface does not swamp one a degree further off.
  constexpr double kMinAngle = 0.05;
  std::vector<double> inverse(m);
  for (size_t v = 0; v < n; ++v) {
    double best_inverse = 0, best_facing = -2;
    size_t fallback = 0;
    for (size_t c = 0; c < m; ++c) {
      const Eigen::Vector3f to_camera = (centres[c] - positions[v]).normalized();
      const double facing = std::clamp(double(normals[v].dot(to_camera)), -1.0, 1.0);
      if (facing > best_facing) best_facing = facing, fallback = c;
      inverse[c] = visibility[c][v] ? 1.0 / std::max(kMinAngle, std::acos(facing)) : 0.0;
      best_inverse = std::max(best_inverse, inverse[c]);
    }
    double sum = 0;
    for (size_t c = 0; c < m; ++c) {
      if (inverse[c] > 0) sum += std::pow(1.0 + best_inverse - inverse[c], -dominance);
    }
    for (size_t c = 0; c < m; ++c) {
      if (inverse[c] > 0) {
        weights[c * n + v] = float(std::pow(1.0 + best_inverse - inverse[c], -dominance) / sum);
      }
    }
    if (m > 0) weights[fallback * n + v] += kFallbackWeight;
  }
  return weights;
}

Image ExpandSilhouette(const Image& rgb, const Image& silhouette, int pixels) {
  Image out;
  out.width = rgb.width;
  out.height = rgb.height;
  out.channels = 4;
  const int w = int(rgb.width), h = int(rgb.height);
  const size_t count = size_t(w) * h;
  out.pixels.assign(count * 4, 0);
  std::vector<uint8_t> filled(count, 1);
  if (!silhouette.pixels.empty()) {
    for (size_t i = 0; i < count; ++i) filled[i] = silhouette.pixels[i] != 0;
  }
  for (size_t i = 0; i < count; ++i) {
    if (!filled[i]) continue;
    for (int k = 0; k < 3; ++k) out.pixels[i * 4 + k] = rgb.pixels[i * 3 + k];
    out.pixels[i * 4 + 3] = 255;
  }
  // Ring by ring, each pixel next to filled ones takes their mean: the rings
  // within `pixels` as the actor, the rest with kFarFillAlpha. The next ring is
  // the unfilled neighbours of this one, so the whole image costs one pass.
  auto neighbours = [w, h](size_t i, auto&& visit) {
    const int x = int(i % size_t(w)), y = int(i / size_t(w));
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if ((dx || dy) && xx >= 0 && yy >= 0 && xx < w && yy < h) visit(size_t(yy) * w + xx);
      }
    }
  };
  std::vector<uint8_t> queued(count, 0);
  std::vector<size_t> ring, next;
  for (size_t i = 0; i < count; ++i) {
    if (filled[i]) continue;
    bool edge = false;
    neighbours(i, [&](size_t j) { edge = edge || filled[j]; });
    if (edge) ring.push_back(i), queued[i] = 1;
  }
  std::vector<std::array<uint8_t, 3>> colours;
  for (int step = 0; !ring.empty(); ++step) {
    colours.resize(ring.size());
    for (size_t r = 0; r < ring.size(); ++r) {
      int sum[3] = {0, 0, 0}, n = 0;
      neighbours(ring[r], [&](size_t j) {
        if (!filled[j]) return;
        for (int k = 0; k < 3; ++k) sum[k] += out.pixels[j * 4 + k];
        ++n;
      });
      for (int k = 0; k < 3; ++k) colours[r][k] = uint8_t((sum[k] + n / 2) / n);
    }
    // Written after the sweep: a pixel of this ring does not feed its neighbours.
    const uint8_t alpha = step < pixels ? 255 : kFarFillAlpha;
    next.clear();
    for (size_t r = 0; r < ring.size(); ++r) {
      const size_t i = ring[r];
      filled[i] = 1;
      for (int k = 0; k < 3; ++k) out.pixels[i * 4 + k] = colours[r][k];
      out.pixels[i * 4 + 3] = alpha;
    }
    for (size_t i : ring) {
      neighbours(i, [&](size_t j) {
        if (!filled[j] && !queued[j]) next.push_back(j), queued[j] = 1;
      });
    }
    ring.swap(next);
  }
  return out;
}

StatusOr<ProjectiveFrame> MakeProjectiveFrameForMesh(
    const std::vector<std::array<uint32_t, 3>>& triangles,
    const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Vector3f>& normals,
    const std::vector<Camera>& cameras, const std::vector<Image>& images,
    const std::vector<Image>& silhouettes, const ProjectiveOptions& o,
    const ParallelRunner& runner) {
  if (images.size() != cameras.size() ||
      (!silhouettes.empty() && silhouettes.size() != cameras.size())) {
    return InvalidArgument("projective texturing: one image (and silhouette) per camera");
  }
  for (size_t c = 0; c < cameras.size(); ++c) {
    const Camera& cam = cameras[c];
    if (images[c].width != cam.width || images[c].height != cam.height || images[c].channels != 3) {
      return InvalidArgument("projective texturing: camera " + cam.name + "'s image is not " +
                             std::to_string(cam.width) + "x" + std::to_string(cam.height) + " RGB");
    }
    if (!silhouettes.empty() &&
        (silhouettes[c].width != cam.width || silhouettes[c].height != cam.height ||
         silhouettes[c].channels != 1)) {
      return InvalidArgument("projective texturing: camera " + cam.name +
                             "'s silhouette is not a grey image of its size");
    }
  }
  if (normals.size() != positions.size()) {
    return InvalidArgument("projective texturing: one normal per vertex");
  }
  for (const auto& t : triangles) {
    for (uint32_t i : t) {
      if (i >= positions.size()) return InvalidArgument("projective texturing: a bad triangle");
    }
  }
  ProjectiveFrame frame;
  frame.positions.reserve(positions.size() * 3);
  for (const auto& p : positions) {
    frame.positions.insert(frame.positions.end(), {p.x(), p.y(), p.z()});
  }
  frame.visibility = VertexVisibility(triangles, positions, normals, cameras, o, runner);
  frame.weights = BlendWeights(positions, normals, cameras, frame.visibility, o.dominance);
  frame.images.resize(cameras.size());
  runner(uint32_t(cameras.size()), [&](uint32_t c) {
    frame.images[c] =
        ExpandSilhouette(images[c], silhouettes.empty() ? Image() : silhouettes[c], o.expand_px);
  });
  return frame;
}

StatusOr<ProjectiveFrame> MakeProjectiveFrame(
    const BodyModel& model, const std::vector<double>& dofs, const std::vector<Camera>& cameras,
    const std::vector<Image>& images, const std::vector<Image>& silhouettes,
    const ProjectiveOptions& o, const ParallelRunner& runner) {
  if (dofs.size() != model.skeleton.Dofs().size()) {
    return InvalidArgument("projective texturing: " + std::to_string(dofs.size()) +
                           " pose values for a skeleton of " +
                           std::to_string(model.skeleton.Dofs().size()) + " DOFs");
  }
  std::vector<Eigen::Vector3f> normals;
  const std::vector<Eigen::Vector3f> posed =
      SkinPositions(model.mesh, SkinningMatrices(model.skeleton, dofs), &normals);
  for (auto& n : normals) n.normalize();
  StatusOr<ProjectiveFrame> frame = MakeProjectiveFrameForMesh(
      model.mesh.triangles, posed, normals, cameras, images, silhouettes, o, runner);
  if (frame.ok()) frame->root = JointPositions(model.skeleton, dofs)[0];
  return frame;
}

}  // namespace fvv
