// Every prefix and every single-byte change of a small sample stream ends in a
// defined outcome (a valid decode or an error status), never a crash or a hang.
// Run under ASan+UBSan in CI (tools/test.sh), which is what makes it bite.
#include <gtest/gtest.h>

#include "conformance/sample/sample_stream.h"
#include "container/file_reader.h"
#include "fuzz/decode_all.h"

namespace fvv {
namespace {

std::vector<uint8_t> TinyStream(bool fast_start) {
  SampleStreamOptions o = TinySampleOptions();
  o.frac_bits_97 = kFracBits97;  // 'texr' version 1, as the encoder writes by default
  o.vertex_visibility = true;
  o.key_interval = 2;
  o.fast_start = fast_start;
  auto s = MakeSampleStreamBytes(o);
  EXPECT_TRUE(s.ok());
  return s.ok() ? *s : std::vector<uint8_t>();
}

TEST(Robustness, EveryPrefixIsTruncatedOrValid) {
  for (bool fast_start : {true, false}) {
    const std::vector<uint8_t> s = TinyStream(fast_start);
    ASSERT_FALSE(s.empty());
    DecodeAllReport full;
    ASSERT_TRUE(DecodeAll(s.data(), s.size(), 0, &full).ok());
    for (size_t n = 0; n < s.size(); ++n) {
      DecodeAllReport r;
      const Status st = DecodeAll(s.data(), n, 0, &r);
      // Any proper prefix of a complete stream misses something it declared.
      ASSERT_FALSE(st.ok()) << "prefix " << n << " of " << s.size() << " decoded";
      EXPECT_TRUE(st.code() == StatusCode::kTruncated || st.code() == StatusCode::kCorrupt)
          << n << ": " << st.ToString();
    }
  }
}

TEST(Robustness, EverySingleByteChangeEndsDefined) {
  const std::vector<uint8_t> s = TinyStream(true);
  ASSERT_FALSE(s.empty());
  DecodeAllReport clean;
  ASSERT_TRUE(DecodeAll(s.data(), s.size(), 0, &clean).ok());
  // Where the fragment payloads are: every change there must be caught (CRC-32C
  // detects any single-byte error). Elsewhere, any defined outcome will do.
  MemorySource src(s.data(), s.size());
  auto reader = FileReader::Open(&src);
  ASSERT_TRUE(reader.ok());
  std::vector<bool> in_payload(s.size(), false);
  for (const IndexEntry& e : (*reader)->info().index) {
    for (uint64_t k = e.offset + 12; k < e.offset + e.size; ++k) in_payload[k] = true;
  }
  size_t payload_bytes = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    payload_bytes += in_payload[i];
    for (uint8_t delta : {uint8_t{0x01}, uint8_t{0x80}, uint8_t{0xFF}}) {
      std::vector<uint8_t> bad = s;
      bad[i] ^= delta;
      DecodeAllReport r;
      const Status st = DecodeAll(bad.data(), bad.size(), 13, &r);
      if (in_payload[i]) {
        // The checksum, or the sub-box structure checked before it.
        EXPECT_FALSE(st.ok()) << "byte " << i << " ^ " << int(delta);
      }
    }
  }
  EXPECT_GT(payload_bytes, s.size() / 6);  // the fragments are a good part of the stream
}

}  // namespace
}  // namespace fvv
