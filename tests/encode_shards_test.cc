// Encoding in shards: the GOP-aligned split of a take, the prepared take
// every shard reads, and the join, which must give byte for byte the stream of
// one encode of the take, and refuse parts that are missing, doubled, foreign
// or made with other settings, naming them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

#include "container/file_reader.h"
#include "container/stream_join.h"
#include "container/writer.h"
#include "encoder/encode/encoder.h"
#include "encoder/encode/prepared_take.h"
#include "encoder/track/joint_truth.h"
#include "encoder/track/track_capture.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

std::vector<char> Bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(f), {});
}

TEST(ShardFrames, WholeGopsCoverTheTakeInOrder) {
  for (uint32_t frames : {1u, 7u, 8u, 9u, 64u, 101u}) {
    for (uint32_t gop : {1u, 2u, 8u}) {
      const uint32_t spans = (frames + gop - 1) / gop;
      for (uint32_t n = 1; n <= spans + 1; ++n) {
        uint32_t next = 0;
        for (uint32_t k = 0; k < n; ++k) {
          StatusOr<ShardFrames> s = ShardFramesOf(frames, gop, k, n);
          if (n > spans) {
            // Some shard must be empty: the first such one is refused.
            if (!s.ok()) {
              EXPECT_EQ(s.status().code(), StatusCode::kInvalidArgument);
              EXPECT_NE(s.status().message().find("no GOP"), std::string::npos);
              next = frames;
              break;
            }
          } else {
            ASSERT_TRUE(s.ok()) << s.status().ToString();
          }
          EXPECT_EQ(s->first, next) << frames << " " << gop << " " << k << "/" << n;
          EXPECT_EQ(s->first % gop, 0u);
          EXPECT_GT(s->count, 0u);
          if (k + 1 < n) {
            EXPECT_EQ(s->count % gop, 0u);
          }
          // As even as whole spans allow.
          EXPECT_LE(s->count, (spans + n - 1) / n * gop);
          next += s->count;
        }
        EXPECT_EQ(next, frames) << frames << " " << gop << " " << n;
      }
    }
  }
  EXPECT_FALSE(ShardFramesOf(10, 2, 3, 3).ok());
  EXPECT_FALSE(ShardFramesOf(10, 2, 0, 0).ok());
}

// A small synthetic take: 7 frames in GOPs of 2 (the last span short), 3
// cameras in groups of 2 (two fragments per span).
class ShardTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/shard_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    SynthOptions o;
    o.output_dir = dir_ + "/cap";
    o.cameras = 3;
    o.frames = 7;
    o.held_out = 0;
    o.noise = 0;
    o.unlit = true;
    o.seed = 9;
    synth_ = RunSynth(o).status();
    if (!synth_.ok()) return;
    EncoderSettings s = Settings();
    s.prepare_frames = 3;
    StatusOr<PrepareSummary> p = PrepareTake(dir_ + "/cap", dir_ + "/prep", s);
    synth_ = p.status();
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override { ASSERT_TRUE(synth_.ok()) << synth_.ToString(); }

  static EncoderSettings Settings() {
    EncoderSettings s;
    s.poses = dir_ + "/cap";  // the generator's true poses: one pose source for every shard
    s.atlas_size = 128;
    s.gop_frames = 2;
    s.gop_cameras = 2;
    s.threads = 1;
    return s;
  }
  static EncoderSettings Shard(uint32_t k, uint32_t n) {
    EncoderSettings s = Settings();
    s.prepared = dir_ + "/prep";
    s.shard = k;
    s.shards = n;
    return s;
  }
  static std::string Encode(const EncoderSettings& s, const std::string& name) {
    const std::string out = dir_ + "/" + name;
    StatusOr<EncodeSummary> r = EncodeCapture(dir_ + "/cap", out, s);
    EXPECT_TRUE(r.ok()) << name << ": " << r.status().ToString();
    return out;
  }

  static std::string dir_;
  static Status synth_;
};
std::string ShardTest::dir_;
Status ShardTest::synth_;

