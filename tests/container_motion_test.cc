// Motion track: round trip within the declared quantisation, interpolation,
// both coders, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "conformance/sample/sample_stream.h"
#include "container/motion_track.h"

namespace fvv {
namespace {

BoxHeader PayloadHeader(size_t size) {
  BoxHeader h;
  h.type = box::kMotion;
  h.header_size = 12;
  h.size = size + 12;
  return h;
}

std::vector<std::vector<double>> Walk(const Skeleton& s, uint32_t first, uint32_t n) {
  std::vector<std::vector<double>> poses;
  for (uint32_t f = first; f < first + n; ++f) poses.push_back(SampleWalkPose(s, f));
  return poses;
}

class MotionRoundTrip : public ::testing::TestWithParam<MotionCoder> {};

TEST_P(MotionRoundTrip, ErrorWithinHalfAStepAtDefaultSteps) {
  const BodyModel model = MakeSampleBodyModel();
  const auto dofs = model.skeleton.Dofs();
  MotionParams p;
  p.coder = GetParam();
  // The defaults: <= 0.05 degree rotation steps, <= 0.5 mm translation.
  ASSERT_LE(p.rotation_step_degrees(), 0.05);
  ASSERT_LE(p.translation_step_um, 500u);
  for (uint32_t first : {0u, 8u, 40u}) {
    const auto truth = Walk(model.skeleton, first, 8);
    std::vector<QuantisedPose> q;
    for (const auto& v : truth) q.push_back(QuantisePose(dofs, p, v));
    auto payload = EncodeMotion(model.skeleton, p, q);
    ASSERT_TRUE(payload.ok()) << payload.status().ToString();
    std::vector<DecodedFrame> frames;
    ASSERT_TRUE(
        DecodeMotion(PayloadHeader(payload->size()), payload->data(), model.skeleton, p, 8, &frames)
            .ok());
    ASSERT_EQ(frames.size(), 8u);
    for (size_t f = 0; f < 8; ++f) {
      ASSERT_TRUE(frames[f].coded);
      EXPECT_EQ(frames[f].values, q[f]);
      const auto back = DequantisePose(dofs, p, frames[f].values);
      for (size_t d = 0; d < dofs.size(); ++d) {
        if (IsRotationDof(dofs[d].kind)) {
          EXPECT_LE(std::fabs(back[d] - truth[f][d]) * 180 / M_PI, 0.025 + 1e-9);
        } else {
          EXPECT_LE(std::fabs(back[d] - truth[f][d]), 0.00025 + 1e-9);
        }
      }
    }
  }
}

TEST_P(MotionRoundTrip, StaticDofsAndJumpsRoundTrip) {
  const BodyModel model = MakeSampleBodyModel();
  const size_t n = model.skeleton.Dofs().size();
  MotionParams p;
  p.coder = GetParam();
  std::mt19937 rng(7);
  std::vector<QuantisedPose> q(8, QuantisedPose(n, 0));
  for (size_t f = 0; f < 8; ++f) {
    for (size_t d = 0; d < n; ++d) {
      // Mix of constant DOFs, smooth ramps, extreme values and random jumps.
      q[f][d] = d % 4 == 0   ? 17
                : d % 4 == 1 ? int32_t(f * 1000) - 3000
                : d % 4 == 2 ? (f % 2 ? INT32_MAX : INT32_MIN)
                             : int32_t(rng());
    }
  }
  auto payload = EncodeMotion(model.skeleton, p, q);
  ASSERT_TRUE(payload.ok());
  std::vector<DecodedFrame> frames;
  ASSERT_TRUE(
      DecodeMotion(PayloadHeader(payload->size()), payload->data(), model.skeleton, p, 8, &frames)
          .ok());
  for (size_t f = 0; f < 8; ++f) EXPECT_EQ(frames[f].values, q[f]) << "frame " << f;
}

TEST_P(MotionRoundTrip, EveryPrefixAndByteFlipEndsDefined) {
  const BodyModel model = MakeSampleBodyModel();
  MotionParams p;
  p.coder = GetParam();
  std::vector<QuantisedPose> q;
  for (const auto& v : Walk(model.skeleton, 3, 8))
    q.push_back(QuantisePose(model.skeleton.Dofs(), p, v));
  auto payload = EncodeMotion(model.skeleton, p, q);
  ASSERT_TRUE(payload.ok());
  std::vector<DecodedFrame> frames;
  int failures = 0;
  for (size_t n = 0; n < payload->size(); ++n) {
    failures +=
        !DecodeMotion(PayloadHeader(n), payload->data(), model.skeleton, p, 8, &frames).ok();
  }
  EXPECT_GT(failures, 0);  // a cut stream must be noticed at least most of the time
  for (size_t i = 0; i < payload->size(); ++i) {
    auto bad = *payload;
    bad[i] ^= 0x5A;
    (void)DecodeMotion(PayloadHeader(bad.size()), bad.data(), model.skeleton, p, 8, &frames);
  }
}

INSTANTIATE_TEST_SUITE_P(Coders, MotionRoundTrip,
                         ::testing::Values(MotionCoder::kArith, MotionCoder::kZstd));

TEST(Motion, InterpolationCodesKeyFramesExactlyAndSlerpsBetween) {
  const BodyModel model = MakeSampleBodyModel();
  const auto dofs = model.skeleton.Dofs();
  MotionParams p;
  p.key_interval = 3;
  std::vector<QuantisedPose> q;
  for (const auto& v : Walk(model.skeleton, 0, 8)) q.push_back(QuantisePose(dofs, p, v));
  auto payload = EncodeMotion(model.skeleton, p, q);
  ASSERT_TRUE(payload.ok());
  std::vector<DecodedFrame> frames;
  ASSERT_TRUE(
      DecodeMotion(PayloadHeader(payload->size()), payload->data(), model.skeleton, p, 8, &frames)
          .ok());
  const std::vector<uint32_t> coded = CodedFrameIndices(8, 3);
  EXPECT_EQ(coded, (std::vector<uint32_t>{0, 3, 6, 7}));
  for (uint32_t f = 0; f < 8; ++f) {
    const bool is_coded = std::find(coded.begin(), coded.end(), f) != coded.end();
    EXPECT_EQ(frames[f].coded, is_coded);
    const auto truth = BoneMotionsFromPose(model.skeleton, p, q[f]);
    for (size_t b = 0; b < truth.size(); ++b) {
      // Angle between decoded and true rotation: exact on key frames, within a
      // few degrees between them (the knees swing ~25 degrees per frame pair).
      int64_t dot = 0;
      for (int k = 0; k < 4; ++k)
        dot += int64_t(truth[b].rotation.c[k]) * frames[f].bones[b].rotation.c[k];
      const double cosine = std::min(1.0, std::fabs(dot / double(kQ30One) / double(kQ30One)));
      const double degrees = 2 * std::acos(cosine) * 180 / M_PI;
      if (is_coded) {
        EXPECT_EQ(frames[f].bones[b].rotation, truth[b].rotation);
      } else {
        EXPECT_LT(degrees, 6.0) << "bone " << b << " frame " << f;
      }
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(double(frames[f].bones[b].translation_um[a]),
                    double(truth[b].translation_um[a]), is_coded ? 0 : 30000);
      }
    }
  }
}

TEST(Motion, TrainedStatisticsRoundTripAndSaveBits) {
  const BodyModel model = MakeSampleBodyModel();
  const auto dofs = model.skeleton.Dofs();
  for (MotionCoder coder : {MotionCoder::kArith, MotionCoder::kZstd}) {
    MotionParams plain;
    plain.coder = coder;
    std::vector<QuantisedPose> q;
    for (const auto& v : Walk(model.skeleton, 0, 64)) q.push_back(QuantisePose(dofs, plain, v));
    MotionParams trained = plain;
    TrainMotionParams(model.skeleton, q, 8, &trained);
    ASSERT_EQ(trained.key_reference.size(), dofs.size());
    ASSERT_TRUE(ValidateMotionParams(trained).ok());
    // Through the box and back.
    const auto box = WriteMotionParamsBox(trained);
    auto h = ParseBoxHeader(box.data(), box.size(), 0, "test");
    ASSERT_TRUE(h.ok());
    MotionParams read;
    ASSERT_TRUE(ReadMotionParams(*h, box.data() + h->header_size, &read).ok());
    EXPECT_EQ(read.key_reference, trained.key_reference);
    EXPECT_EQ(read.context_init, trained.context_init);
    size_t plain_bytes = 0, trained_bytes = 0;
    for (size_t f0 = 0; f0 < q.size(); f0 += 8) {
      const std::vector<QuantisedPose> gop(q.begin() + f0, q.begin() + f0 + 8);
      auto a = EncodeMotion(model.skeleton, plain, gop);
      auto b = EncodeMotion(model.skeleton, read, gop);
      ASSERT_TRUE(a.ok());
      ASSERT_TRUE(b.ok());
      plain_bytes += a->size();
      trained_bytes += b->size();
      std::vector<DecodedFrame> frames;
      ASSERT_TRUE(
          DecodeMotion(PayloadHeader(b->size()), b->data(), model.skeleton, read, 8, &frames).ok());
      for (size_t f = 0; f < 8; ++f) EXPECT_EQ(frames[f].values, gop[f]);
      // Decoding with other statistics than the encoder's gives other values, not a crash.
      (void)DecodeMotion(PayloadHeader(b->size()), b->data(), model.skeleton, plain, 8, &frames);
    }
    if (coder == MotionCoder::kArith) {
      EXPECT_LT(trained_bytes, plain_bytes);
    }
  }
}

TEST(Motion, RejectsBadParams) {
  MotionParams p;
  p.rotation_step = 0;
  EXPECT_FALSE(ValidateMotionParams(p).ok());
  p = MotionParams();
  p.key_interval = 0;
  EXPECT_FALSE(ValidateMotionParams(p).ok());
  p = MotionParams();
  p.coder = static_cast<MotionCoder>(9);
  EXPECT_EQ(ValidateMotionParams(p).code(), StatusCode::kUnsupported);
  p = MotionParams();
  p.key_reference = {1, 2};
  p.first_class = {3};  // lengths differ
  EXPECT_EQ(ValidateMotionParams(p).code(), StatusCode::kCorrupt);
  p.first_class = {3, 12};  // class out of range
  EXPECT_EQ(ValidateMotionParams(p).code(), StatusCode::kCorrupt);
  p.first_class = {3, 4};
  p.context_init = {{5, 64 + 128}, {5, 64 + 256}};  // indices not increasing
  EXPECT_EQ(ValidateMotionParams(p).code(), StatusCode::kCorrupt);
  p.context_init = {{60000, 64 + 128}};  // no such context
  EXPECT_EQ(ValidateMotionParams(p).code(), StatusCode::kCorrupt);
  p.context_init = {{5, 64 + 128}};
  EXPECT_TRUE(ValidateMotionParams(p).ok());
  // Statistics for another skeleton: refused by the encoder and the decoder.
  const BodyModel model = MakeSampleBodyModel();
  std::vector<QuantisedPose> q(2, QuantisedPose(model.skeleton.Dofs().size(), 0));
  EXPECT_EQ(EncodeMotion(model.skeleton, p, q).status().code(), StatusCode::kInvalidArgument);
  std::vector<DecodedFrame> frames;
  const uint8_t payload[4] = {0, 0, 0, 0};
  EXPECT_EQ(DecodeMotion(PayloadHeader(4), payload, model.skeleton, p, 2, &frames).code(),
            StatusCode::kCorrupt);
}

}  // namespace
}  // namespace fvv
