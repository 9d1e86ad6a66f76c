#include "tools/synth/body_texture.h"

#include <algorithm>
#include <cmath>

#include "encoder/body/generic_body.h"
#include "encoder/body/kinematics.h"

namespace fvv {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

uint32_t Hash(int32_t x, int32_t y, int32_t z, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B1u ^ uint32_t(x) * 0x85EBCA77u ^ uint32_t(y) * 0xC2B2AE3Du ^
               uint32_t(z) * 0x27D4EB2Fu;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return h;
}

// Trilinear value noise in [0, 1] at `p` / `scale`.
double Noise(const Vector3d& p, double scale, uint32_t seed) {
  const Vector3d q = p / scale;
  const Eigen::Vector3i i(int(std::floor(q.x())), int(std::floor(q.y())), int(std::floor(q.z())));
  const Vector3d f = q - i.cast<double>();
  const Vector3d s = f.array() * f.array() * (3 - 2 * f.array());
  double v = 0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
    const double w = (dx ? s.x() : 1 - s.x()) * (dy ? s.y() : 1 - s.y()) * (dz ? s.z() : 1 - s.z());
    v += w * (Hash(i.x() + dx, i.y() + dy, i.z() + dz, seed) & 0xFFFF) / 65535.0;
  }
  return v;
}

Vector3f Rgb(int r, int g, int b) { return Vector3f(r, g, b) / 255.0f; }

}  // namespace

Vector3f ClothingColour(const std::vector<Vector3d>& joints, int segment, const Vector3d& p,
                        const Vector3d& n, uint32_t seed) {
  const double fine = Noise(p, 0.004, seed), coarse = Noise(p, 0.03, seed + 1);
  const Vector3f skin = Rgb(226, 174, 142) * float(0.92 + 0.1 * coarse + 0.04 * fine);
  switch (segment) {
    case kSegHead: {
      const Vector3d h = p - joints[kHead];  // head joint: the top of the neck
      const double hair_line = 0.125 - 0.05 * std::max(0.0, -h.z() / 0.09);
      if (h.y() > hair_line || (h.z() < -0.035 && h.y() > 0.03)) {
        return Rgb(62, 40, 26) * float(0.75 + 0.5 * Noise(p, 0.003, seed + 2));  // hair
      }
      if (h.z() > 0.05 && h.y() > 0.02) {  // face
        for (int side : {-1, 1}) {
          const double ex = h.x() - side * 0.034, ey = h.y() - 0.088;
          if (ex * ex / 0.00018 + ey * ey / 0.00004 < 1) return Rgb(250, 250, 245);  // eye
          if (ex * ex + ey * ey < 0.00004) return Rgb(60, 90, 140);
          const double by = h.y() - 0.107;
          if (std::abs(ex) < 0.02 && std::abs(by + 0.002 * ex * ex * 2000) < 0.004) {
            return Rgb(70, 45, 30);  // eyebrow
          }
        }
        const double my = h.y() - 0.045;
        if (std::abs(h.x()) < 0.025 &&
            std::abs(my - 0.01 * (h.x() / 0.025) * (h.x() / 0.025)) < 0.005) {
          return Rgb(170, 80, 80);  // mouth
        }
      }
      return skin;
    }
    case kSegLeftForearm:
    case kSegRightForearm:
    case kSegLeftHand:
    case kSegRightHand:
      return skin;
    case kSegChest:
    case kSegAbdomen:
    case kSegLeftUpperArm:
    case kSegRightUpperArm: {
      Vector3f shirt = Rgb(178, 34, 52);
      const bool sleeve = segment == kSegLeftUpperArm || segment == kSegRightUpperArm;
      if (sleeve) {
        const double along = std::abs(p.x()) - std::abs(joints[kLeftShoulder].x());
        if (along > 0.2) return skin;                  // short sleeves
        if (along > 0.17) shirt = Rgb(240, 240, 235);  // sleeve hem
      } else {
        const double y = p.y() - joints[kLumbar].y();
        if (std::fmod(y + 10, 0.09) < 0.025) shirt = Rgb(238, 236, 228);  // stripes
        const Vector3d logo = p - (joints[kThoracic] + Vector3d(0.06, 0.1, 0.1));
        if (n.z() > 0.4 && logo.x() * logo.x() + logo.y() * logo.y() < 0.0012) {
          shirt = (logo.x() * logo.x() + logo.y() * logo.y() < 0.0005) ? Rgb(250, 200, 40)
                                                                       : Rgb(30, 40, 90);
        }
        if (p.y() > joints[kNeck].y() - 0.015) shirt = Rgb(120, 20, 35);  // collar
      }
      // Knit: a fine diagonal weave plus soft folds.
      const double weave = 0.5 + 0.5 * std::sin((p.x() + p.y() + p.z()) * 900.0);
      return shirt * float(0.82 + 0.1 * weave + 0.12 * coarse + 0.05 * fine);
    }
    case kSegPelvis:
    case kSegLeftThigh:
    case kSegRightThigh:
    case kSegLeftShank:
    case kSegRightShank: {
      if (segment == kSegPelvis && p.y() > joints[kRoot].y() + 0.05) {
        const bool buckle = n.z() > 0.9 && std::abs(p.x()) < 0.025;
        return buckle ? Rgb(200, 180, 90) : Rgb(70, 45, 30) * float(0.9 + 0.2 * fine);  // belt
      }
      // Denim: diagonal twill, seams on the outer legs.
      const double twill = 0.5 + 0.5 * std::sin((p.y() * 1.0 + p.x() + p.z()) * 1400.0);
      Vector3f jeans = Rgb(48, 72, 122) * float(0.8 + 0.12 * twill + 0.2 * coarse);
      if (segment != kSegPelvis && std::abs(n.x()) > 0.97) jeans = Rgb(190, 150, 70);  // seam
      return jeans;
    }
    case kSegLeftFoot:
    case kSegRightFoot: {
      if (p.y() < 0.015) return Rgb(235, 235, 230);  // sole
      return Rgb(38, 38, 42) * float(0.85 + 0.3 * fine);
    }
    default:
      return Rgb(128, 128, 128);
  }
}

