// The encoder session: the state between frames of one `fvv encode` (the
// body model and atlas, the GOP being filled, the coded fragments, the running
// figures), shared by its parts: the session's frame loop and stream
// (encoder_session.cc), GOP coding (gop_coding.cc) and the texture directory
// of --save-textures / --textures (texture_directory.cc). Private to encode/.
#ifndef FVV_ENCODER_ENCODE_ENCODER_SESSION_H_
#define FVV_ENCODER_ENCODE_ENCODER_SESSION_H_

#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "codec/base/thread_pool.h"
#include "codec/colour.h"
#include "codec/fill.h"
#include "codec/mask.h"
#include "codec/predictive_texture.h"
#include "container/writer.h"
#include "encoder/atlas/atlas.h"
#include "encoder/body/body_shape_json.h"
#include "encoder/body/kinematics.h"
#include "encoder/encode/encoder.h"
#include "encoder/encode/ordered_queue.h"
#include "encoder/encode/pose_file.h"
#include "encoder/encode/prepared_take.h"
#include "encoder/encode/seamless_texture.h"
#include "encoder/encode/temporal_fill.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/features.h"
#include "encoder/track/track_capture.h"

namespace fvv {
namespace encoding {

using Clock = std::chrono::steady_clock;
inline double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A camera name as a directory name: itself when it is plain, else by index.
inline std::string CameraDirName(const std::string& name, uint32_t index) {
  bool plain = !name.empty() && name != "." && name != "..";
  for (char ch : name) {
    plain = plain &&
            (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.');
  }
  char buf[32];
  std::snprintf(buf, sizeof(buf), "camera_%02u", index);
  return plain ? name : buf;
}

inline std::string FrameFile(const std::string& dir, const std::string& camera, const char* kind,
                             uint32_t frame) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "/%s_%06u.png", kind, frame);
  return dir + "/" + camera + buf;
}

// The settings' own consistency (ranges, combinations), before any file is read.
Status CheckSettings(const EncoderSettings& s);

// The capture frames an encode covers: the settings' range clamped to the
// capture and to the poses given (may be null); InvalidArgument when none is left.
struct FrameSpan {
  uint32_t first = 0, last = 0;
};
StatusOr<FrameSpan> FramesToEncode(const Capture& cap, const EncoderSettings& s,
                                   const PoseSequence* given);

// The frames textures are resampled from, with silhouettes as tracking takes
// them: the capture's, the person network's masks of the actor (where the
// capture has neither silhouettes nor plates, EncoderSettings::persons), or
// background subtraction. `note`: why the network is not used, if it says so.
struct TextureFrames {
  std::unique_ptr<PersonObserver> persons;  // outlives `frames`, which reads with it
  std::unique_ptr<CaptureFrames> frames;
};
StatusOr<TextureFrames> OpenTextureFrames(const Capture& cap, const EncoderSettings& s,
                                          ThreadPool* pool, std::string* note);

// Feature points for shape refinement's features term (none without a file):
// per frame, the points two or more cameras saw, triangulated.
class TakeFeatures {
 public:
  static StatusOr<TakeFeatures> Load(const Capture& cap, const std::string& path);
  std::map<std::string, Eigen::Vector3d> Of(uint32_t frame) const;

 private:
  std::vector<Camera> cameras_;
  FeatureSet features_;
};

// Where the encoder is, between frames.
class Session {
 public:
  Session(const Capture& capture, const std::string& output, const EncoderSettings& s,
          uint32_t first, uint32_t last)
      : cap_(capture), s_(s), pool_(std::max(1u, s.threads)), first_(first), last_(last) {
    sum_.output = output;
    sum_.first_frame = first;
    sum_.frames = last - first + 1;
    sum_.cameras = uint32_t(capture.cameras.size());
    sum_.atlas_size = s.atlas_size;
    sum_.fps = capture.frame_rate;
    sum_.atlas_texels = uint64_t(sum_.frames) * sum_.cameras * s.atlas_size * s.atlas_size;
    for (uint32_t c = 0; c < sum_.cameras; ++c) {
      cameras_.push_back(capture.cameras[c].calibration);
      camera_dirs_.push_back(CameraDirName(cameras_.back().name, c));
    }
    // Rotation and translation steps of the motion track: poses are quantised
    // before resampling, so textures fit the pose the player will draw.
    motion_.coder = s.motion_coder;
    motion_.key_interval = s.key_interval;
  }

