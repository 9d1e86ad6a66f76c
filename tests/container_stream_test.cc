// The container: every box type round-trips through the writer and both readers;
// incremental reading in any chunking; index placement; the errors a reader must
// report for bad streams.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "codec/mask.h"
#include "conformance/sample/sample_stream.h"
#include "container/box.h"
#include "container/crc32c.h"
#include "container/file_reader.h"
#include "container/stream_reader.h"
#include "container/writer.h"
#include "fuzz/decode_all.h"

namespace fvv {
namespace {

SampleStreamOptions Small() {
  SampleStreamOptions o;
  o.frames = 5;
  o.cameras = 3;
  o.atlas_width = 24;
  o.atlas_height = 16;
  o.gop_frames = 2;
  o.gop_cameras = 2;
  o.vertex_visibility = true;
  o.metadata = {{"title", "caf\xC3\xA9"}, {"licence", "CC0"}};
  return o;
}

TEST(Crc32c, KnownAnswer) {
  const char* s = "123456789";
  EXPECT_EQ(Crc32c(reinterpret_cast<const uint8_t*>(s), 9), 0xE3069283u);
  EXPECT_EQ(Crc32c(reinterpret_cast<const uint8_t*>(s) + 4, 5,
                   Crc32c(reinterpret_cast<const uint8_t*>(s), 4)),
            0xE3069283u);
}

TEST(Box, HeaderRoundTripAndSizeEscape) {
  const std::vector<uint8_t> payload(100, 7);
  const auto b = MakeBox(MakeFourCC("abcd"), 3, 0x123456, payload);
  auto h = ParseBoxHeader(b.data(), b.size(), 40, "test");
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->type, MakeFourCC("abcd"));
  EXPECT_EQ(h->size, 112u);
  EXPECT_EQ(h->version, 3);
  EXPECT_EQ(h->flags, 0x123456u);
  EXPECT_EQ(h->offset, 40u);
  // 64-bit form, as a reader must accept it
  ByteWriter w;
  w.U32(1);
  w.U32(MakeFourCC("wxyz"));
  w.U64(20 + 5);
  w.U32(0);
  auto h64 = ParseBoxHeader(w.bytes().data(), w.bytes().size(), 0, "test");
  ASSERT_TRUE(h64.ok());
  EXPECT_EQ(h64->header_size, 20u);
  EXPECT_EQ(h64->size, 25u);
  // too small, zero size, cut short
  ByteWriter bad;
  bad.U32(5);
  bad.U32(MakeFourCC("abcd"));
  bad.U32(0);
  EXPECT_EQ(ParseBoxHeader(bad.bytes().data(), 12, 0, "t").status().code(), StatusCode::kCorrupt);
  bad.PatchU32(0, 0);
  EXPECT_EQ(ParseBoxHeader(bad.bytes().data(), 12, 0, "t").status().code(), StatusCode::kCorrupt);
  EXPECT_EQ(ParseBoxHeader(b.data(), 7, 0, "t").status().code(), StatusCode::kTruncated);
}

void ExpectSameInfo(const StreamInfo& a, const StreamInfo& b) {
  EXPECT_EQ(a.header.frame_count, b.header.frame_count);
  EXPECT_EQ(a.header.camera_count, b.header.camera_count);
  EXPECT_EQ(a.header.tools, b.header.tools);
  EXPECT_EQ(a.header.atlas_width, b.header.atlas_width);
  EXPECT_EQ(a.header.gop_frames, b.header.gop_frames);
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    EXPECT_EQ(a.cameras[i].name, b.cameras[i].name);
    EXPECT_EQ(a.cameras[i].rotation, b.cameras[i].rotation);
    EXPECT_EQ(a.cameras[i].translation, b.cameras[i].translation);
    EXPECT_EQ(a.cameras[i].fx, b.cameras[i].fx);
  }
  ASSERT_EQ(a.model.skeleton.bones.size(), b.model.skeleton.bones.size());
  for (size_t i = 0; i < a.model.skeleton.bones.size(); ++i) {
    const Bone &x = a.model.skeleton.bones[i], &y = b.model.skeleton.bones[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.parent, y.parent);
    EXPECT_EQ(x.rest_translation, y.rest_translation);
    EXPECT_EQ(x.dof_mask, y.dof_mask);
    EXPECT_EQ(x.dof_min, y.dof_min);
  }
  EXPECT_EQ(a.model.mesh.positions, b.model.mesh.positions);
  EXPECT_EQ(a.model.mesh.normals, b.model.mesh.normals);
  EXPECT_EQ(a.model.mesh.uvs, b.model.mesh.uvs);
  EXPECT_EQ(a.model.mesh.joints, b.model.mesh.joints);
  EXPECT_EQ(a.model.mesh.weights, b.model.mesh.weights);
  EXPECT_EQ(a.model.mesh.segments, b.model.mesh.segments);
  EXPECT_EQ(a.model.mesh.triangles, b.model.mesh.triangles);
  EXPECT_EQ(a.motion.rotation_step, b.motion.rotation_step);
  EXPECT_EQ(a.motion.key_interval, b.motion.key_interval);
  EXPECT_EQ(a.motion.key_reference, b.motion.key_reference);
  EXPECT_EQ(a.motion.first_class, b.motion.first_class);
  EXPECT_EQ(a.motion.context_init, b.motion.context_init);
  EXPECT_EQ(a.metadata, b.metadata);
}

