// Streams with the predictive texture ('ptex', format version 2): the decoder
// library reproduces the encoder's closed-loop reconstruction, whole streams
// are lossless in YUV, byte budgets trade quality for bytes, and bad 'ptex'
// payloads or headers are refused with the right status, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "codec/base/thread_pool.h"
#include "codec/colour.h"
#include "codec/mask.h"
#include "codec/predictive_texture.h"
#include "conformance/sample/sample_stream.h"
#include "container/box.h"
#include "container/crc32c.h"
#include "container/file_reader.h"
#include "fuzz/decode_all.h"
#include "player/decoder/gop_decoder.h"

namespace fvv {
namespace {

SampleStreamOptions Options(bool lossless) {
  SampleStreamOptions o;
  o.frames = 4;
  o.cameras = 3;
  o.atlas_width = 40;
  o.atlas_height = 32;
  o.gop_frames = 4;
  o.gop_cameras = 3;
  o.kernel = WaveletKernel::kLeGall53;
  o.predictive = true;
  o.lossless = lossless;
  o.bpp = 1.0;
  return o;
}

// The span's GOP decoded by the player's decoder under `bytes` per fragment.
std::shared_ptr<DecodedGop> Decode(const std::vector<uint8_t>& bytes, uint64_t budget) {
  MemorySource src(bytes.data(), bytes.size());
  auto reader = FileReader::Open(&src);
  EXPECT_TRUE(reader.ok()) << reader.status().ToString();
  if (!reader.ok()) return nullptr;
  auto f = (*reader)->ReadFragment(0);
  EXPECT_TRUE(f.ok()) << f.status().ToString();
  if (!f.ok()) return nullptr;
  EXPECT_TRUE(f->predictive);
  GopBudget b;
  b.max_bytes = budget;
  auto gop = DecodeGop((*reader)->info(), {*f}, b, SerialRunner);
  EXPECT_TRUE(gop.ok()) << gop.status().ToString();
  return gop.ok() ? *gop : nullptr;
}

// Weighted error of the decoded YUV against the source over the used texels.
double Psnr(const SampleStream& src, const DecodedGop& gop) {
  double sse = 0;
  uint64_t n = 0;
  const Block& b = gop.textures[0];
  for (size_t i = 0; i < src.masks.size(); ++i) {
    if (!src.masks[i]) continue;
    const uint8_t* p = &src.rgb[i * 3];
    const Yuv yuv = RgbToYuv(ColourSpace::kYCbCr601, p[0], p[1], p[2]);
    const int32_t want[3] = {yuv.y, yuv.u, yuv.v};
    for (int k = 0; k < 3; ++k) {
      const double d = double(want[k]) - b.channels[k].samples[i];
      sse += d * d;
    }
    n += 3;
  }
  return sse == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 * double(n) / sse);
}

TEST(PredictiveStream, HeaderSaysVersionTwoAndTheTool) {
  auto s = MakeSampleStream(Options(false));
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  EXPECT_EQ(s->info.header.format_version, 2);
  EXPECT_TRUE(s->info.header.tools & kToolPredictiveTexture);
  EXPECT_FALSE(s->info.header.tools & (kToolSpihtArith | kToolSpihtBinary));
  // Streams without it keep format version 1 (old decoders read them).
  SampleStreamOptions plain = Options(false);
  plain.predictive = false;
  auto p = MakeSampleStream(plain);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p->info.header.format_version, 1);
}

TEST(PredictiveStream, WholeStreamIsLosslessInYuvThroughTheDecoder) {
  auto src = MakeSampleStream(Options(true));
  auto bytes = MakeSampleStreamBytes(Options(true));
  ASSERT_TRUE(src.ok() && bytes.ok());
  auto gop = Decode(*bytes, 0);
  ASSERT_TRUE(gop);
  EXPECT_EQ(Psnr(*src, *gop), 99.0);
  EXPECT_TRUE(gop->complete);
  // The decoded masks are the source's.
  EXPECT_EQ(gop->masks[0], src->masks);
}

TEST(PredictiveStream, ByteBudgetsTradeQualityForBytes) {
  auto src = MakeSampleStream(Options(false));
  auto bytes = MakeSampleStreamBytes(Options(false));
  ASSERT_TRUE(src.ok() && bytes.ok());
  const uint64_t total = src->fragments[0].predictive_texture.Bytes();
  double last = 0;
  for (uint64_t budget : {total / 8, total / 4, total / 2, total}) {
    auto gop = Decode(*bytes, budget);
    ASSERT_TRUE(gop);
    const double psnr = Psnr(*src, *gop);
    std::printf("  %llu of %llu bytes: %.2f dB\n", (unsigned long long)budget,
                (unsigned long long)total, psnr);
    EXPECT_GT(psnr, last + 0.5);
    EXPECT_LE(gop->bytes_decoded, budget);
    last = psnr;
  }
  EXPECT_GT(last, 30);
}