TEST_F(ShardTest, JoinedShardsAreTheWholeTakeByteForByte) {
  StatusOr<PreparedTake> prep = LoadPreparedTake(dir_ + "/prep");
  ASSERT_TRUE(prep.ok()) << prep.status().ToString();
  EXPECT_EQ(prep->frames(), 7u);
  EXPECT_EQ(prep->texture_frames, (std::vector<uint32_t>{0, 3, 6}));

  EncoderSettings whole = Settings();
  whole.prepared = dir_ + "/prep";
  const std::string single = Encode(whole, "whole.fvv");
  std::vector<std::string> parts;
  for (uint32_t k = 0; k < 3; ++k) {
    parts.push_back(Encode(Shard(k, 3), "part_" + std::to_string(k) + ".fvv"));
  }
  // Each part is a stream of its own: its frames, whole GOPs, its own index.
  uint32_t frames = 0;
  for (const std::string& p : parts) {
    StatusOr<std::unique_ptr<FileSource>> src = FileSource::Open(p);
    ASSERT_TRUE(src.ok());
    StatusOr<std::unique_ptr<FileReader>> r = FileReader::Open(src->get());
    ASSERT_TRUE(r.ok()) << p << ": " << r.status().ToString();
    EXPECT_TRUE((*r)->index_in_stream());
    StatusOr<ShardPosition> pos = ReadShardPosition((*r)->info().metadata, p);
    ASSERT_TRUE(pos.ok()) << pos.status().ToString();
    EXPECT_EQ(pos->first, frames);
    frames += (*r)->info().header.frame_count;
    for (size_t i = 0; i < (*r)->fragment_count(); ++i) EXPECT_TRUE((*r)->ReadFragment(i).ok());
  }
  EXPECT_EQ(frames, 7u);

  // Any order in; the whole take's bytes out.
  StatusOr<JoinSummary> j = JoinShards({parts[2], parts[0], parts[1]}, dir_ + "/joined.fvv");
  ASSERT_TRUE(j.ok()) << j.status().ToString();
  EXPECT_EQ(j->parts, 3u);
  EXPECT_EQ(j->frames, 7u);
  EXPECT_EQ(j->fragments, 8u);  // 4 spans x 2 camera groups
  EXPECT_TRUE(j->motion_recoded);
  const std::vector<char> a = Bytes(single), b = Bytes(dir_ + "/joined.fvv");
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "the joined stream differs from one encode of the take";

  // Without the prepared take, each shard would build its own static texture
  // from its own frames: the prepared one is what makes them agree. The whole
  // take encoded without it differs from the one with it.
  const std::vector<char> unprepared = Bytes(Encode(Settings(), "unprepared.fvv"));
  EXPECT_FALSE(unprepared == a);
}

TEST_F(ShardTest, JoinNamesMissingDoubledForeignAndMismatchedParts) {
  std::vector<std::string> parts;
  for (uint32_t k = 0; k < 2; ++k) {
    parts.push_back(Encode(Shard(k, 2), "half_" + std::to_string(k) + ".fvv"));
  }
  const std::string out = dir_ + "/bad_join.fvv";
  auto Refused = [&](const std::vector<std::string>& in, const std::string& says) {
    StatusOr<JoinSummary> j = JoinShards(in, out);
    ASSERT_FALSE(j.ok()) << "joined " << in.size() << " parts; expected: " << says;
    EXPECT_NE(j.status().message().find(says), std::string::npos) << j.status().ToString();
    EXPECT_NE(access(out.c_str(), F_OK), 0) << "a refused join left an output";
  };
  Refused({parts[1]}, "part 0 of 2 is missing");
  Refused({parts[0], parts[0], parts[1]}, "are both part 0");
  Refused({parts[0], parts[1], parts[0]}, "are both part 0");
  // A part of another split of the same take.
  const std::string third = Encode(Shard(2, 3), "third_2.fvv");
  Refused({parts[0], third}, "a part of 3 shards");
  // A stream that is no shard.
  EncoderSettings whole = Settings();
  whole.prepared = dir_ + "/prep";
  Refused({parts[0], Encode(whole, "whole_for_join.fvv")}, "is not a shard");
  // A part coded with other tools (masks).
  EncoderSettings masks = Shard(1, 2);
  masks.masks = true;
  Refused({parts[0], Encode(masks, "half_1_masks.fvv")}, "coding tools differs");
  // Other metadata (another generator's note).
  EncoderSettings meta = Shard(1, 2);
  meta.metadata = {{"take", "another"}};
  Refused({parts[0], Encode(meta, "half_1_meta.fvv")}, "metadata differs");
  // The output may not be one of the inputs.
  StatusOr<JoinSummary> j = JoinShards(parts, parts[0]);
  ASSERT_FALSE(j.ok());
  EXPECT_NE(j.status().message().find("both a part and the output"), std::string::npos);
  // The two good halves still join.
  EXPECT_TRUE(JoinShards(parts, out).ok());
}

