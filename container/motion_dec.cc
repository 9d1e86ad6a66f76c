// Motion track decoder (SPEC.md 6.3, 6.4).

#include "container/motion_common.h"
#include "container/zstd_frame.h"

namespace fvv {
namespace motion {
namespace {

class ArithReader {
 public:
  ArithReader(const uint8_t* data, size_t size) : rc_(data, size) {}
  void Begin(uint16_t*) {}
  uint32_t Flag(uint32_t, uint16_t* p) { return rc_.Decode<kAdaptShift>(p); }
  int64_t Residual(int64_t, ResidualContexts& c, int cls) {
    bool too_long = false;
    const int64_t r = CodeResidualBins([this](uint32_t, uint16_t* p) { return Flag(0, p); }, 0, c,
                                       cls, &too_long);
    bad_ |= too_long;
    return r;
  }
  bool ok() const { return rc_.ok() && !bad_; }

 private:
  RangeDecoder rc_;
  bool bad_ = false;
};

class ByteReaderSide {
 public:
  ByteReaderSide(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  void Begin(uint16_t*) {}
  uint32_t Flag(uint32_t, uint16_t*) {
    if (pos_ >= size_) return Fail();
    const uint8_t b = data_[pos_++];
    if (b > 1) return Fail();
    return b;
  }
  int64_t Residual(int64_t, ResidualContexts&, int) {
    uint64_t z = 0;
    for (int shift = 0;; shift += 7) {
      if (pos_ >= size_ || shift > 35) return Fail();
      const uint8_t b = data_[pos_++];
      z |= uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) break;
    }
    const int64_t half = static_cast<int64_t>(z >> 1);
    return (z & 1) ? -half - 1 : half;
  }
  bool ok() const { return !bad_; }
  bool fully_read() const { return pos_ == size_; }

 private:
  uint32_t Fail() {
    bad_ = true;
    return 0;
  }
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  bool bad_ = false;
};

}  // namespace
}  // namespace motion

Status DecodeMotion(const BoxHeader& box, const uint8_t* payload, const Skeleton& skeleton,
                    const MotionParams& p, uint32_t frame_count,
                    std::vector<DecodedFrame>* frames) {
  const std::string at = BoxContext(box);
  if (box.version != 0) return Unsupported(at + "version " + std::to_string(box.version));
  if (box.payload_size() < 1) return Corrupt(at + "empty");
  const auto predictor = static_cast<motion::Predictor>(payload[0]);
  if (predictor > motion::kLinearExtrapolation) {
    return Corrupt(at + "predictor " + std::to_string(payload[0]) + " unknown");
  }
  const uint8_t* data = payload + 1;
  const size_t size = static_cast<size_t>(box.payload_size() - 1);
  const std::vector<uint32_t> coded_indices = CodedFrameIndices(frame_count, p.key_interval);
  const size_t dof_count = skeleton.Dofs().size();
  if (!p.key_reference.empty() && p.key_reference.size() != dof_count) {
    return Corrupt(at + "the motion parameters give statistics for " +
                   std::to_string(p.key_reference.size()) + " DOFs, the skeleton has " +
                   std::to_string(dof_count));
  }
  std::vector<QuantisedPose> coded(coded_indices.size(), QuantisedPose(dof_count, 0));
  bool ok;
  if (p.coder == MotionCoder::kArith) {
    motion::ArithReader r(data, size);
    ok = motion::TraverseMotion(r, skeleton, p, predictor, &coded);
  } else {
    // The byte form needs at most one byte per flag and 5 per residual.
    const uint64_t bound = uint64_t{coded.size()} * (skeleton.bones.size() + dof_count * 6) + 16;
    const StatusOr<uint64_t> content = ZstdContentSize(data, size);
    if (!content.ok() || *content > bound) {
      return Corrupt(at + "zstd frame size missing or beyond what " + std::to_string(frame_count) +
                     " frames can need");
    }
    std::vector<uint8_t> raw(static_cast<size_t>(*content));
    if (!ZstdDecompress(data, size, &raw).ok()) return Corrupt(at + "zstd data does not decode");
    motion::ByteReaderSide r(raw.data(), raw.size());
    ok = motion::TraverseMotion(r, skeleton, p, predictor, &coded) && r.fully_read();
  }
  if (!ok) return Corrupt(at + "motion data is truncated or invalid");
  frames->assign(frame_count, DecodedFrame());
  for (size_t j = 0; j < coded_indices.size(); ++j) {
    DecodedFrame& f = (*frames)[coded_indices[j]];
    f.coded = true;
    f.values = std::move(coded[j]);
    f.bones = BoneMotionsFromPose(skeleton, p, f.values);
  }
  motion::Interpolate(coded_indices, frames);
  return Status::Ok();
}

}  // namespace fvv
