#include "encoder/encode/seamless_texture.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "codec/fill.h"
#include "encoder/capture/calibration.h"

namespace fvv {
namespace {

// A float image of `channels` interleaved channels.
struct Layer {
  int width = 0, height = 0, channels = 1;
  std::vector<float> px;
  Layer() = default;
  Layer(int w, int h, int c) : width(w), height(h), channels(c), px(size_t(w) * h * c, 0.0f) {}
  float& at(int x, int y, int k) { return px[(size_t(y) * width + x) * channels + k]; }
  float at(int x, int y, int k) const { return px[(size_t(y) * width + x) * channels + k]; }
};

constexpr float kBinomial[5] = {1 / 16.f, 4 / 16.f, 6 / 16.f, 4 / 16.f, 1 / 16.f};

// Blur with the 5-tap binomial and keep every other sample (edges clamped).
Layer Reduce(const Layer& in) {
  const int w = (in.width + 1) / 2, h = (in.height + 1) / 2, ch = in.channels;
  Layer rows(w, in.height, ch), out(w, h, ch);
  for (int y = 0; y < in.height; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int k = 0; k < ch; ++k) {
        float s = 0;
        for (int t = -2; t <= 2; ++t) {
          s += kBinomial[t + 2] * in.at(std::clamp(2 * x + t, 0, in.width - 1), y, k);
        }
        rows.at(x, y, k) = s;
      }
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int k = 0; k < ch; ++k) {
        float s = 0;
        for (int t = -2; t <= 2; ++t) {
          s += kBinomial[t + 2] * rows.at(x, std::clamp(2 * y + t, 0, in.height - 1), k);
        }
        out.at(x, y, k) = s;
      }
    }
  }
  return out;
}

// The inverse step: `in` interpolated up to width x height (zeros inserted
// between samples, the binomial filter with twice its gain per axis).
Layer Expand(const Layer& in, int width, int height) {
  const int ch = in.channels;
  Layer rows(width, in.height, ch), out(width, height, ch);
  const auto expand_1d = [](int j, int m, const auto& get) {
    float s = 0;
    for (int i = (j - 1) / 2 - 1; i <= (j + 2) / 2; ++i) {
      const int d = j - 2 * i;
      if (d < -2 || d > 2) continue;
      s += 2 * kBinomial[d + 2] * get(std::clamp(i, 0, m - 1));
    }
    return s;
  };
  for (int y = 0; y < in.height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int k = 0; k < ch; ++k) {
        rows.at(x, y, k) = expand_1d(x, in.width, [&](int i) { return in.at(i, y, k); });
      }
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int k = 0; k < ch; ++k) {
        out.at(x, y, k) = expand_1d(y, in.height, [&](int i) { return rows.at(x, i, k); });
      }
    }
  }
  return out;
}

std::vector<Layer> GaussianPyramid(Layer base, int levels) {
  std::vector<Layer> p;
  p.push_back(std::move(base));
  for (int l = 1; l < levels; ++l) p.push_back(Reduce(p.back()));
  return p;
}

// Laplacian levels: each Gaussian level less its coarser level expanded; the
// coarsest level as it is.
std::vector<Layer> LaplacianPyramid(Layer base, int levels) {
  std::vector<Layer> g = GaussianPyramid(std::move(base), levels);
  for (int l = 0; l + 1 < levels; ++l) {
    const Layer up = Expand(g[l + 1], g[l].width, g[l].height);
    for (size_t i = 0; i < g[l].px.size(); ++i) g[l].px[i] -= up.px[i];
  }
  return g;
}

}  // namespace

std::vector<int16_t> BestCameraLabels(const TexelMap& map, const Mesh& mesh,
                                      const std::vector<Eigen::Vector3f>& positions,
                                      const std::vector<Camera>& cameras,
                                      const CameraTextures& textures) {
  const size_t texels = size_t(textures.size) * textures.size;
  std::vector<int16_t> labels(texels, -1);
  std::vector<Eigen::Vector3d> centres;
  for (const Camera& c : cameras) centres.push_back(CameraCentre(c));
  // Per triangle, the cameras facing it, best first (computed on first use).
  std::vector<std::vector<int16_t>> ranked(mesh.triangles.size());
  std::vector<uint8_t> done(mesh.triangles.size(), 0);
  for (size_t e = 0; e < map.texel.size(); ++e) {
    const uint32_t t = map.triangle[e];
    if (!done[t]) {
      done[t] = 1;
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector3d a = positions[tri[0]].cast<double>(),
                            b = positions[tri[1]].cast<double>(),
                            c = positions[tri[2]].cast<double>();
      const Eigen::Vector3d n = (b - a).cross(c - a).normalized(), centroid = (a + b + c) / 3;
      std::vector<std::pair<double, int16_t>> facing;
      for (size_t k = 0; k < cameras.size(); ++k) {
        const double f = n.dot((centres[k] - centroid).normalized());
        if (f > 0) facing.emplace_back(-f, int16_t(k));
      }
      std::sort(facing.begin(), facing.end());
      for (const auto& f : facing) ranked[t].push_back(f.second);
    }
    const uint32_t texel = map.texel[e];
    for (int16_t k : ranked[t]) {
      if (textures.masks[k][texel]) {
        labels[texel] = k;
        break;
      }
    }
  }
  return labels;
}

