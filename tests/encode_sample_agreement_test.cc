// The cameras' agreement on a surface point's colour: a sample the others
// disagree with is dropped (encoder/encode/sample_agreement.h), so a person
// walking between a camera and the actor does not reach the atlas.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>

#include "encoder/encode/encoder.h"
#include "encoder/encode/sample_agreement.h"
#include "encoder/io/image_io.h"
#include "encoder/track/person_observer.h"
#include "tools/synth/synth.h"

namespace fvv {
namespace {

// Cameras x texels of RGB samples, all seen, each texel one colour.
struct Frame {
  Frame(uint32_t cameras, size_t texels) : n(cameras), t(texels) {
    rgb.assign(n * t * 3, 100);
    mask.assign(n * t, 1);
    for (size_t i = 0; i < t; ++i) list.push_back(uint32_t(i));
  }
  void Set(uint32_t c, size_t i, int r, int g, int b) {
    uint8_t* p = &rgb[(c * t + i) * 3];
    p[0] = uint8_t(r), p[1] = uint8_t(g), p[2] = uint8_t(b);
  }
  SampleAgreementCount Drop(const SampleAgreementOptions& o = {},
                            const uint8_t* suspects = nullptr) {
    return DropDisagreeingSamples(n, t, list.data(), list.size(), rgb.data(), mask.data(), o,
                                  suspects);
  }
  bool Seen(uint32_t c, size_t i) const { return mask[c * t + i] != 0; }
  uint32_t n;
  size_t t;
  std::vector<uint8_t> rgb, mask;
  std::vector<uint32_t> list;
};

// Only a suspect camera's samples are checked: kept where another camera
// backs them, dropped where none does or none other saw the texel; the other
// cameras' samples stay whatever they saw.
TEST(SampleAgreement, ChecksTheSuspectCamerasOnly) {
  Frame f(3, 4);
  const uint8_t suspects[3] = {0, 1, 0};
  // Texel 0: the suspect agrees with camera 0: kept.
  f.Set(1, 0, 104, 98, 100);
  // Texel 1: the suspect saw red, the others grey: dropped.
  f.Set(1, 1, 220, 30, 30);
  // Texel 2: cameras 0 and 2 disagree, the suspect agrees with camera 2:
  // nobody dropped (cameras 0 and 2 are not checked).
  f.Set(0, 2, 0, 0, 0), f.Set(2, 2, 200, 200, 200), f.Set(1, 2, 205, 195, 200);
  // Texel 3: the suspect alone saw it: dropped; camera 0 alone would be kept.
  f.mask[0 * f.t + 3] = f.mask[2 * f.t + 3] = 0;
  const SampleAgreementCount r = f.Drop({40, 2}, suspects);
  EXPECT_EQ(r.dropped, 2u);
  EXPECT_TRUE(f.Seen(1, 0));
  EXPECT_FALSE(f.Seen(1, 1));
  EXPECT_TRUE(f.Seen(0, 1) && f.Seen(2, 1));
  EXPECT_TRUE(f.Seen(0, 2) && f.Seen(1, 2) && f.Seen(2, 2));
  EXPECT_FALSE(f.Seen(1, 3));
  Frame g(3, 1);
  g.mask[1] = g.mask[2] = 0;  // camera 0 alone, not suspect
  EXPECT_EQ(g.Drop({40, 2}, suspects).dropped, 0u);
  EXPECT_TRUE(g.Seen(0, 0));
}

TEST(SampleAgreement, DropsTheSamplesNoOtherCameraBacks) {
  Frame f(5, 4);
  // Texel 0: four cameras within 20 levels of each other, camera 3 saw red.
  f.Set(0, 0, 90, 100, 110), f.Set(1, 0, 100, 95, 105), f.Set(2, 0, 108, 100, 100);
  f.Set(4, 0, 95, 104, 99), f.Set(3, 0, 220, 30, 30);
  // Texel 1: shading spreads the cameras over 30 levels a channel, but each
  // has a camera close to it: kept.
  f.Set(0, 1, 70, 70, 70), f.Set(1, 1, 100, 100, 100), f.Set(2, 1, 85, 85, 85);
  f.Set(3, 1, 95, 90, 92), f.Set(4, 1, 78, 80, 75);
  // Texel 2: only two cameras saw it, and they disagree: neither is kept.
  for (uint32_t c = 2; c < 5; ++c) f.mask[c * f.t + 2] = 0;
  f.Set(0, 2, 0, 0, 0), f.Set(1, 2, 255, 255, 255);
  // Texel 3: three cameras; the unseen samples of the others do not count.
  f.mask[0 * f.t + 3] = f.mask[1 * f.t + 3] = 0;
  f.Set(0, 3, 255, 0, 0), f.Set(1, 3, 255, 0, 0);
  f.Set(2, 3, 40, 40, 40), f.Set(3, 3, 44, 38, 41), f.Set(4, 3, 200, 200, 200);
  const SampleAgreementCount r = f.Drop();
  EXPECT_EQ(r.voted, 4u);
  EXPECT_EQ(r.dropped, 4u);
  EXPECT_FALSE(f.Seen(3, 0));
  for (uint32_t c : {0u, 1u, 2u, 4u}) EXPECT_TRUE(f.Seen(c, 0)) << c;
  for (uint32_t c = 0; c < 5; ++c) EXPECT_TRUE(f.Seen(c, 1)) << c;
  EXPECT_FALSE(f.Seen(0, 2) || f.Seen(1, 2));
  EXPECT_FALSE(f.Seen(4, 3));
  EXPECT_TRUE(f.Seen(2, 3) && f.Seen(3, 3));
}

TEST(SampleAgreement, TheLimitIsTheMeanOverTheChannels) {
  for (int step : {39, 41}) {
    Frame f(3, 1);
    f.Set(2, 0, 100 + step, 100 + step, 100 + step);
    SampleAgreementOptions o;
    o.max_difference = 40;
    EXPECT_EQ(f.Drop(o).dropped, step > 40 ? 1u : 0u) << step;
  }
  // A point one camera alone sees, or fewer than asked, is not checked.
  Frame one(1, 1);
  EXPECT_EQ(one.Drop().voted, 0u);
  Frame f(3, 1);
  f.Set(2, 0, 250, 250, 250);
  SampleAgreementOptions four;
  four.min_cameras = 4;
  EXPECT_EQ(f.Drop(four).voted, 0u);
}

// Calls `visit(seen, rgb)` for every texel of cameras cam00.. and frames 0..
// of the saved textures in `dirs`: per directory, whether the texel was seen (mask
// 255) and its colour.
template <typename Visit>
void ForEachTexel(const std::vector<std::string>& dirs, uint32_t cameras, uint32_t frames,
                  Visit visit) {
  const size_t n = dirs.size();
  std::vector<Image> tex(n), mask(n);
  std::vector<uint8_t> seen(n);
  std::vector<const uint8_t*> rgb(n);
  for (uint32_t c = 0; c < cameras; ++c) {
    char name[16];
    std::snprintf(name, sizeof(name), "cam%02u", c);
    for (uint32_t f = 0; f < frames; ++f) {
      for (size_t k = 0; k < n; ++k) {
        StatusOr<Image> t = ReadImage(TexturePath(dirs[k], name, f));
        StatusOr<Image> m = ReadImage(TextureMaskPath(dirs[k], name, f));
        ASSERT_TRUE(t.ok() && m.ok()) << dirs[k] << " " << name << " frame " << f;
        tex[k] = std::move(*t), mask[k] = std::move(*m);
      }
      for (size_t i = 0; i < mask[0].pixels.size(); ++i) {
        for (size_t k = 0; k < n; ++k) {
          seen[k] = mask[k].pixels[i] == 255;
          rgb[k] = &tex[k].pixels[i * 3];
        }
        visit(seen, rgb);
      }
    }
  }
}
// Sum of absolute differences over R, G and B.
int Difference(const uint8_t* a, const uint8_t* b) {
  return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
}

// A person walking between a camera and the actor. Two synthetic takes, the
// same but for a bystander who crosses behind the actor as camera 0 sees him,
// so in front of him for the cameras across the ring; both encoded with the
// true poses and silhouettes from background subtraction against the plates
// (the bystander is in them). Texels the take with the bystander keeps as
// seen whose colour differs from the take without him are his. The check
// removes most of them; what is left is where fewer than two cameras saw the
// point (docs/encoder.md has the figures).
class BystanderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/agreement_test_" + std::to_string(getpid());
    std::system(("rm -rf '" + dir_ + "'").c_str());
    for (bool bystander : {false, true}) {
      SynthOptions o;
      o.output_dir = dir_ + (bystander ? "/with" : "/without");
      o.cameras = 8;
      o.width = 320, o.height = 240;
      o.frames = 5;  // the bystander crosses the middle at frame 2
      o.held_out = 0;
      o.noise = 0;
      o.unlit = true;
      o.seed = 7;
      o.bystander = bystander;
      const Status made = RunSynth(o).status();
      if (!made.ok()) synth_ = made;
    }
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override { ASSERT_TRUE(synth_.ok()) << synth_.ToString(); }