TEST(PredictiveStream, EveryPrefixIsTruncatedOrCorrupt) {
  SampleStreamOptions o = TinySampleOptions();
  o.kernel = WaveletKernel::kLeGall53;
  o.predictive = true;
  auto s = MakeSampleStreamBytes(o);
  ASSERT_TRUE(s.ok()) << s.status().ToString();
  DecodeAllReport full;
  ASSERT_TRUE(DecodeAll(s->data(), s->size(), 0, &full).ok());
  EXPECT_GT(full.fragments, 1u);
  for (size_t n = 0; n < s->size(); ++n) {
    DecodeAllReport r;
    const Status st = DecodeAll(s->data(), n, 0, &r);
    ASSERT_FALSE(st.ok()) << "prefix " << n;
    EXPECT_TRUE(st.code() == StatusCode::kTruncated || st.code() == StatusCode::kCorrupt)
        << st.ToString();
  }
}

// Random bytes in place of every stream decode safely (the CRC is what a
// reader checks first; the codec itself must still be safe on any bytes).
TEST(PredictiveStream, ArbitraryStreamBytesDecodeSafely) {
  auto src = MakeSampleStream(Options(false));
  ASSERT_TRUE(src.ok());
  PredictiveGop gop;
  gop.frames = 4, gop.cameras = 3, gop.width = 40, gop.height = 32;
  gop.mask = src->masks;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    PredictiveStreams s = src->fragments[0].predictive_texture;
    for (std::vector<uint8_t>* st : s.Ordered()) {
      st->resize(rng() % 64);
      for (uint8_t& b : *st) b = uint8_t(rng());
      if (!st->empty() && trial % 2 == 0) (*st)[0] = uint8_t(rng() % 31);  // a valid top plane
    }
    PredictiveDecoded out;
    const Status st = DecodePredictive(s, gop, &out);
    if (!st.ok()) {
      EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
      continue;
    }
    for (const auto& view : out.yuv) {
      for (const auto& plane : view) {
        for (int32_t v : plane) ASSERT_TRUE(v >= 0 && v <= 255);
      }
    }
  }
}

// The stream's fragment payload, rewritten by `edit` with a fresh checksum.
Status ReadEdited(const std::vector<uint8_t>& stream,
                  const std::function<void(FragmentData*, FileHeader*)>& edit) {
  MemorySource src(stream.data(), stream.size());
  auto reader = FileReader::Open(&src);
  if (!reader.ok()) return reader.status();
  auto f = (*reader)->ReadFragment(0);
  if (!f.ok()) return f.status();
  FileHeader h = (*reader)->info().header;
  FragmentData frag = *f;
  edit(&frag, &h);
  const std::vector<uint8_t> box = WriteFragmentBox(frag, false);
  FVV_ASSIGN_OR_RETURN(const BoxHeader b, ParseBoxHeader(box.data(), box.size(), 0, "test"));
  FVV_RETURN_IF_ERROR(ValidateFileHeader(h));
  FragmentData out;
  return ReadFragment(b, box.data() + b.header_size, h, FragmentReadOptions(), &out);
}

TEST(PredictiveStream, BadPayloadsAndHeadersAreRefused) {
  auto s = MakeSampleStreamBytes(Options(false));
  ASSERT_TRUE(s.ok());
  EXPECT_TRUE(ReadEdited(*s, [](FragmentData*, FileHeader*) {}).ok());
  // 'ptex' in a stream whose header does not declare the tool, and 'texr'
  // where it does.
  EXPECT_EQ(ReadEdited(*s,
                       [](FragmentData*, FileHeader* h) {
                         h->tools &= ~kToolPredictiveTexture;
                         h->tools |= kToolSpihtArith;
                       })
                .code(),
            StatusCode::kCorrupt);
  EXPECT_EQ(ReadEdited(*s, [](FragmentData* f, FileHeader*) { f->predictive = false; }).code(),
            StatusCode::kCorrupt);
  // A kernel the header does not declare; an unknown kernel (Corrupt, as in texr).
  EXPECT_EQ(
      ReadEdited(*s, [](FragmentData* f,
                        FileHeader*) { f->predictive_texture.kernel = WaveletKernel::kCdf97; })
          .code(),
      StatusCode::kCorrupt);
  EXPECT_EQ(ReadEdited(*s,
                       [](FragmentData* f, FileHeader*) {
                         f->predictive_texture.kernel = static_cast<WaveletKernel>(7);
                       })
                .code(),
            StatusCode::kCorrupt);
  // Stream counts that do not follow the fragment's shape: the sizes then
  // disagree with the bytes that follow.
  EXPECT_EQ(ReadEdited(*s, [](FragmentData* f, FileHeader*) { f->predictive_texture.r.pop_back(); })
                .code(),
            StatusCode::kCorrupt);
  // The tool in a version 1 header, and without masks.
  EXPECT_EQ(ReadEdited(*s, [](FragmentData*, FileHeader* h) { h->format_version = 1; }).code(),
            StatusCode::kCorrupt);
  EXPECT_EQ(ReadEdited(*s, [](FragmentData*, FileHeader* h) { h->tools &= ~kToolMasks; }).code(),
            StatusCode::kCorrupt);
}

}  // namespace
}  // namespace fvv