std::vector<uint8_t> CompositeLabels(const CameraTextures& textures,
                                     const std::vector<int16_t>& labels) {
  std::vector<uint8_t> out(labels.size() * 3, 0);
  for (size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 0) continue;
    std::copy_n(textures.rgb[labels[i]] + i * 3, 3, &out[i * 3]);
  }
  return out;
}

std::vector<uint8_t> BlendSeamless(const CameraTextures& textures,
                                   const std::vector<int16_t>& labels, int levels) {
  const int size = int(textures.size);
  const size_t texels = size_t(size) * size;
  if (levels <= 0) {
    levels = 1;
    for (int s = size; s > 4; s = (s + 1) / 2) ++levels;
  }
  // Accumulated over the cameras: sum of region weight x Laplacian, and of
  // region weight, per level.
  std::vector<Layer> numerator, denominator;
  for (size_t c = 0; c < textures.rgb.size(); ++c) {
    bool used = false;
    for (int16_t l : labels) used = used || l == int16_t(c);
    if (!used) continue;
    // The camera's texture with the texels it did not see filled smoothly
    // (the codec's pyramid fill), so its pyramid does not pull in zeros.
    Shape4D shape;
    shape.n = {1, 1, uint32_t(size), uint32_t(size)};
    UsedMask seen(textures.masks[c], textures.masks[c] + texels);
    Layer image(size, size, 3);
    for (int k = 0; k < 3; ++k) {
      Plane4D plane(shape);
      for (size_t i = 0; i < texels; ++i) plane.samples[i] = textures.rgb[c][i * 3 + k];
      FillUnused(seen, 128, &plane);
      for (size_t i = 0; i < texels; ++i) image.px[i * 3 + k] = float(plane.samples[i]);
    }
    Layer region(size, size, 1);
    for (size_t i = 0; i < texels; ++i) region.px[i] = labels[i] == int16_t(c) ? 1.0f : 0.0f;
    const std::vector<Layer> lap = LaplacianPyramid(std::move(image), levels);
    const std::vector<Layer> weight = GaussianPyramid(std::move(region), levels);
    if (numerator.empty()) {
      for (int l = 0; l < levels; ++l) {
        numerator.emplace_back(lap[l].width, lap[l].height, 3);
        denominator.emplace_back(lap[l].width, lap[l].height, 1);
      }
    }
    for (int l = 0; l < levels; ++l) {
      for (size_t i = 0; i < weight[l].px.size(); ++i) {
        const float w = weight[l].px[i];
        denominator[l].px[i] += w;
        for (int k = 0; k < 3; ++k) numerator[l].px[i * 3 + k] += w * lap[l].px[i * 3 + k];
      }
    }
  }
  std::vector<uint8_t> out(texels * 3, 0);
  if (numerator.empty()) return out;
  // Blend each level, then collapse from the coarsest.
  Layer image;
  for (int l = levels - 1; l >= 0; --l) {
    Layer blended(numerator[l].width, numerator[l].height, 3);
    for (size_t i = 0; i < denominator[l].px.size(); ++i) {
      const float w = denominator[l].px[i];
      if (w > 1e-6f) {
        for (int k = 0; k < 3; ++k) blended.px[i * 3 + k] = numerator[l].px[i * 3 + k] / w;
      }
    }
    if (l < levels - 1) {
      const Layer up = Expand(image, blended.width, blended.height);
      for (size_t i = 0; i < blended.px.size(); ++i) blended.px[i] += up.px[i];
    }
    image = std::move(blended);
  }
  for (size_t i = 0; i < texels; ++i) {
    if (labels[i] < 0) continue;
    for (int k = 0; k < 3; ++k) {
      out[i * 3 + k] = uint8_t(std::lround(std::clamp(image.px[i * 3 + k], 0.0f, 255.0f)));
    }
  }
  return out;
}

StaticTexture::StaticTexture(uint32_t size)
    : size_(size), sum_(size_t(size) * size * 3, 0.0f), count_(size_t(size) * size, 0) {}

void StaticTexture::Add(const std::vector<uint8_t>& rgb, const std::vector<int16_t>& labels) {
  for (size_t i = 0; i < count_.size() && i < labels.size(); ++i) {
    if (labels[i] < 0) continue;
    for (int k = 0; k < 3; ++k) sum_[i * 3 + k] += rgb[i * 3 + k];
    ++count_[i];
  }
}

void StaticTexture::Set(const std::vector<uint8_t>& rgb, const std::vector<uint8_t>& coverage) {
  for (size_t i = 0; i < count_.size(); ++i) {
    const bool seen = i < coverage.size() && coverage[i] && (i + 1) * 3 <= rgb.size();
    count_[i] = seen;
    for (int k = 0; k < 3; ++k) sum_[i * 3 + k] = seen ? rgb[i * 3 + k] : 0.0f;
  }
}

void StaticTexture::Get(size_t texel, uint8_t* rgb) const {
  for (int k = 0; k < 3; ++k) {
    rgb[k] = uint8_t(std::lround(sum_[texel * 3 + k] / float(std::max(1u, count_[texel]))));
  }
}

std::vector<uint8_t> StaticTexture::Rgb() const {
  std::vector<uint8_t> out(count_.size() * 3, 0);
  for (size_t i = 0; i < count_.size(); ++i) {
    if (count_[i]) Get(i, &out[i * 3]);
  }
  return out;
}

std::vector<uint8_t> StaticTexture::Coverage() const {
  std::vector<uint8_t> out(count_.size());
  for (size_t i = 0; i < count_.size(); ++i) out[i] = count_[i] > 0;
  return out;
}

}  // namespace fvv