TEST_F(ShardTest, EncodeRefusesShardsWithoutTheirPreparedTake) {
  auto Refused = [&](const EncoderSettings& s, const std::string& says) {
    StatusOr<EncodeSummary> r = EncodeCapture(dir_ + "/cap", dir_ + "/refused.fvv", s);
    ASSERT_FALSE(r.ok()) << "expected: " << says;
    EXPECT_NE(r.status().message().find(says), std::string::npos) << r.status().ToString();
  };
  EncoderSettings s = Shard(0, 2);
  s.prepared.clear();
  Refused(s, "--shard needs --prepared");
  s = Shard(2, 2);
  Refused(s, "below N");
  s = Shard(0, 5);  // 4 time spans
  Refused(s, "no GOP");
  s = Shard(0, 2);
  s.gop_frames = 4;
  Refused(s, "prepared for GOPs of 2");
  s = Shard(0, 2);
  s.atlas_size = 64;
  Refused(s, "prepared for a 128 atlas");
  s = Shard(0, 2);
  s.key_interval = 2;
  Refused(s, "key interval 1");
  s = Shard(0, 2);
  s.first_frame = 2;
  Refused(s, "the prepared take sets the frames");
  // Poses other than the ones the take was prepared with.
  std::ifstream in(dir_ + "/cap/truth/truth.json");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text += " ";
  std::ofstream(dir_ + "/other_poses.json") << text;
  s = Shard(0, 2);
  s.poses = dir_ + "/other_poses.json";
  Refused(s, "not the poses file");
  // A directory that is not a prepared take.
  s = Shard(0, 2);
  s.prepared = dir_ + "/cap";
  Refused(s, "prepared.json");
  // A take prepared with poses is encoded with them, not tracked.
  s = Shard(0, 2);
  s.poses.clear();
  Refused(s, "needs --poses");
}

// Shards that track their own frames: the take's shared pass settles the
// actor's shape; each shard tracks its frames with warm-up frames on both
// sides, so that its poses near a border are those of one run over the
// whole take. 4 cameras at 320x240, 24 frames in GOPs of 4, 3 shards.
class TrackedShardTest : public ::testing::Test {
 protected:
  static constexpr uint32_t kFrames = 24, kShards = 3, kWarmUp = 8;
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/tracked_shard_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    SynthOptions o;
    o.output_dir = dir_ + "/cap";
    o.cameras = 4;
    o.width = 320;
    o.height = 240;
    o.frames = kFrames;
    o.held_out = 0;
    o.seed = 5;
    status_ = RunSynth(o).status();
    if (!status_.ok()) return;
    EncoderSettings s = Settings();
    s.prepare_frames = 3;
    s.track_warm_up = kWarmUp;
    StatusOr<PrepareSummary> p = PrepareTake(dir_ + "/cap", dir_ + "/prep", s);
    status_ = p.status();
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override { ASSERT_TRUE(status_.ok()) << status_.ToString(); }

  static EncoderSettings Settings() {
    EncoderSettings s;
    s.atlas_size = 128;
    s.gop_frames = 4;
    s.threads = 2;
    return s;
  }
  // The mean joint error against the truth per frame of `tracked`.
  static std::vector<double> Errors(const TrackCaptureResult& tracked) {
    StatusOr<JointErrors> e =
        CompareWithTruth(dir_ + "/cap", tracked.model.skeleton, tracked.Poses(), tracked.first);
    EXPECT_TRUE(e.ok()) << e.status().ToString();
    return e.ok() ? e->per_frame : std::vector<double>(tracked.fits.size(), 1.0);
  }

  static std::string dir_;
  static Status status_;
};
std::string TrackedShardTest::dir_;
Status TrackedShardTest::status_;