void ExpectSameFragment(const FragmentData& a, const FragmentData& b) {
  EXPECT_EQ(a.info.gop_index, b.info.gop_index);
  EXPECT_EQ(a.info.first_frame, b.info.first_frame);
  EXPECT_EQ(a.info.frame_count, b.info.frame_count);
  EXPECT_EQ(a.info.first_camera, b.info.first_camera);
  EXPECT_EQ(a.info.camera_count, b.info.camera_count);
  EXPECT_EQ(a.motion, b.motion);
  EXPECT_EQ(a.masks, b.masks);
  EXPECT_EQ(a.vertex_visibility, b.vertex_visibility);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(a.texture.channels[c].data, b.texture.channels[c].data);
    EXPECT_EQ(a.texture.channels[c].planes, b.texture.channels[c].planes);
    EXPECT_EQ(a.texture.channels[c].points.size(), b.texture.channels[c].points.size());
  }
  EXPECT_EQ(a.texture.params.kernel, b.texture.params.kernel);
}

class StreamRoundTrip : public ::testing::TestWithParam<bool> {};  // fast start or not

TEST_P(StreamRoundTrip, EveryBoxSurvivesBothReaders) {
  SampleStreamOptions o = Small();
  o.fast_start = GetParam();
  auto sample = MakeSampleStream(o);
  ASSERT_TRUE(sample.ok()) << sample.status().ToString();
  auto bytes = WriteStreamToMemory(sample->info, sample->fragments);
  ASSERT_TRUE(bytes.ok()) << bytes.status().ToString();
  StreamInfo expected = sample->info;
  expected.header.frame_count = o.frames;
  ASSERT_EQ(sample->fragments.size(), 3u * 2u);

  // Random access.
  MemorySource src(bytes->data(), bytes->size());
  auto reader = FileReader::Open(&src);
  ASSERT_TRUE(reader.ok()) << reader.status().ToString();
  ExpectSameInfo((*reader)->info(), expected);
  EXPECT_TRUE((*reader)->index_in_stream());
  EXPECT_EQ((*reader)->fast_start(), GetParam());
  ASSERT_EQ((*reader)->fragment_count(), sample->fragments.size());
  for (size_t i = sample->fragments.size(); i-- > 0;) {  // any order
    auto f = (*reader)->ReadFragment(i);
    ASSERT_TRUE(f.ok()) << f.status().ToString();
    ExpectSameFragment(*f, sample->fragments[i]);
  }
  EXPECT_EQ(*(*reader)->FindFragment(3, 2), 3u);  // span 1, camera group 1
  EXPECT_FALSE((*reader)->FindFragment(5, 0).ok());
  EXPECT_FALSE((*reader)->FindFragment(0, 3).ok());

  // Incremental, in chunks of several sizes.
  for (size_t chunk : {size_t{1}, size_t{7}, size_t{4096}, bytes->size()}) {
    StreamReader sr;
    size_t pos = 0, fragments = 0;
    std::vector<ReaderEvent> events;
    for (;;) {
      auto e = sr.Next();
      ASSERT_TRUE(e.ok()) << e.status().ToString();
      if (*e == ReaderEvent::kEnd) break;
      if (*e == ReaderEvent::kNeedMoreInput) {
        if (pos == bytes->size()) {
          sr.Finish();
        } else {
          const size_t n = std::min(chunk, bytes->size() - pos);
          sr.Push(bytes->data() + pos, n);
          pos += n;
        }
        continue;
      }
      events.push_back(*e);
      if (*e == ReaderEvent::kFragment)
        ExpectSameFragment(sr.fragment(), sample->fragments[fragments++]);
    }
    EXPECT_EQ(fragments, sample->fragments.size());
    ASSERT_GE(events.size(), 5u);
    EXPECT_EQ(events[0], ReaderEvent::kHeader);
    EXPECT_EQ(events[1], ReaderEvent::kCameras);
    EXPECT_EQ(events[2], ReaderEvent::kModel);
    EXPECT_EQ(events[3], ReaderEvent::kMotionParams);
    EXPECT_EQ(events[4], ReaderEvent::kMetadata);
    EXPECT_EQ(events.back(), GetParam() ? ReaderEvent::kFragment : ReaderEvent::kIndex);
    if (chunk == bytes->size()) ExpectSameInfo(sr.info(), expected);
  }
}

