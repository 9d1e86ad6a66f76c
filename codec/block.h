// The 4D texture block: samples indexed (frame t, camera c, row y, column x).
// One GOP of multi-view texture is one block; a still image is a 1x1xHxW block.
#ifndef FVV_CODEC_BLOCK_H_
#define FVV_CODEC_BLOCK_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "codec/base/large_buffer.h"

namespace fvv {

constexpr int kAxes = 4;  // axis order everywhere: 0 = t, 1 = c, 2 = y, 3 = x

struct Shape4D {
  std::array<uint32_t, kAxes> n{1, 1, 1, 1};

  uint32_t frames() const { return n[0]; }
  uint32_t cameras() const { return n[1]; }
  uint32_t height() const { return n[2]; }
  uint32_t width() const { return n[3]; }
  size_t count() const { return size_t{n[0]} * n[1] * n[2] * n[3]; }
  // Row-major with x fastest.
  size_t Stride(int axis) const {
    size_t s = 1;
    for (int a = kAxes - 1; a > axis; --a) s *= n[a];
    return s;
  }
  size_t Index(uint32_t t, uint32_t c, uint32_t y, uint32_t x) const {
    return ((size_t{t} * n[1] + c) * n[2] + y) * n[3] + x;
  }
  bool operator==(const Shape4D& o) const { return n == o.n; }
  bool operator!=(const Shape4D& o) const { return n != o.n; }
  std::string ToString() const;  // "8x8x512x512 (frames x cameras x height x width)"
};

// One channel of a block. Samples are integers in the channel's nominal range
// (see ColourSpace); int32 leaves room for transforms done in place.
struct Plane4D {
  Shape4D shape;
  std::vector<int32_t> samples;

  Plane4D() = default;
  explicit Plane4D(const Shape4D& s, int32_t fill = 0) : shape(s) {
    AssignLarge(&samples, s.count(), fill);
  }
};

// How the three channels relate to RGB.
enum class ColourSpace : uint8_t {
  kYCbCr601 = 0,  // BT.601 full range, all channels 0..255, chroma centred on 128 (lossy)
  kRct = 1,       // JPEG 2000 reversible colour transform: Y 0..255, U and V -255..255 (lossless)
};

enum class ChromaFormat : uint8_t {
  k444 = 0,  // U and V at full resolution (their rate is reduced by rate allocation instead)
  k420 = 1,  // U and V halved in height and width
};

// How a 4:2:0 chroma plane returns to luma resolution for RGB (SPEC.md 9.7).
// The samples are the same either way; a stream's tool bit 18 says which.
enum class ChromaUpsampling : uint8_t {
  kNearest = 0,   // each sample over its 2x2 cell (format versions 1-8)
  kBilinear = 1,  // centred in its cell, weights 9/3/3/1 of 16 (format version 9)
};

// Fractional bits of a block's samples (SPEC.md 9.6): with p of them a sample
// counts 2^-p steps of the 8-bit scale, so Y, U and V keep what the BT.601
// conversion computes below a whole step instead of rounding it away twice (on
// the way in and on the way out); at high rates that rounding was most of the
// error. Lossless coding (RCT) and the reversible kernels use whole samples.
constexpr int kMaxSampleFrac = 4;
// What encoders use with the 9/7 (3 keeps nearly all of the gain of 4).
constexpr int kDefaultSampleFrac = 3;

struct Block {
  ColourSpace colour = ColourSpace::kYCbCr601;
  ChromaFormat chroma = ChromaFormat::k444;
  ChromaUpsampling upsampling = ChromaUpsampling::kNearest;  // with k420
  std::array<Plane4D, 3> channels;                           // Y, U, V
  // Fractional bits p of every sample: 0 (whole samples) in format versions
  // before 7. Y is in 0..255 * 2^p, and so are U and V in YCbCr.
  uint8_t sample_frac = 0;

  const Shape4D& shape() const { return channels[0].shape; }
};

// Shape of the chroma planes for a luma shape under a chroma format.
Shape4D ChromaShape(const Shape4D& luma, ChromaFormat format);

// Per-texel "used" flags (1 = some camera saw the texel). Same shape as luma.
using UsedMask = std::vector<uint8_t>;

// Nominal sample range of a channel, used for level shift and output clamping.
struct SampleRange {
  int32_t min, max, offset;  // offset is subtracted before the transform (level shift)
  int frac = 0;              // fractional bits of the samples (all three fields are scaled)
};
SampleRange ChannelRange(ColourSpace colour, int channel, int sample_frac = 0);

}  // namespace fvv

#endif  // FVV_CODEC_BLOCK_H_