Image BakeBodyTexture(const BodyModel& model, int size, uint32_t seed) {
  Image img;
  img.width = img.height = static_cast<uint32_t>(size);
  img.channels = 3;
  img.pixels.assign(size_t(size) * size * 3, 0);
  std::vector<uint8_t> set(size_t(size) * size, 0);
  const Mesh& m = model.mesh;
  const std::vector<Vector3d> joints = JointPositions(model.skeleton, {});
  for (const auto& t : m.triangles) {
    Eigen::Vector2d uv[3];
    Vector3d pos[3], nor[3];
    for (int k = 0; k < 3; ++k) {
      uv[k] = Eigen::Vector2d(m.uvs[t[k]][0] * size, m.uvs[t[k]][1] * size);
      pos[k] = Vector3d(m.positions[t[k]][0], m.positions[t[k]][1], m.positions[t[k]][2]);
      nor[k] = Vector3d(m.normals[t[k]][0], m.normals[t[k]][1], m.normals[t[k]][2]);
    }
    const double area =
        (uv[1] - uv[0]).x() * (uv[2] - uv[0]).y() - (uv[1] - uv[0]).y() * (uv[2] - uv[0]).x();
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, int(std::floor(std::min({uv[0].x(), uv[1].x(), uv[2].x()}))));
    const int x1 = std::min(size - 1, int(std::ceil(std::max({uv[0].x(), uv[1].x(), uv[2].x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({uv[0].y(), uv[1].y(), uv[2].y()}))));
    const int y1 = std::min(size - 1, int(std::ceil(std::max({uv[0].y(), uv[1].y(), uv[2].y()}))));
    const int segment = m.segments[t[0]];
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d q(x + 0.5, y + 0.5);
        double b[3];
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& a = uv[(k + 1) % 3];
          const Eigen::Vector2d& c = uv[(k + 2) % 3];
          b[k] = ((c - a).x() * (q - a).y() - (c - a).y() * (q - a).x()) / area;
        }
        if (b[0] < -1e-9 || b[1] < -1e-9 || b[2] < -1e-9) continue;
        const Vector3d p = b[0] * pos[0] + b[1] * pos[1] + b[2] * pos[2];
        const Vector3d n = (b[0] * nor[0] + b[1] * nor[1] + b[2] * nor[2]).normalized();
        const Vector3f c = ClothingColour(joints, segment, p, n, seed);
        const size_t i = size_t(y) * size + x;
        for (int k = 0; k < 3; ++k) {
          img.pixels[3 * i + k] = uint8_t(std::clamp(c[k] * 255.0f + 0.5f, 0.0f, 255.0f));
        }
        set[i] = 1;
      }
    }
  }
  // Gutter fill: a few passes of copying set neighbours into unset texels.
  for (int pass = 0; pass < 8; ++pass) {
    std::vector<uint8_t> next = set;
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) {
        const size_t i = size_t(y) * size + x;
        if (set[i]) continue;
        for (const auto& d : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int nx = x + d.first, ny = y + d.second;
          if (nx < 0 || ny < 0 || nx >= size || ny >= size) continue;
          const size_t j = size_t(ny) * size + nx;
          if (!set[j]) continue;
          std::copy_n(&img.pixels[3 * j], 3, &img.pixels[3 * i]);
          next[i] = 1;
          break;
        }
      }
    }
    set.swap(next);
  }
  return img;
}

}  // namespace fvv