  ThreadPool& pool() { return pool_; }
  EncodeSummary& summary() { return sum_; }
  const std::vector<std::string>& camera_dirs() const { return camera_dirs_; }

  bool HasShape() const { return !model_.mesh.positions.empty(); }
  // The silhouettes frames come with are the person network's masks: the
  // resampling's margin follows (SilhouetteMargin).
  void SetPersonMasks(bool person_masks) { person_masks_ = person_masks; }
  // The body model and atlas for the actor's shape (once); with
  // refine_shape, the model refined on `first` (its pose, images and
  // silhouettes) first.
  Status SetShape(const BodyShape& shape, const RefinementFrame* first);
  // Instead of SetShape: the prepared take's model and atlas, and its static
  // texture, held fixed (frames no longer add to it).
  Status UsePrepared(const PreparedTake& take);
  const BodyShape& shape() const { return shape_; }
  const BodyModel& model() const { return model_; }
  // The static texture so far (fallback_texture or static_texture), or null.
  const StaticTexture* static_texture() const { return static_.get(); }

  // --prepare: one frame resampled into the static texture, nothing coded.
  Status AddStaticFrame(uint32_t frame, const std::vector<double>& dofs,
                        const std::vector<Image>& images, const std::vector<Image>& silhouettes);

  // One frame: `images` and `silhouettes` per camera, or, with `textures`, the
  // atlas textures and masks themselves.
  Status AddFrame(uint32_t frame, const std::vector<double>& dofs, const std::vector<Image>& images,
                  const std::vector<Image>& silhouettes);

  // Metadata known only once the frames are in (written by Finish).
  void AddMetadata(std::string key, std::string value) {
    extra_metadata_.emplace_back(std::move(key), std::move(value));
  }
  Status Finish(const std::string& output);

 private:
  // The samples' fractional bits: whole samples for the predictive codec.
  int SampleFrac() const {
    return s_.texture_codec == TextureCodec::kSpiht4d
               ? UsableSampleFrac(s_.kernel, s_.frac_bits_97, s_.weights, s_.sample_frac)
               : 0;
  }
  // The stream's 4:2:0 rule (tool bit 18 with 4:2:0 SPIHT textures).
  ChromaUpsampling ChromaUpsamplingOf() const {
    return s_.chroma == ChromaFormat::k420 && s_.texture_codec == TextureCodec::kSpiht4d
               ? s_.chroma_upsampling
               : ChromaUpsampling::kNearest;
  }
  Status FillHeader(FileHeader* h) const;
  // The model on the grid the stream stores it on (EncoderSettings::quantise_model).
  Status StoreModelAsDecoded();
  // The atlas texel map and the span buffers, once the model is set.
  Status AllocateForModel();
  // The frame's pose quantised as the stream carries it, every camera
  // resampled into `slot`; the skinned vertex positions.
  StatusOr<std::vector<Eigen::Vector3f>> Resample(uint32_t frame, uint32_t slot,
                                                  const QuantisedPose& q,
                                                  const std::vector<Image>& images,
                                                  const std::vector<Image>& silhouettes,
                                                  bool track_surface);
  // With EncoderSettings::surface: the frame's surface tracked, quantised
  // into span_surface_[slot] and returned as the decoder will have it (the
  // model's mesh with the frame's bind-pose positions).
  StatusOr<const Mesh*> TrackSurface(uint32_t slot, const std::vector<Affine>& skin,
                                     const std::vector<Image>& images,
                                     const std::vector<Image>& silhouettes);

  // Codes the `frames` frames held for the current time span: one block per
  // camera group.
  // The frame's seamless texture joins the static one; the best-facing camera
  // of every texel is kept for the fallback.
  void AddToStaticTexture(uint32_t slot, const std::vector<Eigen::Vector3f>& positions);

  // Whether the span's unseen texels are filled (ApplyFallback). A texture
  // directory holds the textures as its encode coded them, fills included,
  // and a filled texel reads as seen there: filling again would take a
  // twin's colour from a filled texel, where its encode did not.
  bool AppliesFills() const { return s_.fallback_texture && s_.textures.empty(); }
  // Texels of the span's frames that no camera saw take the colour of the
  // nearest frames that saw them (temporal_fill_frames), else the static
  // texture's, in their best-facing camera.
  void ApplyFallback(uint32_t frames);
  // Then texels still unheld, far from what the cameras saw, from their twin
  // on the other side of the body (mirror_texels.h).
  void FillFromMirrors(uint32_t frames);