TEST_F(TrackedShardTest, ShardsTrackTheirFramesAsTheWholeTakeDoesAtTheBorders) {
  StatusOr<PreparedTake> prep = LoadPreparedTake(dir_ + "/prep");
  ASSERT_TRUE(prep.ok()) << prep.status().ToString();
  EXPECT_TRUE(prep->shards_track);
  EXPECT_EQ(prep->warm_up, kWarmUp);
  EXPECT_EQ(prep->poses_crc, 0u);
  EXPECT_FALSE(prep->texture_frames.empty());

  // One run over the whole take, as fvv track does it.
  TrackCaptureOptions whole;
  StatusOr<TrackCaptureResult> all = TrackCapture(dir_ + "/cap", whole);
  ASSERT_TRUE(all.ok()) << all.status().ToString();
  ASSERT_EQ(all->fits.size(), kFrames);
  // The prepared shape is the one the whole run settles on.
  for (int s = 0; s < kGenericSegmentCount; ++s) {
    EXPECT_NEAR(prep->shape.length[s], all->shape.length[s], 1e-9) << s;
    EXPECT_NEAR(prep->shape.girth[s], all->shape.girth[s], 1e-9) << s;
  }
  const std::vector<double> reference = Errors(*all);

  std::vector<double> sharded;
  for (uint32_t k = 0; k < kShards; ++k) {
    StatusOr<ShardFrames> part = ShardFramesOf(kFrames, 4, k, kShards);
    ASSERT_TRUE(part.ok());
    TrackCaptureOptions o;
    UsePreparedTracking(*prep, part->first, part->first + part->count - 1, &o);
    StatusOr<TrackCaptureResult> r = TrackCapture(dir_ + "/cap", o);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    // Only the shard's own frames are reported; the warm-up is counted.
    ASSERT_EQ(r->fits.size(), part->count);
    EXPECT_EQ(r->first, part->first);
    EXPECT_EQ(r->frames.front(), part->first);
    EXPECT_EQ(r->frames.back(), part->first + part->count - 1);
    const uint32_t before = std::min(kWarmUp, part->first);
    const uint32_t after = std::min(kWarmUp, kFrames - part->first - part->count);
    EXPECT_EQ(r->warm_up_frames, before + after);
    // The shape is the prepared one, never fitted again.
    EXPECT_EQ(r->shape.stature, prep->shape.stature);
    for (double e : Errors(*r)) sharded.push_back(e);
  }
  ASSERT_EQ(sharded.size(), reference.size());
  // Near each border (8 frames on each side), the error is the whole run's
  // within half a centimetre.
  for (uint32_t border : {8u, 16u}) {
    double mine = 0, theirs = 0;
    for (uint32_t f = border - 8; f < border + 8; ++f) mine += sharded[f], theirs += reference[f];
    std::string both;
    for (uint32_t f = border - 8; f < border + 8; ++f) {
      both += " " + std::to_string(f) + ": " + std::to_string(sharded[f]) + "/" +
              std::to_string(reference[f]);
    }
    EXPECT_LT((mine - theirs) / 16, 0.005)
        << "border before frame " << border << "; shard / whole run (m):" << both;
  }
}