INSTANTIATE_TEST_SUITE_P(IndexPlacement, StreamRoundTrip, ::testing::Bool());

class DecodedPayloads : public ::testing::TestWithParam<MaskCoding> {};
INSTANTIATE_TEST_SUITE_P(MaskModes, DecodedPayloads,
                         ::testing::Values(MaskCoding::kContext, MaskCoding::kMixing));

TEST_P(DecodedPayloads, MatchTheSource) {
  SampleStreamOptions o = Small();
  o.mask_coding = GetParam();
  auto sample = MakeSampleStream(o);
  ASSERT_TRUE(sample.ok());
  // Mask mode 2 makes a version 2 stream; mode 1 keeps version 1.
  EXPECT_EQ(sample->info.header.format_version, GetParam() == MaskCoding::kMixing ? 2 : 1);
  auto bytes = WriteStreamToMemory(sample->info, sample->fragments);
  ASSERT_TRUE(bytes.ok());
  MemorySource src(bytes->data(), bytes->size());
  auto reader = FileReader::Open(&src);
  ASSERT_TRUE(reader.ok());
  const StreamInfo& info = (*reader)->info();
  for (size_t i = 0; i < (*reader)->fragment_count(); ++i) {
    auto f = (*reader)->ReadFragment(i);
    ASSERT_TRUE(f.ok());
    EXPECT_EQ(f->mask_mode, GetParam());
    const Shape4D shape = f->info.TextureShape(info.header);
    std::vector<uint8_t> masks(shape.count());
    ASSERT_TRUE(
        DecodeMasks(f->masks.data(), f->masks.size(), shape, f->mask_mode, masks.data()).ok());
    const size_t texels = size_t{shape.height()} * shape.width();
    for (uint32_t t = 0; t < shape.frames(); ++t)
      for (uint32_t c = 0; c < shape.cameras(); ++c)
        for (size_t k = 0; k < texels; ++k)
          ASSERT_EQ(masks[(size_t{t} * shape.cameras() + c) * texels + k],
                    sample->masks[(size_t{f->info.first_frame + t} * info.header.camera_count +
                                   f->info.first_camera + c) *
                                      texels +
                                  k]);
    if (f->info.first_camera == 0) {
      std::vector<DecodedFrame> frames;
      ASSERT_TRUE(DecodeMotion(MotionBoxHeader(*f), f->motion.data(), info.model.skeleton,
                               info.motion, f->info.frame_count, &frames)
                      .ok());
      for (uint32_t t = 0; t < f->info.frame_count; ++t) {
        EXPECT_EQ(frames[t].values, sample->poses[f->info.first_frame + t]);
      }
    }
  }
}

// Mask mode 2 exists from format version 2 on: in a version 1 stream the
// reader refuses it as unsupported, naming the mode and the version.
TEST(Stream, MaskMode2NeedsFormatVersion2) {
  SampleStreamOptions o = Small();
  o.mask_coding = MaskCoding::kMixing;
  auto sample = MakeSampleStream(o);
  ASSERT_TRUE(sample.ok());
  sample->info.header.format_version = 1;
  auto bytes = WriteStreamToMemory(sample->info, sample->fragments);
  ASSERT_TRUE(bytes.ok());
  MemorySource src(bytes->data(), bytes->size());
  auto reader = FileReader::Open(&src);
  ASSERT_TRUE(reader.ok());
  auto f = (*reader)->ReadFragment(0);
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(f.status().message().find("mask mode 2 needs format version 2"), std::string::npos)
      << f.status().ToString();
}

