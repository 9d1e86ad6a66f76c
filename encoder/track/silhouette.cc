#include "encoder/track/silhouette.h"

#include <algorithm>
#include <cmath>

#include "encoder/io/mask_box.h"

namespace fvv {
namespace {

// One 3x3 pass: erosion (all neighbours set) or dilation (any set).
void Morph(std::vector<uint8_t>* m, int w, int h, bool erode) {
  std::vector<uint8_t> out(m->size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      bool all = true, any = false;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = std::clamp(x + dx, 0, w - 1), ny = std::clamp(y + dy, 0, h - 1);
          const bool v = (*m)[size_t(ny) * w + nx] != 0;
          all = all && v;
          any = any || v;
        }
      }
      out[size_t(y) * w + x] = (erode ? all : any) ? 1 : 0;
    }
  }
  m->swap(out);
}

// 4-connected components of pixels equal to `value`: labels (0 = other) and sizes.
int Label(const std::vector<uint8_t>& m, int w, int h, uint8_t value, std::vector<int>* labels,
          std::vector<size_t>* sizes, std::vector<char>* touches_border) {
  labels->assign(m.size(), 0);
  sizes->assign(1, 0);
  touches_border->assign(1, 0);
  std::vector<size_t> stack;
  int next = 0;
  for (size_t start = 0; start < m.size(); ++start) {
    if (m[start] != value || (*labels)[start]) continue;
    ++next;
    sizes->push_back(0);
    touches_border->push_back(0);
    stack.push_back(start);
    (*labels)[start] = next;
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      ++(*sizes)[next];
      const int x = int(i % w), y = int(i / w);
      if (x == 0 || y == 0 || x == w - 1 || y == h - 1) (*touches_border)[next] = 1;
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        const size_t j = size_t(ny[k]) * w + nx[k];
        if (m[j] == value && !(*labels)[j]) {
          (*labels)[j] = next;
          stack.push_back(j);
        }
      }
    }
  }
  return next;
}

}  // namespace

Image TemporalMedian(const std::vector<Image>& frames) {
  Image out;
  if (frames.empty()) return out;
  out.width = frames[0].width;
  out.height = frames[0].height;
  out.channels = 3;
  out.pixels.resize(frames[0].pixels.size());
  std::vector<uint8_t> values(frames.size());
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    for (size_t f = 0; f < frames.size(); ++f) values[f] = frames[f].pixels[i];
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    out.pixels[i] = values[values.size() / 2];
  }
  return out;
}

void CleanMask(Image* mask, const SilhouetteParams& p) {
  const int w = int(mask->width), h = int(mask->height);
  // The work is done in the box around the set pixels, grown by 4: the
  // morphology reaches 2 pixels out, and beyond the box everything is
  // background, as it is outside the image. A person mask is a small part
  // of a 1080x1920 frame.
  const MaskBox box = SetPixelBox(mask->pixels.data(), w, h);
  if (box.empty()) return;
  const int x0 = std::max(0, box.x0 - 4), y0 = std::max(0, box.y0 - 4);
  const int x1 = std::min(w - 1, box.x1 + 4), y1 = std::min(h - 1, box.y1 + 4);
  const int bw = x1 - x0 + 1, bh = y1 - y0 + 1;
  std::vector<uint8_t> m(size_t(bw) * bh);
  for (int y = 0; y < bh; ++y) {
    for (int x = 0; x < bw; ++x)
      m[size_t(y) * bw + x] = mask->pixels[size_t(y0 + y) * w + x0 + x] != 0;
  }
  Morph(&m, bw, bh, true);  // open: remove speckle
  Morph(&m, bw, bh, false);
  Morph(&m, bw, bh, false);  // close: bridge one-pixel cracks
  Morph(&m, bw, bh, true);
  std::vector<int> labels;
  std::vector<size_t> sizes;
  std::vector<char> border;
  const int n = Label(m, bw, bh, 1, &labels, &sizes, &border);
  const size_t largest = n ? *std::max_element(sizes.begin() + 1, sizes.end()) : 0;
  const double min_size =
      std::max(p.min_component * double(mask->pixels.size()), p.keep_relative * largest);
  for (size_t i = 0; i < m.size(); ++i) {
    if (m[i] && sizes[labels[i]] < min_size) m[i] = 0;
  }
  // Holes: background regions enclosed by the actor (not touching the border)
  // and tiny relative to it (misclassified texels, not the gap between two legs)
  // are filled.
  Label(m, bw, bh, 0, &labels, &sizes, &border);
  for (size_t i = 0; i < m.size(); ++i) {
    if (!m[i] && !border[labels[i]] && sizes[labels[i]] < 0.01 * largest) m[i] = 1;
  }
  std::fill(mask->pixels.begin(), mask->pixels.end(), 0);
  for (int y = 0; y < bh; ++y) {
    for (int x = 0; x < bw; ++x)
      mask->pixels[size_t(y0 + y) * w + x0 + x] = m[size_t(y) * bw + x] ? 255 : 0;
  }
}

