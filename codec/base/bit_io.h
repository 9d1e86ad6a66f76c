// The one bit reader of fvv, and its writer. MSB-first.
// Reading past the end (or past a caller-set budget) yields zeros and sets a
// sticky flag; callers check it at syntax-element boundaries instead of after
// every bit (dav1d GetBits, libjxl BitReader).
#ifndef FVV_CODEC_BASE_BIT_IO_H_
#define FVV_CODEC_BASE_BIT_IO_H_

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace fvv {

class BitWriter {
 public:
  void PutBit(uint32_t bit) {
    acc_ = (acc_ << 1) | (bit & 1);
    if (++nacc_ == 8) {
      bytes_.push_back(static_cast<uint8_t>(acc_));
      acc_ = 0;
      nacc_ = 0;
    }
  }
  void PutBits(uint32_t value, int count) {
    for (int i = count - 1; i >= 0; --i) PutBit(value >> i);
  }
  uint64_t bit_count() const { return uint64_t{bytes_.size()} * 8 + nacc_; }
  // Pads the last byte with zeros.
  std::vector<uint8_t> Finish() {
    while (nacc_ != 0) PutBit(0);
    return std::move(bytes_);
  }

 private:
  std::vector<uint8_t> bytes_;
  uint32_t acc_ = 0;
  int nacc_ = 0;
};

class BitReader {
 public:
  BitReader(const uint8_t* data, size_t size) : data_(data), limit_bits_(uint64_t{size} * 8) {}

  // True if `count` more bits can be read without passing the end.
  bool CanRead(uint64_t count) const { return pos_ + count <= limit_bits_; }
  uint32_t GetBit() {
    if (pos_ >= limit_bits_) {
      overrun_ = true;
      return 0;
    }
    const uint32_t bit = (data_[pos_ >> 3] >> (7 - (pos_ & 7))) & 1;
    ++pos_;
    return bit;
  }
  uint32_t GetBits(int count) {
    uint32_t v = 0;
    for (int i = 0; i < count; ++i) v = (v << 1) | GetBit();
    return v;
  }
  bool overrun() const { return overrun_; }
  uint64_t bit_position() const { return pos_; }
  size_t bytes_consumed() const { return static_cast<size_t>((pos_ + 7) / 8); }

 private:
  const uint8_t* data_;
  uint64_t limit_bits_;
  uint64_t pos_ = 0;
  bool overrun_ = false;
};

// Little-endian byte-level reader for headers, with the same sticky-error rule.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint8_t U8() { return pos_ + 1 <= size_ ? data_[pos_++] : Fail8(); }
  uint16_t U16() {
    const uint32_t lo = U8();  // two statements: operand evaluation order is unspecified
    return static_cast<uint16_t>(lo | (uint32_t{U8()} << 8));
  }
  uint32_t U32() {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t{U8()} << (8 * i);
    return v;
  }
  uint64_t U64() {
    const uint64_t lo = U32();
    return lo | (uint64_t{U32()} << 32);
  }
  int16_t I16() { return static_cast<int16_t>(U16()); }
  int32_t I32() { return static_cast<int32_t>(U32()); }
  // IEEE-754 binary32 / binary64, stored by bit pattern.
  float F32() {
    const uint32_t bits = U32();
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }
  double F64() {
    const uint64_t bits = U64();
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
  }
  // string(): u16 byte length, then that many bytes of UTF-8.
  std::string Str() {
    const uint16_t n = U16();
    const uint8_t* p = Bytes(n);
    return p ? std::string(reinterpret_cast<const char*>(p), n) : std::string();
  }
  // Returns nullptr (and sets the error) if fewer than n bytes remain.
  const uint8_t* Bytes(size_t n) {
    if (n > size_ - pos_) {
      overrun_ = true;
      pos_ = size_;
      return nullptr;
    }
    const uint8_t* p = data_ + pos_;
    pos_ += n;
    return p;
  }
  size_t remaining() const { return size_ - pos_; }
  size_t position() const { return pos_; }
  bool overrun() const { return overrun_; }

 private:
  uint8_t Fail8() {
    overrun_ = true;
    return 0;
  }
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  bool overrun_ = false;
};

class ByteWriter {
 public:
  void U8(uint32_t v) { bytes_.push_back(static_cast<uint8_t>(v)); }
  void U16(uint32_t v) {
    U8(v);
    U8(v >> 8);
  }
  void U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) U8(v >> (8 * i));
  }
  void U64(uint64_t v) {
    U32(static_cast<uint32_t>(v));
    U32(static_cast<uint32_t>(v >> 32));
  }
  void I16(int32_t v) { U16(static_cast<uint32_t>(v)); }
  void I32(int32_t v) { U32(static_cast<uint32_t>(v)); }
  void F32(float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    U32(bits);
  }
  void F64(double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, 8);
    U64(bits);
  }
  // Strings longer than 65535 bytes are cut; callers validate lengths first.
  void Str(const std::string& s) {
    const size_t n = s.size() < 65535 ? s.size() : 65535;
    U16(static_cast<uint32_t>(n));
    Bytes(reinterpret_cast<const uint8_t*>(s.data()), n);
  }
  void Bytes(const uint8_t* p, size_t n) { bytes_.insert(bytes_.end(), p, p + n); }
  void Bytes(const std::vector<uint8_t>& v) { Bytes(v.data(), v.size()); }
  // Overwrites 4 bytes written earlier (sizes known only after the content).
  void PatchU32(size_t pos, uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_[pos + i] = static_cast<uint8_t>(v >> (8 * i));
  }
  void PatchU64(size_t pos, uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_[pos + i] = static_cast<uint8_t>(v >> (8 * i));
  }
  size_t size() const { return bytes_.size(); }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

}  // namespace fvv

#endif  // FVV_CODEC_BASE_BIT_IO_H_
