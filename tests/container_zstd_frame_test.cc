// The zstd frames the decoder reads: XXH64 against the content checksums
// libzstd writes (the WebAssembly build checks frames with it), the declared
// size, and a frame whose content no longer matches its checksum.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "container/zstd_frame.h"

namespace fvv {
namespace {

uint32_t StoredChecksum(const std::vector<uint8_t>& frame) {
  const size_t n = frame.size();
  return uint32_t(frame[n - 4]) | (uint32_t(frame[n - 3]) << 8) | (uint32_t(frame[n - 2]) << 16) |
         (uint32_t(frame[n - 1]) << 24);
}

TEST(ZstdFrame, Xxh64IsTheChecksumLibzstdWrites) {
  EXPECT_EQ(Xxh64(nullptr, 0), 0xEF46DB3751D8E999ull);  // the algorithm's empty input
  std::mt19937 rng(7);
  // Every tail length and stripe count: 0..99 bytes, then larger sizes.
  std::vector<size_t> sizes;
  for (size_t n = 1; n < 100; ++n) sizes.push_back(n);
  for (size_t n : {255, 1024, 4099, 100000}) sizes.push_back(n);
  for (size_t n : sizes) {
    std::vector<uint8_t> data(n);
    for (uint8_t& b : data) b = uint8_t(rng() % 7);  // compressible, so zstd codes blocks
    const std::vector<uint8_t> frame = ZstdCompress(data.data(), data.size(), 3);
    ASSERT_GE(frame.size(), 8u) << n;
    EXPECT_EQ(uint32_t(Xxh64(data.data(), data.size())), StoredChecksum(frame)) << n;
  }
}

TEST(ZstdFrame, ADamagedFrameIsCorrupt) {
  std::vector<uint8_t> data(5000);
  for (size_t i = 0; i < data.size(); ++i) data[i] = uint8_t(i * i % 13);
  std::vector<uint8_t> frame = ZstdCompress(data.data(), data.size(), 19);
  auto size = ZstdContentSize(frame.data(), frame.size());
  ASSERT_TRUE(size.ok());
  EXPECT_EQ(*size, data.size());
  std::vector<uint8_t> out(data.size());
  ASSERT_TRUE(ZstdDecompress(frame.data(), frame.size(), &out).ok());
  EXPECT_EQ(out, data);
  frame.back() ^= 1;  // the stored checksum
  EXPECT_EQ(ZstdDecompress(frame.data(), frame.size(), &out).code(), StatusCode::kCorrupt);
  const uint8_t not_a_frame[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_EQ(ZstdContentSize(not_a_frame, 8).status().code(), StatusCode::kCorrupt);
}

}  // namespace
}  // namespace fvv