void RefineMaskEdges(Image* coarse, const Image& fine, int radius) {
  const int w = int(coarse->width), h = int(coarse->height), r = std::max(1, radius);
  // Ones of the coarse mask in each (2r + 1)^2 window, from a summed-area
  // table over the mask's box grown by the radius (nothing changes outside).
  const MaskBox box = SetPixelBox(coarse->pixels.data(), w, h);
  if (box.empty()) return;
  const int x0 = std::max(0, box.x0 - r), y0 = std::max(0, box.y0 - r);
  const int x1 = std::min(w - 1, box.x1 + r), y1 = std::min(h - 1, box.y1 + r);
  const int bw = x1 - x0 + 1, bh = y1 - y0 + 1;
  std::vector<int32_t> sum(size_t(bw + 1) * (bh + 1), 0);
  for (int y = 0; y < bh; ++y) {
    int32_t row = 0;
    for (int x = 0; x < bw; ++x) {
      row += coarse->pixels[size_t(y0 + y) * w + x0 + x] != 0;
      sum[size_t(y + 1) * (bw + 1) + x + 1] = sum[size_t(y) * (bw + 1) + x + 1] + row;
    }
  }
  auto ones = [&](int x, int y) {  // window around box pixel (x, y), clipped to the box
    const int ax = std::max(0, x - r), ay = std::max(0, y - r);
    const int bx = std::min(bw - 1, x + r), by = std::min(bh - 1, y + r);
    const size_t s = size_t(bw + 1);
    return sum[(by + 1) * s + bx + 1] - sum[ay * s + bx + 1] - sum[(by + 1) * s + ax] +
           sum[ay * s + ax];
  };
  const int32_t full = (2 * r + 1) * (2 * r + 1);
  std::vector<uint8_t> out(size_t(bw) * bh);
  for (int y = 0; y < bh; ++y) {
    for (int x = 0; x < bw; ++x) {
      const int32_t n = ones(x, y);
      const size_t i = size_t(y0 + y) * w + x0 + x;
      out[size_t(y) * bw + x] = n == full ? 255 : n == 0 ? 0 : (fine.pixels[i] ? 255 : 0);
    }
  }
  for (int y = 0; y < bh; ++y) {
    std::copy_n(&out[size_t(y) * bw], bw, &coarse->pixels[size_t(y0 + y) * w + x0]);
  }
}

StatusOr<Image> ExtractSilhouette(const Image& frame, const BackgroundModel& bg,
                                  const SilhouetteParams& p) {
  const Image& b = bg.colour;
  if (frame.channels != 3 || b.channels != 3 || frame.width != b.width ||
      frame.height != b.height) {
    return InvalidArgument("silhouette: frame and background must be RGB images of one size");
  }
  Image mask;
  mask.width = frame.width;
  mask.height = frame.height;
  mask.channels = 1;
  mask.pixels.assign(size_t{frame.width} * frame.height, 0);
  for (size_t i = 0; i < mask.pixels.size(); ++i) {
    const double ir = frame.pixels[3 * i], ig = frame.pixels[3 * i + 1],
                 ib = frame.pixels[3 * i + 2];
    const double br = b.pixels[3 * i], bgc = b.pixels[3 * i + 1], bb = b.pixels[3 * i + 2];
    if (std::abs(ir - br) + std::abs(ig - bgc) + std::abs(ib - bb) < p.min_difference) continue;
    // Brightness distortion alpha (I ~ alpha B) and chroma distortion |I - alpha B|.
    const double bnorm2 = br * br + bgc * bgc + bb * bb + 1e-6;
    const double alpha = (ir * br + ig * bgc + ib * bb) / bnorm2;
    const double cd =
        std::sqrt((ir - alpha * br) * (ir - alpha * br) + (ig - alpha * bgc) * (ig - alpha * bgc) +
                  (ib - alpha * bb) * (ib - alpha * bb));
    // Relative to the pixel's expected brightness (alpha |B|): a dark, shaded
    // actor has little absolute chroma but still differs in direction.
    const double chroma_limit = p.chroma + p.chroma_relative * alpha * std::sqrt(bnorm2);
    const bool shade = alpha >= p.shadow_low && alpha <= p.highlight_high && cd < chroma_limit;
    if (!shade) mask.pixels[i] = 255;
  }
  CleanMask(&mask, p);
  return mask;
}

double MaskIou(const Image& a, const Image& b) {
  size_t inter = 0, uni = 0;
  for (size_t i = 0; i < a.pixels.size() && i < b.pixels.size(); ++i) {
    const bool x = a.pixels[i] != 0, y = b.pixels[i] != 0;
    inter += x && y;
    uni += x || y;
  }
  return uni ? double(inter) / uni : 1.0;
}

}  // namespace fvv
