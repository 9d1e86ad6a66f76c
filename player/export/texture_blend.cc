#include "player/export/texture_blend.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <memory>
#include <utility>

#include "container/geometric_visibility.h"

namespace fvv {
namespace {

// A camera's view of the posed surface for streams without masks: its depth
// map at the size players use, pinhole (lens distortion only moves where
// things are, not what hides what).
struct CameraDepth {
  int width = 0, height = 0;
  double scale_x = 0, scale_y = 0;  // depth-map texels per image pixel
  double texel_angle = 0;
  std::vector<float> depth;

  // Camera-frame position of world point p.
  static glm::dvec3 ToCamera(const fvv_camera& c, const glm::vec3& p) {
    glm::dvec3 q;
    for (int r = 0; r < 3; ++r) {
      q[r] = c.rotation[3 * r] * p.x + c.rotation[3 * r + 1] * p.y + c.rotation[3 * r + 2] * p.z +
             c.translation[r];
    }
    return q;
  }
  // Depth-map pixel of camera-frame point q (z > 0).
  glm::dvec2 Pixel(const fvv_camera& c, const glm::dvec3& q) const {
    return {(c.fx * q.x / q.z + c.cx + 0.5) * scale_x - 0.5,
            (c.fy * q.y / q.z + c.cy + 0.5) * scale_y - 0.5};
  }

  CameraDepth(const fvv_camera& c, const fvv_model& model, const std::vector<glm::vec3>& posed) {
    namespace gv = geometric_visibility;
    gv::DepthMapSize(c.width, c.height, &width, &height);
    scale_x = double(width) / c.width;
    scale_y = double(height) / c.height;
    texel_angle = 1.0 / std::min(c.fx * scale_x, c.fy * scale_y);
    std::vector<double> px(posed.size() * 2, 0.0);
    std::vector<float> inv_z(posed.size(), 0.0f);
    for (size_t v = 0; v < posed.size(); ++v) {
      const glm::dvec3 q = ToCamera(c, posed[v]);
      if (!(q.z > 1e-6)) continue;
      const glm::dvec2 p = Pixel(c, q);
      px[2 * v] = p.x;
      px[2 * v + 1] = p.y;
      inv_z[v] = float(1 / q.z);
    }
    depth = RasterizeDepth(model.triangles, model.triangle_count, px.data(), inv_z.data(), width,
                           height);
  }

