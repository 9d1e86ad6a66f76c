// Fuzz target: the motion track decoder on the sample skeleton. Byte 0 picks
// the coder and key interval, byte 1 the frame count; the rest is a 'motn' payload.
#include <cstddef>
#include <cstdint>

#include "container/motion_track.h"
#include "fuzz/fuzz_skeleton.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  fvv::MotionParams p;
  p.coder = (data[0] & 1) ? fvv::MotionCoder::kZstd : fvv::MotionCoder::kArith;
  p.key_interval = static_cast<uint16_t>(1 + ((data[0] >> 1) & 7));
  const uint32_t frames = 1 + data[1] % 32;
  fvv::BoxHeader h;
  h.type = fvv::box::kMotion;
  h.header_size = 12;
  h.size = size - 2 + 12;
  std::vector<fvv::DecodedFrame> out;
  (void)fvv::DecodeMotion(h, data + 2, fvv::FuzzSkeleton(), p, frames, &out);
  return 0;
}