TEST(Stream, FileWriterRenamesOnlyOnSuccess) {
  const std::string path = ::testing::TempDir() + "/fvv_writer_test.fvv";
  std::remove(path.c_str());
  auto sample = MakeSampleStream(Small());
  ASSERT_TRUE(sample.ok());
  {
    auto w = FileWriter::Create(path, sample->info);
    ASSERT_TRUE(w.ok());
    ASSERT_TRUE((*w)->AddFragment(sample->fragments[0]).ok());
    // destroyed without Close(): nothing under the final name, no temp left
  }
  EXPECT_EQ(std::fopen(path.c_str(), "rb"), nullptr);
  {
    auto w = FileWriter::Create(path, sample->info);
    ASSERT_TRUE(w.ok());
    for (const auto& f : sample->fragments) ASSERT_TRUE((*w)->AddFragment(f).ok());
    // Out of order and too many fragments are refused.
    EXPECT_EQ((*w)->AddFragment(sample->fragments[0]).code(), StatusCode::kInvalidArgument);
    ASSERT_TRUE((*w)->Close().ok());
  }
  auto src = FileSource::Open(path);
  ASSERT_TRUE(src.ok());
  auto reader = FileReader::Open(src->get());
  ASSERT_TRUE(reader.ok()) << reader.status().ToString();
  EXPECT_EQ((*reader)->fragment_count(), sample->fragments.size());
  std::remove(path.c_str());
}

TEST(Stream, WriterRefusesWhatReadersWouldReject) {
  auto sample = MakeSampleStream(Small());
  ASSERT_TRUE(sample.ok());
  MemorySink sink;
  StreamInfo bad = sample->info;
  bad.header.atlas_width = 1024;  // beyond level 1
  EXPECT_EQ(StreamWriter::Create(bad, &sink).status().code(), StatusCode::kLimitExceeded);
  bad = sample->info;
  bad.cameras.pop_back();
  EXPECT_EQ(StreamWriter::Create(bad, &sink).status().code(), StatusCode::kInvalidArgument);
  bad = sample->info;
  bad.model.mesh.weights[0][0] = 1;
  EXPECT_FALSE(StreamWriter::Create(bad, &sink).ok());
  bad = sample->info;
  bad.metadata.push_back({"k", "\xFF\xFE"});
  EXPECT_EQ(StreamWriter::Create(bad, &sink).status().code(), StatusCode::kInvalidArgument);
}

// Rebuilds a stream with one top-level box replaced (or inserted).
std::vector<uint8_t> Splice(const std::vector<uint8_t>& s, size_t at, size_t remove,
                            const std::vector<uint8_t>& insert) {
  std::vector<uint8_t> out(s.begin(), s.begin() + at);
  out.insert(out.end(), insert.begin(), insert.end());
  out.insert(out.end(), s.begin() + at + remove, s.end());
  return out;
}

StatusCode DecodeCode(const std::vector<uint8_t>& s) {
  DecodeAllReport r;
  return DecodeAll(s.data(), s.size(), 0, &r).code();
}