  // Whether the camera sees point p, facing it by `facing`.
  bool Sees(const fvv_camera& c, const glm::vec3& p, double facing) const {
    const glm::dvec3 q = ToCamera(c, p);
    if (!(q.z > 1e-6)) return false;
    const glm::dvec2 at = Pixel(c, q);
    const long x = std::lround(at.x), y = std::lround(at.y);
    if (x < 0 || y < 0 || x >= width || y >= height) return false;
    return q.z <= depth[size_t(y) * width + x] +
                      geometric_visibility::DepthAllowance(q.z, facing, texel_angle);
  }
};

float Cross2(const glm::vec2& a, const glm::vec2& b) { return a.x * b.y - a.y * b.x; }

// Bilinear sample of an RGB float image at texel coordinates (x, y).
glm::vec3 Sample(const std::vector<float>& rgb, int w, int h, float x, float y) {
  x = std::clamp(x - 0.5f, 0.0f, float(w - 1));
  y = std::clamp(y - 0.5f, 0.0f, float(h - 1));
  const int x0 = int(x), y0 = int(y);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const float fx = x - x0, fy = y - y0;
  const auto at = [&](int xx, int yy) {
    const float* p = &rgb[(size_t(yy) * w + xx) * 3];
    return glm::vec3(p[0], p[1], p[2]);
  };
  return glm::mix(glm::mix(at(x0, y0), at(x1, y0), fx), glm::mix(at(x0, y1), at(x1, y1), fx), fy);
}

}  // namespace

TextureBlend::TextureBlend(const fvv_model& model, uint32_t width, uint32_t height,
                           std::vector<fvv_camera> cameras)
    : model_(model), width_(width), height_(height), cameras_(std::move(cameras)) {
  for (const fvv_camera& c : cameras_) centres_.emplace_back(c.centre[0], c.centre[1], c.centre[2]);
  const size_t texels = size_t(width) * height;
  std::vector<int32_t> owner(texels, -1);
  std::vector<glm::vec3> bary(texels);
  for (uint32_t t = 0; t < model.triangle_count; ++t) {
    glm::vec2 p[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = model.triangles[3 * t + k];
      p[k] = {model.uvs[2 * v] * float(width), model.uvs[2 * v + 1] * float(height)};
    }
    const float twice = Cross2(p[1] - p[0], p[2] - p[0]);
    if (!(std::abs(twice) > 1e-12f)) continue;
    const int x0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
    const int x1 = std::min(int(width) - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
    const int y0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
    const int y1 = std::min(int(height) - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const glm::vec2 q(x + 0.5f, y + 0.5f);
        glm::vec3 w;
        for (int k = 0; k < 3; ++k) {
          w[k] = Cross2(p[(k + 2) % 3] - p[(k + 1) % 3], q - p[(k + 1) % 3]) / twice;
        }
        if (w.x < 0 || w.y < 0 || w.z < 0) continue;
        const size_t i = size_t(y) * width + x;
        owner[i] = int32_t(t);
        bary[i] = w;
      }
    }
  }
  for (size_t i = 0; i < texels; ++i) {
    if (owner[i] < 0) continue;
    texel_.push_back(uint32_t(i));
    triangle_.push_back(uint32_t(owner[i]));
    bary_.push_back(bary[i]);
  }
  sum_.assign(texels * 3, 0.0f);
  weight_.assign(texels, 0.0f);
}

void TextureBlend::Add(const fvv_frame& frame) {
  // The posed surface: vertices skinned with the frame's matrices.
  const uint32_t n = model_.vertex_count;
  std::vector<glm::vec3> position(n), normal(n);
  for (uint32_t v = 0; v < n; ++v) {
    glm::mat4 m(0.0f);
    for (int k = 0; k < 4; ++k) {
      const float w = model_.weights[4 * v + k];
      if (w == 0) continue;
      m += w * glm::make_mat4(frame.bone_skin + 16 * size_t(model_.joints[4 * v + k]));
    }
    position[v] = glm::vec3(m * glm::vec4(glm::make_vec3(model_.positions + 3 * size_t(v)), 1));
    normal[v] = glm::mat3(m) * glm::make_vec3(model_.normals + 3 * size_t(v));
  }
  std::vector<std::unique_ptr<CameraDepth>> depth(frame.camera_count);
  for (uint32_t c = 0; c < frame.camera_count && c < cameras_.size(); ++c) {
    if (frame.views[c].pixels && !frame.views[c].mask) {
      depth[c] = std::make_unique<CameraDepth>(cameras_[c], model_, position);
    }
  }
  for (size_t e = 0; e < texel_.size(); ++e) {
    const uint32_t* tri = model_.triangles + 3 * size_t(triangle_[e]);
    const glm::vec3& b = bary_[e];
    const glm::vec3 p = b.x * position[tri[0]] + b.y * position[tri[1]] + b.z * position[tri[2]];
    const glm::vec3 nn =
        glm::normalize(b.x * normal[tri[0]] + b.y * normal[tri[1]] + b.z * normal[tri[2]]);
    const size_t i = texel_[e];
    for (uint32_t c = 0; c < frame.camera_count && c < centres_.size(); ++c) {
      const fvv_view& view = frame.views[c];
      if (!view.pixels || (view.mask && !view.mask[i])) continue;
      const float cosine = glm::dot(nn, glm::normalize(centres_[c] - p));
      if (!(cosine > geometric_visibility::kMinFacing)) continue;
      if (depth[c] && !depth[c]->Sees(cameras_[c], p, cosine)) continue;
      const float w = cosine * cosine;
      for (int k = 0; k < 3; ++k) sum_[3 * i + k] += w * view.pixels[3 * i + k];
      weight_[i] += w;
    }
  }
}

std::vector<uint8_t> TextureBlend::Finish(uint32_t size) const {
  const int w = int(width_), h = int(height_);
  const size_t texels = size_t(w) * h;
  std::vector<float> rgb(texels * 3, 0.0f);
  std::vector<uint8_t> known(texels, 0);
  for (size_t i = 0; i < texels; ++i) {
    if (weight_[i] <= 0) continue;
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = sum_[3 * i + k] / weight_[i];
    known[i] = 1;
  }
  // Unseen texels: rings grown from the known ones, each texel the mean of its
  // known 8-neighbours, until none is left.
  std::vector<size_t> frontier;
  for (size_t i = 0; i < texels; ++i) {
    if (!known[i]) frontier.push_back(i);
  }
  while (!frontier.empty()) {
    std::vector<std::pair<size_t, glm::vec3>> filled;
    std::vector<size_t> left;
    for (size_t i : frontier) {
      const int x = int(i % w), y = int(i / w);
      glm::vec3 s(0.0f);
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const size_t j = size_t(yy) * w + xx;
          if (!known[j]) continue;
          s += glm::vec3(rgb[3 * j], rgb[3 * j + 1], rgb[3 * j + 2]);
          ++count;
        }
      }
      if (count) {
        filled.emplace_back(i, s / float(count));
      } else {
        left.push_back(i);
      }
    }
    if (filled.empty()) break;  // nothing was seen at all: stays black
    for (const auto& [i, c] : filled) {
      for (int k = 0; k < 3; ++k) rgb[3 * i + k] = c[k];
      known[i] = 1;
    }
    frontier = std::move(left);
  }
  const int out_w = size ? int(size) : w, out_h = size ? int(size) : h;
  std::vector<uint8_t> out(size_t(out_w) * out_h * 3);
  // Downscaling averages the texels each output texel covers; upscaling is bilinear.
  const float sx = float(w) / out_w, sy = float(h) / out_h;
  const int taps_x = std::max(1, int(std::ceil(sx))), taps_y = std::max(1, int(std::ceil(sy)));
  for (int y = 0; y < out_h; ++y) {
    for (int x = 0; x < out_w; ++x) {
      glm::vec3 c(0.0f);
      for (int ty = 0; ty < taps_y; ++ty) {
        for (int tx = 0; tx < taps_x; ++tx) {
          c += Sample(rgb, w, h, (x + (tx + 0.5f) / taps_x) * sx, (y + (ty + 0.5f) / taps_y) * sy);
        }
      }
      c /= float(taps_x * taps_y);
      for (int k = 0; k < 3; ++k) {
        out[(size_t(y) * out_w + x) * 3 + k] = uint8_t(std::clamp(std::lround(c[k]), 0L, 255L));
      }
    }
  }
  return out;
}

}  // namespace fvv