  // Without masks: texels a player may take from a camera that did not see
  // them take the mean colour of the cameras that did, so that the player's
  // blend there is the seeing cameras' (span_usable_ marks them), where that
  // camera can weigh least_blend_share of the blend; the rest go to the fill.
  void FillForPlayers(uint32_t frames);

  Status CodeSpan(uint32_t frames);

  // What one camera group's coding adds to the summary.
  struct GroupFigures {
    std::array<double, 3> sse{};
    std::array<uint64_t, 3> samples{};
    double sse_rgb = 0;
    uint64_t visible_texels = 0, texture_bytes = 0, mask_bytes = 0, surface_bytes = 0;
  };
  // Camera group `g` of the span: its fragment and figures. Reads the span
  // buffers only, so groups code side by side.
  Status CodeGroup(uint32_t g, uint32_t frames, uint32_t span_first, FragmentData* out,
                   GroupFigures* figures) const;

  // One GOP with the predictive scheme; the same rate targets as SPIHT's.
  Status CodePredictive(const Block& block, std::vector<uint8_t>& rgb, const UsedMask& used,
                        const Shape4D& shape, FragmentData* frag, GroupFigures* figures) const;

  // Y, U, V errors against the block coded; RGB errors against the texels as
  // resampled (what a player shows against what the cameras saw).
  void Measure(const Block& block, const Block& decoded, const UsedMask& seen,
               const std::vector<uint8_t>& a, GroupFigures* figures) const;

  uint32_t CameraGroups() const { return (sum_.cameras + s_.gop_cameras - 1) / s_.gop_cameras; }

  Status SaveTextures(uint32_t frame, uint32_t slot);

  Status ReadTextures(uint32_t frame, uint32_t slot);

  Status MakeTextureDirectories() const;

  // textures.json: what the textures are (atlas, cameras, frames) and the
  // poses and body shape they were resampled with, so `--textures` can encode
  // them again (it is also a valid poses file).
  Status WriteTexturesJson() const;

  const Capture& cap_;
  const EncoderSettings& s_;
  bool person_masks_ = false;
  mutable ThreadPool pool_;  // shared by the const coding of camera groups
  uint32_t first_, last_;
  EncodeSummary sum_;
  std::vector<Camera> cameras_;
  std::vector<std::string> camera_dirs_;
  MotionParams motion_;
  BodyShape shape_;
  BodyModel model_;
  TexelMap map_;
  std::vector<uint8_t> span_rgb_, span_mask_;  // (slot, camera, y, x)
  std::vector<uint8_t> span_usable_;           // without masks: what a player may use
  // Without masks, per slot: the posed surface (blend shares; empty for a
  // texture directory's frames).
  std::vector<std::vector<Eigen::Vector3f>> span_positions_, span_normals_;
  std::vector<int32_t> mirror_;                      // MirrorTexels, with mirror_fill
  std::unique_ptr<StaticTexture> static_;            // with fallback_texture or static_texture
  bool static_fixed_ = false;                        // a prepared take's: frames do not add to it
  std::vector<std::vector<int16_t>> span_fallback_;  // per slot: best-facing camera per texel
  std::vector<uint8_t> all_seen_;                    // texels x 1: "every camera" masks
  // With temporal_fill_frames: per slot, the seamless texture and its labels.
  std::vector<std::vector<uint8_t>> span_seamless_;
  std::vector<std::vector<int16_t>> span_labels_;
  std::vector<QuantisedPose> poses_;
  std::unique_ptr<SurfaceTracker> surface_tracker_;  // with EncoderSettings::surface
  Mesh surface_mesh_;                                // the model's, at a frame's surface
  std::vector<std::vector<int32_t>> span_surface_;   // per slot: SPEC.md 3.5.2's values
  std::vector<int32_t> surface_values_;              // the last frame's
  Metadata extra_metadata_;
  std::vector<std::vector<double>> raw_poses_;
  std::vector<FragmentData> fragments_;
  std::array<double, 3> sse_{};
  std::array<uint64_t, 3> samples_{};
  double sse_rgb_ = 0;
};

}  // namespace encoding
}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_ENCODER_SESSION_H_
