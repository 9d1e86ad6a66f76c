// Motion track encoder: one 'motn' box per fragment (SPEC.md 6.3).
#include <zstd.h>

#include "container/motion_traversal.h"

namespace fvv {
namespace motion {
namespace {

class ArithWriter {
 public:
  uint32_t Flag(uint32_t bit, uint16_t* p) {
    rc_.Encode<kAdaptShift>(bit, p);
    return bit;
  }
  int64_t Residual(int64_t r, ResidualContexts& c, int cls) {
    Flag(r != 0, &c.zero[cls]);
    if (r == 0) return 0;
    Flag(r < 0, &c.sign);
    const uint64_t m = static_cast<uint64_t>(r < 0 ? -r : r);
    const int n = BitLength(m);
    for (int i = 0; i < n; ++i) {
      Flag(i + 1 < n, &c.length[cls][i < kMaxLengthBins ? i : kMaxLengthBins - 1]);
    }
    for (int i = n - 2; i >= 0; --i) {
      uint16_t even = kProbInit;  // lower mantissa bits are close to uniform
      Flag((m >> i) & 1, i == n - 2 ? &c.mantissa[n] : &even);
    }
    return r;
  }
  bool ok() const { return true; }
  std::vector<uint8_t> Finish() { return rc_.Finish(); }

 private:
  RangeEncoder rc_;
};

class ByteWriterSide {
 public:
  uint32_t Flag(uint32_t bit, uint16_t*) {
    out_.push_back(static_cast<uint8_t>(bit));
    return bit;
  }
  int64_t Residual(int64_t r, ResidualContexts&, int) {
    // zigzag, then LEB128
    uint64_t z = r < 0 ? (static_cast<uint64_t>(-(r + 1)) << 1) | 1 : static_cast<uint64_t>(r) << 1;
    do {
      out_.push_back(static_cast<uint8_t>((z & 0x7F) | (z > 0x7F ? 0x80 : 0)));
      z >>= 7;
    } while (z != 0);
    return r;
  }
  bool ok() const { return true; }
  std::vector<uint8_t> out_;
};

std::vector<uint8_t> CodeWith(MotionCoder coder, const Skeleton& skeleton, Predictor predictor,
                              std::vector<QuantisedPose> poses) {
  if (coder == MotionCoder::kArith) {
    ArithWriter w;
    TraverseMotion(w, skeleton, predictor, &poses);
    return w.Finish();
  }
  ByteWriterSide w;
  TraverseMotion(w, skeleton, predictor, &poses);
  std::vector<uint8_t> packed(ZSTD_compressBound(w.out_.size()));
  const size_t n = ZSTD_compress(packed.data(), packed.size(), w.out_.data(), w.out_.size(), 19);
  packed.resize(ZSTD_isError(n) ? 0 : n);
  return packed;
}

}  // namespace
}  // namespace motion

StatusOr<std::vector<uint8_t>> EncodeMotion(const Skeleton& skeleton, const MotionParams& p,
                                               const std::vector<QuantisedPose>& poses) {
  FVV_RETURN_IF_ERROR(ValidateMotionParams(p));
  if (poses.empty()) return InvalidArgument("motion: a fragment needs at least one frame");
  const size_t dof_count = skeleton.Dofs().size();
  std::vector<QuantisedPose> coded;
  for (uint32_t f : CodedFrameIndices(static_cast<uint32_t>(poses.size()), p.key_interval)) {
    if (poses[f].size() != dof_count) {
      return InvalidArgument("motion: frame " + std::to_string(f) + " has " +
                             std::to_string(poses[f].size()) + " values, the skeleton " +
                             std::to_string(dof_count) + " DOFs");
    }
    coded.push_back(poses[f]);
  }
  // Both predictors are tried; the fragment records the one that codes smaller.
  std::vector<uint8_t> best;
  motion::Predictor best_predictor = motion::kPreviousValue;
  for (motion::Predictor pred : {motion::kPreviousValue, motion::kLinearExtrapolation}) {
    std::vector<uint8_t> data = motion::CodeWith(p.coder, skeleton, pred, coded);
    if (data.empty()) return Internal("motion: zstd compression failed");
    if (best.empty() || data.size() < best.size()) {
      best = std::move(data);
      best_predictor = pred;
    }
  }
  ByteWriter w;
  w.U8(best_predictor);
  w.Bytes(best);
  return std::move(w.bytes());
}

}  // namespace fvv