TEST(Stream, BadStreamsGiveTheirPinnedStatus) {
  SampleStreamOptions o = Small();
  o.fast_start = false;  // index at the end: header boxes can be spliced freely
  auto good = MakeSampleStreamBytes(o);
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(DecodeCode(*good), StatusCode::kOk);
  auto header = ParseBoxHeader(good->data(), good->size(), 0, "t");
  ASSERT_TRUE(header.ok());
  const size_t after_header = static_cast<size_t>(header->size);

  // Unknown boxes (appended, so no offset moves): skipped when not essential,
  // fatal when essential.
  const auto junk = MakeBox(MakeFourCC("zzzz"), 0, 0, std::vector<uint8_t>(50, 1));
  EXPECT_EQ(DecodeCode(Splice(*good, good->size(), 0, junk)), StatusCode::kOk);
  const auto must = MakeBox(MakeFourCC("zzzz"), 0, kBoxFlagEssential, {1, 2});
  EXPECT_EQ(DecodeCode(Splice(*good, good->size(), 0, must)), StatusCode::kUnsupported);
  // Inserting a box moves every fragment: the index no longer matches.
  EXPECT_EQ(DecodeCode(Splice(*good, after_header, 0, junk)), StatusCode::kCorrupt);

  // Newer format version.
  auto newer = *good;
  newer[12] = kFormatVersion + 1;
  EXPECT_EQ(DecodeCode(newer), StatusCode::kUnsupported);
  // A version 1 stream read as version 2 is still valid (version 2 only adds).
  auto v2 = *good;
  v2[12] = 2;
  EXPECT_EQ(DecodeCode(v2), StatusCode::kOk);
  // Level beyond its limits: level 1 allows 8 cameras; claim 200 (the header is
  // checked before the camera box that disagrees).
  auto cams = *good;
  cams[12 + 20] = 200;
  EXPECT_EQ(DecodeCode(cams), StatusCode::kLimitExceeded);
  // Not an fvv stream at all.
  EXPECT_EQ(DecodeCode(std::vector<uint8_t>(64, 0x41)), StatusCode::kCorrupt);
  // Truncation anywhere past the header: Truncated.
  EXPECT_EQ(DecodeCode(std::vector<uint8_t>(good->begin(), good->end() - 1)),
            StatusCode::kTruncated);
  EXPECT_EQ(DecodeCode(std::vector<uint8_t>(good->begin(), good->begin() + after_header + 5)),
            StatusCode::kTruncated);
  // A box size that runs past its parent / is below the header size.
  auto badsize = *good;
  badsize[after_header] = 3;
  badsize[after_header + 1] = badsize[after_header + 2] = badsize[after_header + 3] = 0;
  EXPECT_EQ(DecodeCode(badsize), StatusCode::kCorrupt);

  // Checksum: flip a byte inside the last fragment's texture data.
  MemorySource src(good->data(), good->size());
  auto reader = FileReader::Open(&src);
  ASSERT_TRUE(reader.ok());
  const IndexEntry last = (*reader)->info().index.back();
  auto damaged = *good;
  damaged[last.offset + last.size - 30] ^= 0x10;
  EXPECT_EQ(DecodeCode(damaged), StatusCode::kChecksumMismatch);

  // Inconsistent index: an entry pointing at the wrong offset.
  auto bad_index = *good;
  const uint64_t index_offset = (*reader)->info().header.index_offset;
  ASSERT_GT(index_offset, 0u);
  bad_index[index_offset + 12 + 4 + 10] ^= 0x01;  // entry 0's offset
  EXPECT_EQ(DecodeCode(bad_index), StatusCode::kCorrupt);
  MemorySource bad_src(bad_index.data(), bad_index.size());
  auto bad_reader = FileReader::Open(&bad_src);
  if (bad_reader.ok()) {
    EXPECT_EQ((*bad_reader)->ReadFragment(0).status().code(), StatusCode::kCorrupt);
  }
}

TEST(Stream, StreamWithoutIndexIsScanned) {
  SampleStreamOptions o = Small();
  o.fast_start = false;
  auto good = MakeSampleStreamBytes(o);
  ASSERT_TRUE(good.ok());
  MemorySource src(good->data(), good->size());
  auto reader = FileReader::Open(&src);
  ASSERT_TRUE(reader.ok());
  const uint64_t index_offset = (*reader)->info().header.index_offset;
  // Drop the index box and clear index_offset: still readable by scanning.
  std::vector<uint8_t> no_index(good->begin(), good->begin() + index_offset);
  for (int i = 0; i < 8; ++i) no_index[kHeaderIndexOffsetPos + i] = 0;
  MemorySource src2(no_index.data(), no_index.size());
  auto scanned = FileReader::Open(&src2);
  ASSERT_TRUE(scanned.ok()) << scanned.status().ToString();
  EXPECT_FALSE((*scanned)->index_in_stream());
  ASSERT_EQ((*scanned)->fragment_count(), (*reader)->fragment_count());
  for (size_t i = 0; i < (*scanned)->fragment_count(); ++i) {
    EXPECT_TRUE((*scanned)->ReadFragment(i).ok());
  }
}

}  // namespace
}  // namespace fvv
