// Adaptive binary range coder (carry-propagating, byte-oriented, in the family of
// the LZMA coder) used for SPIHT decisions in "arith" mode.
//
// Probabilities are 15-bit estimates of P(bit = 0), adapted by 1/32 of the error
// after each decision. The encoder's first output byte is always zero and is not
// stored. Truncation rule (what makes the stream embedded): a decoder that must
// read a byte at or beyond its budget stops before the next decision; every
// decision it has produced is then exactly the encoder's, because the 32-bit code
// register only ever held bytes of the real stream.
#ifndef FVV_CODEC_RANGE_CODER_H_
#define FVV_CODEC_RANGE_CODER_H_

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fvv {

constexpr int kProbBits = 15;
constexpr uint16_t kProbInit = 1u << (kProbBits - 1);
constexpr int kProbAdaptShift = 5;
constexpr uint32_t kRangeTop = 1u << 24;

class RangeEncoder {
 public:
  // kShift: adaptation rate; SPIHT uses the default, short streams (motion) adapt faster.
  template <int kShift = kProbAdaptShift>
  void Encode(uint32_t bit, uint16_t* prob) {
    EncodeWithProbability(bit, *prob);
    if (bit == 0) {
      *prob += ((1u << kProbBits) - *prob) >> kShift;
    } else {
      *prob -= *prob >> kShift;
    }
  }
  // Codes `bit` with a given 15-bit probability of a 0 in [1, 32767], which the
  // caller adapts (mixed models, codec/logistic_mixing.h).
  void EncodeWithProbability(uint32_t bit, uint32_t prob_zero) {
    const uint32_t bound = (range_ >> kProbBits) * prob_zero;
    if (bit == 0) {
      range_ = bound;
    } else {
      low_ += bound;
      range_ -= bound;
    }
    while (range_ < kRangeTop) {
      range_ <<= 8;
      ShiftLow();
    }
  }
  // Bytes a decoder must be given to decode every decision encoded so far.
  uint64_t BytesNeeded() const { return 4 + shifts_; }
  std::vector<uint8_t> Finish() {
    for (int i = 0; i < 5; ++i) ShiftLow();
    return std::move(out_);
  }

 private:
  void ShiftLow() {
    ++shifts_;
    if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
      uint8_t temp = cache_;
      do {
        Emit(static_cast<uint8_t>(temp + carry));
        temp = 0xFF;
      } while (--cache_size_ != 0);
      cache_ = static_cast<uint8_t>(low_ >> 24);
    }
    ++cache_size_;
    low_ = (low_ & 0x00FFFFFFu) << 8;
  }
  void Emit(uint8_t b) {
    if (first_) {
      first_ = false;  // always 0, not stored
      return;
    }
    out_.push_back(b);
  }

  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  uint64_t shifts_ = 0;
  bool first_ = true;
  std::vector<uint8_t> out_;
};

class RangeDecoder {
 public:
  // `budget` <= size: bytes the decoder may use.
  RangeDecoder(const uint8_t* data, size_t budget) : data_(data), budget_(budget) {
    for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | NextByte();
  }
  // False once a read went past the budget: no further decision is trustworthy.
  bool ok() const { return !exhausted_; }
  template <int kShift = kProbAdaptShift>
  uint32_t Decode(uint16_t* prob) {
    const uint32_t bit = DecodeWithProbability(*prob);
    if (bit == 0) {
      *prob += ((1u << kProbBits) - *prob) >> kShift;
    } else {
      *prob -= *prob >> kShift;
    }
    return bit;
  }
  // The decoder of RangeEncoder::EncodeWithProbability.
  uint32_t DecodeWithProbability(uint32_t prob_zero) {
    const uint32_t bound = (range_ >> kProbBits) * prob_zero;
    uint32_t bit;
    if (code_ < bound) {
      range_ = bound;
      bit = 0;
    } else {
      code_ -= bound;
      range_ -= bound;
      bit = 1;
    }
    while (range_ < kRangeTop) {
      range_ <<= 8;
      code_ = (code_ << 8) | NextByte();
    }
    return bit;
  }
  size_t bytes_consumed() const { return pos_ < budget_ ? pos_ : budget_; }

 private:
  uint32_t NextByte() {
    if (pos_ >= budget_) {
      exhausted_ = true;
      return 0;
    }
    return data_[pos_++];
  }
  const uint8_t* data_;
  size_t budget_;
  size_t pos_ = 0;
  uint32_t code_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  bool exhausted_ = false;
};

}  // namespace fvv

#endif  // FVV_CODEC_RANGE_CODER_H_
