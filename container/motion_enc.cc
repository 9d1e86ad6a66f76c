// Motion track encoder: one 'motn' box per fragment (SPEC.md 6.3).
#include <zstd.h>

#include <algorithm>

#include "container/motion_common.h"

namespace fvv {
namespace motion {
namespace {

class ArithWriter {
 public:
  void Begin(uint16_t*) {}
  uint32_t Flag(uint32_t bit, uint16_t* p) {
    rc_.Encode<kAdaptShift>(bit, p);
    return bit;
  }
  int64_t Residual(int64_t r, ResidualContexts& c, int cls) {
    bool unused;
    return CodeResidualBins([this](uint32_t bit, uint16_t* p) { return Flag(bit, p); }, r, c, cls,
                            &unused);
  }
  bool ok() const { return true; }
  std::vector<uint8_t> Finish() { return rc_.Finish(); }

 private:
  RangeEncoder rc_;
};

// Counts the decisions of each context (training of the initial probabilities).
class CountingSide {
 public:
  explicit CountingSide(std::vector<std::array<uint32_t, 2>>* counts) : counts_(*counts) {}
  void Begin(uint16_t* base) { base_ = base; }
  uint32_t Flag(uint32_t bit, uint16_t* p) {
    const ptrdiff_t i = p - base_;
    if (i >= 0 && static_cast<size_t>(i) < counts_.size()) ++counts_[i][bit & 1];
    return bit;
  }
  int64_t Residual(int64_t r, ResidualContexts& c, int cls) {
    bool unused;
    return CodeResidualBins([this](uint32_t bit, uint16_t* p) { return Flag(bit, p); }, r, c, cls,
                            &unused);
  }
  bool ok() const { return true; }

 private:
  std::vector<std::array<uint32_t, 2>>& counts_;
  uint16_t* base_ = nullptr;
};

class ByteWriterSide {
 public:
  void Begin(uint16_t*) {}
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

std::vector<uint8_t> CodeWith(const MotionParams& params, const Skeleton& skeleton,
                              Predictor predictor, std::vector<QuantisedPose> poses) {
  if (params.coder == MotionCoder::kArith) {
    ArithWriter w;
    TraverseMotion(w, skeleton, params, predictor, &poses);
    return w.Finish();
  }
  ByteWriterSide w;
  TraverseMotion(w, skeleton, params, predictor, &poses);
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
  if (!p.key_reference.empty() && p.key_reference.size() != dof_count) {
    return InvalidArgument("motion: statistics for " + std::to_string(p.key_reference.size()) +
                           " DOFs, the skeleton has " + std::to_string(dof_count));
  }
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
    std::vector<uint8_t> data = motion::CodeWith(p, skeleton, pred, coded);
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

namespace fvv {

void TrainMotionParams(const Skeleton& skeleton, const std::vector<QuantisedPose>& poses,
                       uint32_t gop_frames, MotionParams* p) {
  p->key_reference.clear();
  p->first_class.clear();
  p->context_init.clear();
  const size_t dofs = skeleton.Dofs().size();
  if (poses.empty() || gop_frames == 0) return;
  // Per DOF: the median value (key frames are coded against it) and the median
  // class of frame-to-frame changes (the context of a fragment's first
  // predicted frame).
  for (size_t d = 0; d < dofs; ++d) {
    std::vector<int32_t> values;
    std::vector<int> classes;
    for (size_t f = 0; f < poses.size(); ++f) {
      values.push_back(poses[f][d]);
      if (f > 0) {
        const int64_t r = int64_t{poses[f][d]} - poses[f - 1][d];
        classes.push_back(motion::ResidualClass(true, r));
      }
    }
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    p->key_reference.push_back(values[values.size() / 2]);
    int cls = motion::kClasses - 1;
    if (!classes.empty()) {
      std::nth_element(classes.begin(), classes.begin() + classes.size() / 2, classes.end());
      cls = classes[classes.size() / 2];
    }
    p->first_class.push_back(static_cast<uint8_t>(cls));
  }
  // Context statistics of the fragments as they will be coded.
  std::vector<std::array<uint32_t, 2>> counts(motion::kContextCount, {0, 0});
  for (size_t f0 = 0; f0 < poses.size(); f0 += gop_frames) {
    const uint32_t n = static_cast<uint32_t>(std::min<size_t>(gop_frames, poses.size() - f0));
    std::vector<QuantisedPose> coded;
    for (uint32_t f : CodedFrameIndices(n, p->key_interval)) coded.push_back(poses[f0 + f]);
    motion::CountingSide side(&counts);
    motion::TraverseMotion(side, skeleton, *p, motion::kLinearExtrapolation, &coded);
  }
  for (size_t i = 0; i < counts.size(); ++i) {
    const uint64_t n0 = counts[i][0], n = counts[i][0] + counts[i][1];
    if (n < 4) continue;
    // Stored as p8 in 1..254, probability p8 * 128 + 64 (SPEC.md 3.4).
    const uint64_t p8 = ((n0 * 2 + 1) << (kProbBits - 7)) / (2 * n + 2);
    const uint64_t clamped = std::min<uint64_t>(std::max<uint64_t>(p8, 1), 254);
    p->context_init.push_back(
        {static_cast<uint16_t>(i), static_cast<uint16_t>(clamped * 128 + 64)});
  }
}

}  // namespace fvv
