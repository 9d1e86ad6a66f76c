// The texture in chunks (SPEC.md 3.5.1): a chunked fragment read from any
// prefix past its head holds, per channel, the prefix of the stream its whole
// chunks carry; every delivered chunk is verified and nothing after the
// prefix is looked at; the samples are those of 'texr' at the same bytes.
#include <gtest/gtest.h>

#include <vector>

#include "codec/block_codec.h"
#include "conformance/sample/sample_stream.h"
#include "container/box.h"
#include "container/crc32c.h"
#include "container/file_reader.h"
#include "container/fragment.h"
#include "container/writer.h"

namespace fvv {
namespace {

SampleStreamOptions ChunkedOptions(bool chunks) {
  SampleStreamOptions o;
  o.frames = 4;
  o.cameras = 2;
  o.atlas_width = 64;
  o.atlas_height = 48;
  o.gop_frames = 4;
  o.gop_cameras = 1;
  o.coder = EntropyCoder::kQuadtree;
  o.bpp = 3.0;
  o.texture_chunks = chunks;
  return o;
}

struct Chunked {
  SampleStream sample;
  std::vector<uint8_t> bytes;
  std::unique_ptr<MemorySource> source;
  std::unique_ptr<FileReader> reader;
};

Chunked Open(bool chunks) {
  Chunked c;
  auto s = MakeSampleStream(ChunkedOptions(chunks));
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  c.sample = std::move(s).value();
  c.bytes = *WriteStreamToMemory(c.sample.info, c.sample.fragments);
  c.source = std::make_unique<MemorySource>(c.bytes.data(), c.bytes.size());
  auto r = FileReader::Open(c.source.get());
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  c.reader = std::move(r).value();
  return c;
}

TEST(TextureChunks, AWholeFragmentReadsBackItsStreamsAndTheIndexKnowsItsHead) {
  const Chunked c = Open(true);
  EXPECT_EQ(c.reader->info().header.format_version, 11);
  for (size_t i = 0; i < c.reader->fragment_count(); ++i) {
    auto f = c.reader->ReadFragment(i);
    ASSERT_TRUE(f.ok()) << f.status().ToString();
    EXPECT_TRUE(f->chunked);
    const EncodedBlock& written = c.sample.fragments[i].texture;
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_EQ(f->texture.channels[ch].data, written.channels[ch].data) << "channel " << ch;
      EXPECT_EQ(f->texture.channels[ch].planes, written.channels[ch].planes);
    }
    // Several chunks per fragment, each channel's passes interleaved.
    EXPECT_GT(f->chunks.size(), 6u);
    const IndexEntry& e = c.reader->info().index[i];
    EXPECT_EQ(e.head_size, f->head_bytes);
    EXPECT_LT(e.head_size, e.size);
  }
}

TEST(TextureChunks, EveryPrefixHoldsTheStreamsOfItsWholeChunks) {
  const Chunked c = Open(true);
  const IndexEntry& e = c.reader->info().index[1];
  auto whole = c.reader->ReadFragment(1);
  ASSERT_TRUE(whole.ok());
  // Below the head: Truncated, whatever the cut.
  for (uint64_t n : {uint64_t{1}, uint64_t{12}, uint64_t{e.head_size} - 1}) {
    auto f = c.reader->ReadFragment(1, n);
    ASSERT_FALSE(f.ok()) << n;
    EXPECT_EQ(f.status().code(), StatusCode::kTruncated) << n;
  }
  size_t last_total = 0;
  for (uint64_t n = e.head_size; n <= e.size; n += 37) {
    auto f = c.reader->ReadFragment(1, n);
    ASSERT_TRUE(f.ok()) << n << ": " << f.status().ToString();
    auto expected = ChunkedPrefixBytes(*whole, n);
    ASSERT_TRUE(expected.ok());
    size_t total = 0;
    for (int ch = 0; ch < 3; ++ch) {
      const std::vector<uint8_t>& got = f->texture.channels[ch].data;
      const std::vector<uint8_t>& all = whole->texture.channels[ch].data;
      ASSERT_EQ(got.size(), (*expected)[ch]) << n;
      EXPECT_TRUE(std::equal(got.begin(), got.end(), all.begin())) << n;
      total += got.size();
    }
    // What a prefix holds never shrinks as it grows, and it wastes at most a
    // chunk (and its 7 bytes) of the bytes past the head.
    EXPECT_GE(total, last_total);
    last_total = total;
    uint64_t largest = 0;
    for (const TextureChunk& k : whole->chunks) largest = std::max<uint64_t>(largest, k.size);
    EXPECT_GE(total + whole->chunks.size() * kChunkHeaderBytes + largest, n - e.head_size) << n;
  }
}

// A byte changed inside a chunk: a prefix that holds the chunk fails with
// ChecksumMismatch, a shorter one does not see it.
TEST(TextureChunks, ADamagedChunkFailsOnlyThePrefixesThatHoldIt) {
  Chunked c = Open(true);
  const IndexEntry& e = c.reader->info().index[0];
  auto whole = c.reader->ReadFragment(0);
  ASSERT_TRUE(whole.ok());
  // The end of the third chunk, and a byte inside it.
  uint64_t end = whole->head_bytes;
  for (int k = 0; k < 3; ++k) end += kChunkHeaderBytes + whole->chunks[k].size;
  c.bytes[e.offset + end - 2] ^= 0x04;
  MemorySource damaged(c.bytes.data(), c.bytes.size());
  auto reader = FileReader::Open(&damaged);
  ASSERT_TRUE(reader.ok());
  auto before = (*reader)->ReadFragment(0, end - 1);
  ASSERT_TRUE(before.ok()) << before.status().ToString();
  EXPECT_EQ(before->chunks.size(), 2u);
  auto holding = (*reader)->ReadFragment(0, end);
  ASSERT_FALSE(holding.ok());
  EXPECT_EQ(holding.status().code(), StatusCode::kChecksumMismatch);
  auto all = (*reader)->ReadFragment(0);
  ASSERT_FALSE(all.ok());
  EXPECT_EQ(all.status().code(), StatusCode::kChecksumMismatch);
}

// The same samples as 'texr': the whole stream, and each prefix against
// 'texr' cut to the bytes of each channel that prefix holds.
TEST(TextureChunks, ChunksDecodeToTheSamplesOfTheSameBytesOfTexr) {
  const Chunked chunked = Open(true);
  const Chunked plain = Open(false);
  EXPECT_EQ(plain.reader->info().header.format_version, 8);
  auto a = chunked.reader->ReadFragment(1);
  auto b = plain.reader->ReadFragment(1);
  ASSERT_TRUE(a.ok() && b.ok());
  const IndexEntry& e = chunked.reader->info().index[1];
  const uint64_t head = e.head_size;
  for (uint64_t n : {uint64_t{0}, head, head + 300, head + 1500}) {
    auto bytes = ChunkedPrefixBytes(*a, n);
    ASSERT_TRUE(bytes.ok());
    DecodeBudget cut;
    cut.channel_max_bytes = *bytes;
    auto from_chunks = DecodeBlock(a->texture, cut, SerialRunner);
    auto from_texr = DecodeBlock(b->texture, cut, SerialRunner);
    ASSERT_TRUE(from_chunks.ok() && from_texr.ok());
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_EQ(from_chunks->channels[ch].samples, from_texr->channels[ch].samples) << n;
    }
  }
  // What chunks cost: 7 bytes a chunk, the head's 'txhd' and 'txck' header.
  EXPECT_LT(chunked.bytes.size(), plain.bytes.size() * 103 / 100);
}

// A stream cut inside a chunked fragment's head reads as Truncated; a 'texr'
// fragment shorter than its box is Truncated whatever the prefix.
TEST(TextureChunks, OnlyAChunkedFragmentDecodesFromAPrefix) {
  const Chunked plain = Open(false);
  const IndexEntry& e = plain.reader->info().index[0];
  auto f = plain.reader->ReadFragment(0, e.size - 1);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.status().code(), StatusCode::kTruncated);
  EXPECT_TRUE(plain.reader->ReadFragment(0, e.size).ok());
}

}  // namespace
}  // namespace fvv
