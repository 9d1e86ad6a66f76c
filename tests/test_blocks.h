// Deterministic test blocks shared by the codec suites.
#ifndef FVV_TESTS_TEST_BLOCKS_H_
#define FVV_TESTS_TEST_BLOCKS_H_

#include <cmath>
#include <cstdint>
#include <random>

#include "codec/block.h"

namespace fvv::testing {

// Shapes with odd, unequal and unit extents: where trees and bands have corners.
inline const Shape4D kOddShapes[] = {Shape4D{{3, 5, 17, 33}}, Shape4D{{1, 1, 64, 64}},
                                     Shape4D{{8, 8, 32, 32}}, Shape4D{{2, 7, 1, 9}},
                                     Shape4D{{1, 1, 1, 1}},   Shape4D{{5, 1, 3, 1}}};

// Uniform random samples in each channel's full range.
inline Block RandomBlock(const Shape4D& shape, ColourSpace colour, uint32_t seed) {
  std::mt19937 rng(seed);
  Block b;
  b.colour = colour;
  for (int c = 0; c < 3; ++c) {
    const SampleRange r = ChannelRange(colour, c);
    b.channels[c] = Plane4D(shape);
    std::uniform_int_distribution<int32_t> d(r.min, r.max);
    for (int32_t& s : b.channels[c].samples) s = d(rng);
  }
  return b;
}

// Smooth content with a little noise: what wavelets are for.
// A block whose sample of channel c at (t, cam, y, x) is value(c, t, cam, y, x),
// called in storage order, channel by channel.
template <class Fn>
Block FunctionBlock(const Shape4D& shape, ColourSpace colour, Fn value) {
  Block b;
  b.colour = colour;
  for (int c = 0; c < 3; ++c) {
    b.channels[c] = Plane4D(shape);
    size_t i = 0;
    for (uint32_t t = 0; t < shape.n[0]; ++t)
      for (uint32_t cam = 0; cam < shape.n[1]; ++cam)
        for (uint32_t y = 0; y < shape.n[2]; ++y)
          for (uint32_t x = 0; x < shape.n[3]; ++x, ++i)
            b.channels[c].samples[i] = value(c, t, cam, y, x);
  }
  return b;
}

inline Block SmoothBlock(const Shape4D& shape, ColourSpace colour, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> noise(-2, 2);
  return FunctionBlock(shape, colour, [&](int c, uint32_t t, uint32_t cam, uint32_t y, uint32_t x) {
    const SampleRange r = ChannelRange(colour, c);
    const double v =
        (r.max + r.min) / 2.0 + (r.max - r.min) * 0.3 *
                                    std::sin(0.11 * x + 0.07 * y + 0.3 * t + 0.2 * cam + c) *
                                    std::cos(0.05 * x - 0.09 * y);
    return std::clamp<int32_t>(static_cast<int32_t>(v) + noise(rng), r.min, r.max);
  });
}

inline uint64_t Fnv1a(const void* data, size_t n, uint64_t h = 1469598103934665603ull) {
  const uint8_t* p = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

inline uint64_t HashBlock(const Block& b) {
  uint64_t h = 1469598103934665603ull;
  for (const Plane4D& p : b.channels) h = Fnv1a(p.samples.data(), p.samples.size() * 4, h);
  return h;
}

}  // namespace fvv::testing

#endif  // FVV_TESTS_TEST_BLOCKS_H_