  // Encodes `take` with the check's limit `limit` (0: off) and the hull of
  // what else stands there (`occluders`), its textures saved.
  static StatusOr<EncodeSummary> Encode(const std::string& take, double limit, bool occluders,
                                        const std::string& textures) {
    EncoderSettings s;
    s.poses = dir_ + "/" + take;
    s.atlas_size = 256;
    s.gop_frames = 5;
    s.last_frame = 4;
    s.agreement.max_difference = limit;
    s.occluders.enabled = occluders;
    s.save_textures = textures;
    return EncodeCapture(dir_ + "/" + take, textures + ".fvv", s);
  }

  struct Comparison {
    size_t compared = 0, bystander = 0;
  };
  // Texels both encodes kept as seen, and those of them differing by more
  // than 40 levels (mean over R, G, B): the bystander's.
  static Comparison Compare(const std::string& a, const std::string& b) {
    Comparison r;
    ForEachTexel({a, b}, 8, 5,
                 [&](const std::vector<uint8_t>& seen, const std::vector<const uint8_t*>& rgb) {
                   if (!seen[0] || !seen[1]) return;
                   ++r.compared;
                   r.bystander += Difference(rgb[0], rgb[1]) > 3 * 40;
                 });
    return r;
  }

  static std::string dir_;
  static Status synth_;
};
std::string BystanderTest::dir_;
Status BystanderTest::synth_;

TEST_F(BystanderTest, MostOfAPersonInFrontOfTheActorIsKeptOutOfTheAtlas) {
  const double limit = SampleAgreementOptions{}.max_difference;
  ASSERT_GT(limit, 0);
  for (const auto& [take, vote] : std::vector<std::pair<std::string, double>>{
           {"without", limit}, {"with", limit}, {"without", 0}, {"with", 0}}) {
    StatusOr<EncodeSummary> sum =
        Encode(take, vote, false, dir_ + "/tex_" + take + (vote > 0 ? "_vote" : "_all"));
    ASSERT_TRUE(sum.ok()) << sum.status().ToString();
    if (vote > 0 && take == "without") {
      // Where nothing stands in the way, the cameras mostly agree (at 320x240
      // they differ on the clothing's finest pattern).
      EXPECT_LT(sum->agreement_dropped, sum->agreement_texels * 15 / 100)
          << sum->agreement_dropped << " of " << sum->agreement_texels;
    }
  }
  const Comparison all = Compare(dir_ + "/tex_without_all", dir_ + "/tex_with_all");
  const Comparison voted = Compare(dir_ + "/tex_without_vote", dir_ + "/tex_with_vote");
  std::printf("  without the check: %zu of %zu texels the bystander's; with it: %zu of %zu\n",
              all.bystander, all.compared, voted.bystander, voted.compared);
  EXPECT_GT(all.bystander, 5000u);  // he does stand in the way
  EXPECT_LT(voted.bystander, all.bystander / 4);
  EXPECT_GT(voted.compared, all.compared * 90 / 100);  // the rest is kept
}

// The silhouettes from background subtraction hold the bystander; where they
// reach past the actor's model, the cameras that see him there carve his hull,
// and what it hides from a camera is not sampled. Checked against the take
// without him: none of his colours reach the atlas, and little of the actor
// is lost.
TEST_F(BystanderTest, WhatTheHullOfSomethingElseHidesNeverReachesTheAtlas) {
  for (const auto& [take, occluders] : std::vector<std::pair<std::string, bool>>{
           {"without", true}, {"with", true}, {"without", false}, {"with", false}}) {
    StatusOr<EncodeSummary> sum =
        Encode(take, 0, occluders, dir_ + "/tex_" + take + (occluders ? "_hull" : "_none"));
    ASSERT_TRUE(sum.ok()) << sum.status().ToString();
    if (occluders) {
      std::printf("  %s: something else found in %u of 5 frames, %llu samples left out\n",
                  take.c_str(), sum->occluder_frames, (unsigned long long)sum->occluded_samples);
    }
    if (occluders && take == "with") {
      EXPECT_GT(sum->occluded_samples, 1000u);
    }
    if (occluders && take == "without") {  // nobody else there: nothing left out
      EXPECT_EQ(sum->occluded_samples, 0u);
    }
  }
  // Unlit and without noise, the two takes' cameras see the actor alike
  // wherever the bystander does not hide him: a texel seen in both takes
  // without the hull is his where its colours differ at all (over 3 levels),
  // else the actor's.
  size_t hidden = 0, visible = 0, kept = 0, lost = 0;
  ForEachTexel({dir_ + "/tex_without_none", dir_ + "/tex_with_none", dir_ + "/tex_with_hull"}, 8, 5,
               [&](const std::vector<uint8_t>& seen, const std::vector<const uint8_t*>& rgb) {
                 if (!seen[0] || !seen[1]) return;
                 const bool his = Difference(rgb[0], rgb[1]) > 3 * 3;
                 hidden += his, visible += !his;
                 kept += his && seen[2] && Difference(rgb[0], rgb[2]) > 3 * 40;
                 lost += !his && !seen[2];
               });
  std::printf(
      "  texels the bystander hides: %zu, of them with his colour after the hull: %zu; "
      "the actor's texels: %zu, lost to the hull: %zu\n",
      hidden, kept, visible, lost);
  EXPECT_GT(hidden, 10000u);           // he does stand in the way
  EXPECT_LT(kept, hidden / 200);       // his colours do not reach the atlas
  EXPECT_LT(lost, visible * 6 / 100);  // and little of the actor is lost
}

// The person network's mask of the actor takes in someone passing close in
// front of one camera, and the other cameras' masks (the actor's alone) do not
// hold him: no hull can be carved of him. That camera's silhouette then holds
// far more than the actor's model explains, and in those frames its samples
// are kept only where another camera backs their colour. Two synthetic takes
// in real conditions (no plates, props, 4 portrait cameras), the same but for
// the bystander, with the true poses and the network's masks.
TEST(PersonMaskBystander, ACameraWhoseMaskTookInSomeoneElseIsCheckedAgainstTheOthers) {
  if (!PersonObserverAvailable() || !PersonObserver::Load(DefaultModelDirectory()).ok()) {
    GTEST_SKIP() << "person models unavailable (tools/setup.sh fetches them)";
  }
  const std::string dir =
      ::testing::TempDir() + "/person_mask_bystander_" + std::to_string(getpid());
  std::system(("rm -rf '" + dir + "'").c_str());
  for (bool bystander : {false, true}) {
    SynthOptions o;
    o.output_dir = dir + (bystander ? "/with" : "/without");
    o.plates = false, o.clutter = true, o.bystander = bystander;
    o.cameras = 4, o.width = 360, o.height = 640;
    o.frames = 8;
    o.held_out = 0;
    o.noise = 0;
    o.unlit = true;
    o.seed = 7;
    ASSERT_TRUE(RunSynth(o).ok());
  }
  const auto encode = [&](const std::string& take, double suspect_share) {
    EncoderSettings s;
    s.poses = dir + "/" + take;
    s.persons = TrackCaptureOptions::Persons::kOn;
    s.atlas_size = 256;
    s.occluders.suspect_share = suspect_share;
    s.save_textures = dir + "/tex_" + take + (suspect_share > 0 ? "_checked" : "_plain");
    return EncodeCapture(dir + "/" + take, s.save_textures + ".fvv", s);
  };
  for (const std::string take : {"without", "with"}) {
    StatusOr<EncodeSummary> plain = encode(take, 0);
    ASSERT_TRUE(plain.ok()) << plain.status().ToString();
    EXPECT_EQ(plain->suspect_camera_frames, 0u);
    StatusOr<EncodeSummary> checked = encode(take, OccluderOptions{}.suspect_share);
    ASSERT_TRUE(checked.ok()) << checked.status().ToString();
    std::printf("  %s him: %u suspect camera frames, %llu samples dropped\n", take.c_str(),
                checked->suspect_camera_frames, (unsigned long long)checked->suspect_dropped);
    if (take == "without") {
      EXPECT_EQ(checked->suspect_camera_frames, 0u) << "nobody else there, nobody suspect";
    } else {
      EXPECT_GT(checked->suspect_camera_frames, 0u);
    }
  }
  // Texels both takes kept as seen whose colours differ by over 40 levels:
  // his (the masks differ between the takes only where he is).
  const auto compare = [&](const std::string& which) {
    size_t compared = 0, his = 0;
    ForEachTexel({dir + "/tex_without_" + which, dir + "/tex_with_" + which}, 4, 8,
                 [&](const std::vector<uint8_t>& seen, const std::vector<const uint8_t*>& rgb) {
                   if (!seen[0] || !seen[1]) return;
                   ++compared;
                   his += Difference(rgb[0], rgb[1]) > 3 * 40;
                 });
    return std::make_pair(compared, his);
  };
  const auto [plain_compared, plain_his] = compare("plain");
  const auto [checked_compared, checked_his] = compare("checked");
  std::printf("  his texels: %zu of %zu without the check, %zu of %zu with it\n", plain_his,
              plain_compared, checked_his, checked_compared);
  EXPECT_GT(plain_his, 5000u);  // he does reach the atlas through that mask
  EXPECT_LT(checked_his, plain_his / 5);
  EXPECT_GT(checked_compared, plain_compared * 85 / 100);  // the rest is kept
  std::system(("rm -rf '" + dir + "'").c_str());
}

}  // namespace
}  // namespace fvv