TEST_F(TrackedShardTest, ShardsTrackAndJoin) {
  std::vector<std::string> parts;
  for (uint32_t k = 0; k < kShards; ++k) {
    EncoderSettings s = Settings();
    s.prepared = dir_ + "/prep";
    s.shard = k;
    s.shards = kShards;
    parts.push_back(dir_ + "/part_" + std::to_string(k) + ".fvv");
    StatusOr<EncodeSummary> r = EncodeCapture(dir_ + "/cap", parts.back(), s);
    ASSERT_TRUE(r.ok()) << r.status().ToString();
    EXPECT_NE(r->pose_source.find("tracked"), std::string::npos) << r->pose_source;
  }
  StatusOr<JoinSummary> j = JoinShards(parts, dir_ + "/joined.fvv");
  ASSERT_TRUE(j.ok()) << j.status().ToString();
  EXPECT_EQ(j->frames, kFrames);
  // The joined stream drops the parts' border poses with the other shard keys.
  {
    StatusOr<std::unique_ptr<FileSource>> src = FileSource::Open(dir_ + "/joined.fvv");
    ASSERT_TRUE(src.ok());
    StatusOr<std::unique_ptr<FileReader>> r = FileReader::Open(src->get());
    ASSERT_TRUE(r.ok());
    for (const auto& kv : (*r)->info().metadata) EXPECT_NE(kv.first, kShardPosesAfterKey);
  }

  // Part 0 as if its tracking had lost an arm in its warm-up frames: the
  // join names both parts and where they disagree; a malformed record too.
  StatusOr<std::unique_ptr<FileSource>> src = FileSource::Open(parts[0]);
  ASSERT_TRUE(src.ok());
  StatusOr<std::unique_ptr<FileReader>> part0 = FileReader::Open(src->get());
  ASSERT_TRUE(part0.ok());
  auto Rewritten = [&](const std::string& name, const std::string& value) {
    StreamInfo info = (*part0)->info();
    bool found = false;
    for (auto& kv : info.metadata) {
      if (kv.first == kShardPosesAfterKey) kv.second = value, found = true;
    }
    EXPECT_TRUE(found) << "part 0 carries no " << kShardPosesAfterKey;
    info.header.index_offset = 0;
    const std::string out = dir_ + "/" + name;
    StatusOr<std::unique_ptr<FileWriter>> w = FileWriter::Create(out, info);
    EXPECT_TRUE(w.ok());
    for (size_t i = 0; i < (*part0)->fragment_count(); ++i) {
      StatusOr<FragmentData> f = (*part0)->ReadFragment(i);
      EXPECT_TRUE(f.ok());
      EXPECT_TRUE((*w)->AddFragment(*f).ok());
    }
    EXPECT_TRUE((*w)->Close().ok());
    return out;
  };
  std::string value;
  for (const auto& kv : (*part0)->info().metadata) {
    if (kv.first == kShardPosesAfterKey) value = kv.second;
  }
  // The first frame's root.tx (its 4th value) 30 cm off: the whole body elsewhere.
  std::istringstream in(value.substr(0, value.find(';')));
  std::vector<std::string> fields{std::istream_iterator<std::string>(in), {}};
  ASSERT_GT(fields.size(), 12u);
  fields[4] = std::to_string(std::stod(fields[4]) + 0.3);
  std::string turned;
  for (const std::string& f : fields) turned += (turned.empty() ? "" : " ") + f;
  turned += value.substr(value.find(';'));
  const std::string bad = Rewritten("part_0_turned.fvv", turned);
  StatusOr<JoinSummary> refused = JoinShards({bad, parts[1], parts[2]}, dir_ + "/refused.fvv");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("disagree at their border"), std::string::npos)
      << refused.status().ToString();
  EXPECT_NE(refused.status().message().find(" cm apart"), std::string::npos)
      << refused.status().ToString();
  const std::string malformed = Rewritten("part_0_malformed.fvv", "8 1 2 3");
  refused = JoinShards({malformed, parts[1], parts[2]}, dir_ + "/refused.fvv");
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("malformed"), std::string::npos)
      << refused.status().ToString();

  // A shard encoded again going on from the part before it (where a join
  // found the two disagreeing): no first-frame search, and it joins.
  EncoderSettings again = Settings();
  again.prepared = dir_ + "/prep";
  again.shard = 2;
  again.shards = kShards;
  again.after = parts[1];
  const std::string rerun = dir_ + "/part_2_after.fvv";
  StatusOr<EncodeSummary> r2 = EncodeCapture(dir_ + "/cap", rerun, again);
  ASSERT_TRUE(r2.ok()) << r2.status().ToString();
  EXPECT_TRUE(JoinShards({parts[0], parts[1], rerun}, dir_ + "/joined_after.fvv").ok());
  // Only the part just before it will do.
  again.after = parts[0];
  r2 = EncodeCapture(dir_ + "/cap", dir_ + "/refused.fvv", again);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.status().message().find("is part 0 of 3"), std::string::npos)
      << r2.status().ToString();
  again.shard = 0;
  r2 = EncodeCapture(dir_ + "/cap", dir_ + "/refused.fvv", again);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.status().message().find("--after goes with --shard"), std::string::npos)
      << r2.status().ToString();

  // The take was prepared without poses: a poses file is refused.
  EncoderSettings s = Settings();
  s.prepared = dir_ + "/prep";
  s.poses = dir_ + "/cap";
  StatusOr<EncodeSummary> r = EncodeCapture(dir_ + "/cap", dir_ + "/refused.fvv", s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("leave out --poses"), std::string::npos)
      << r.status().ToString();
}

}  // namespace
}  // namespace fvv
