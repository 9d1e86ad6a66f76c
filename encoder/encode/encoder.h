// The encoder: a capture directory in, a .fvv out. The capture front
// end (silhouettes and marker-free motion capture, or poses given), the body
// model with its texture atlas, multi-view resampling of every camera into the
// atlas, 4D-SPIHT texture coding of GOP blocks (frames x cameras), lossless
// shape masks, the motion track, and the container writer.
//
// Frames are read once: each frame is tracked, resampled into the atlas and
// held until its GOP time span is complete, then the span's blocks are coded
// (the pool's threads share each block's wavelet and SPIHT work). Memory is one
// time span of atlas textures plus the coded output, which is written at the
// end (the motion track's statistics need the whole take; the index goes at the
// front).
#ifndef FVV_ENCODER_ENCODE_ENCODER_H_
#define FVV_ENCODER_ENCODE_ENCODER_H_

#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include "codec/base/status.h"
#include "codec/block_codec.h"
#include "codec/mask.h"
#include "container/index_box.h"
#include "container/motion_track.h"
#include "encoder/encode/occluders.h"
#include "encoder/encode/resample.h"
#include "encoder/encode/sample_agreement.h"
#include "encoder/shape/shape_refinement.h"
#include "encoder/shape/surface_tracking.h"
#include "encoder/track/camera_choice.h"
#include "encoder/track/track_capture.h"
#include "encoder/track/tracker.h"

namespace fvv {

enum class TextureCodec : uint8_t { kSpiht4d, kPredictive };

struct EncoderSettings {
  // Input. With neither, the tracker runs on the capture.
  std::string poses;     // poses.json (fvv track) or truth.json: no tracking
  std::string textures;  // a --save-textures directory: no tracking, no resampling
  uint32_t first_frame = 0, last_frame = UINT32_MAX;  // clamped to the capture
  bool extract_silhouettes = false;  // background subtraction even if silhouettes are given
  TrackerOptions tracker;
  // Silhouettes from the person network, for tracking and for the textures
  // alike (TrackCaptureOptions::persons): auto where the capture has neither
  // silhouettes nor plates and the models load.
  TrackCaptureOptions::Persons persons = TrackCaptureOptions::Persons::kAuto;
  std::string person_models;  // empty: DefaultModelDirectory()
  // The cameras the tracker fits with (encoder/track/camera_choice.h): a
  // count, kTrackingCamerasAuto or kTrackingCamerasAll. Every camera is
  // resampled for texture whichever the fit read.
  uint32_t track_cameras = kTrackingCamerasAuto;
  // Tracked poses only (given poses are used as they are): smoothing over time
  // before resampling (encoder/track/pose_smoothing.h).
  PoseSmoothing pose_smoothing = TrackCaptureOptions{}.smoothing;
  ResampleOptions resample;
  // A camera's sample that no other camera seeing the point backs is dropped
  // (encoder/encode/sample_agreement.h): what stood in front of the actor.
  // Off by default (max_difference 0: every sample kept): at low resolution
  // the cameras also disagree on fine clothing patterns (docs/encoder.md).
  SampleAgreementOptions agreement = {0, 2};
  // What else stands in the cameras' silhouettes (encoder/encode/occluders.h):
  // a surface point behind it is not sampled. The clearance it must stand in
  // front by is resample.occluder_clearance.
  OccluderOptions occluders;
  // Refine the body model's shape to the actor on the first encoded frame
  // (silhouettes, stereo) before resampling: the stream's model is
  // then the refined mesh (same topology, skinning and atlas).
  bool refine_shape = false;
  ShapeRefinementOptions refinement;
  std::string features;  // feature points (features.json) for the refinement's features term
  // Seamless texture: each frame's camera textures blended into one
  // (best camera per triangle, multi-resolution splines), averaged over the
  // frames into a static texture of the actor. With fallback_texture, texels
  // no camera of a frame sees take the static texture's colour, in the
  // best-facing camera's texture (its mask marks them), instead of the
  // codec's smooth fill. `static_texture`: also write it as an image.
  bool fallback_texture = true;
  // Before the static texture: a texel no camera saw in a frame takes the
  // mean colour of the frames of its time span, at most this many frames
  // away, that saw it (encoder/encode/temporal_fill.h; 0: off).
  uint32_t temporal_fill_frames = 15;
  // After the static texture: a texel no camera has seen in any frame so far,
  // deep inside what the cameras missed, takes the colour of its mirror on the
  // other side of the body where a camera saw that in the frame
  // (encoder/encode/mirror_texels.h).
  bool mirror_fill = true;
  std::string static_texture;

  // Format and rate.
  uint32_t atlas_size = 512;  // 16..4096
  // 8 frames x 1 camera: a transform across the cameras of a GOP codes worse
  // than each camera on its own at the same bytes (the cameras see different
  // parts of the body; docs/encoder.md, "Why one camera per GOP"), and single-camera fragments let
  // a player decode only the cameras it blends.
  uint16_t gop_frames = 8, gop_cameras = 1;  // gop_cameras 0: all the capture's cameras
  // kSpiht4d: 4D wavelet + 4D SPIHT per GOP block ('texr'). kPredictive: the
  // predictive multi-view scheme with shape-adaptive BISK ('ptex', format
  // version 2), which predicts across the GOP's cameras (give it several per
  // GOP), needs masks, and codes 4:4:4 only.
  TextureCodec texture_codec = TextureCodec::kSpiht4d;
  WaveletKernel kernel = WaveletKernel::kCdf97;
  // The 9/7's sample precision (fractional bits, SPEC.md 9.6): 5 writes format
  // version 3 (docs/encoder.md); 2 keeps a 9/7
  // SPIHT stream readable by version 1 and 2 decoders.
  int frac_bits_97 = kFracBits97;
  // kNeighbourContexts: what format version 4 decoders read; kArith: versions 1..3.
  EntropyCoder coder = EntropyCoder::kSetSignContexts;
  // kOwnBand (format version 6) weights coefficients by their own band's norm;
  // kAxisBands is what format versions 1 to 5 decoders read.
  BandWeights weights = BandWeights::kOwnBand;
  // Fractional bits of the decoded samples (format version 7, codec/block.h):
  // the atlas goes into the 9/7 with its YCbCr unrounded to 1/2^n, and comes out
  // so (docs/encoder.md, "Fractional samples"). 0 is what format versions 1
  // to 6 decoders read. The 5/3, Haar and predictive codecs take 0.
  int sample_frac = kDefaultSampleFrac;
  ChromaFormat chroma = ChromaFormat::k444;
  // With 4:2:0, how a player returns chroma to full resolution (SPEC.md 9.7):
  // bilinear is format version 9 (about +0.3-0.5 dB RGB at 120:1 and 280:1 on
  // the demo atlas textures); nearest is what versions 1 to 8 decoders read.
  ChromaUpsampling chroma_upsampling = ChromaUpsampling::kBilinear;
  // Texels no camera saw: the codec's pyramid fill refined by sparse-fill
  // projections (codec/fill.h; docs/encoder.md, "Filling texels no camera
  // saw").
  FillOptions fill;
  // Rate-distortion pruning of isolated coefficients in the last coded bitplane
  // with a bits-per-texel or bytes target (EncodeSettings::prune_isolated),
  // for a second SPIHT encode and two decodes per GOP. Encoder-side only.
  bool prune_isolated = true;
  // kPsnr: weighted-YUV PSNR over visible texels per GOP; kBitsPerSample: bits
  // per atlas texel (all of them, seen or not); kTotalBytes: bytes per GOP.
  RateMode rate_mode = RateMode::kPsnr;
  double rate_value = 36;
  // Code the shape masks (which camera saw which texel). Without them, the
  // default, players take each camera's visibility from the decoded geometry
  // and the encoder fills what they may take (docs/encoder.md, "Streams without
  // masks"). The predictive texture codec needs them (they are its supports).
  bool masks = false;
  // Without masks: a texel a camera did not see but a player may take from it
  // is coded (with the colour of the cameras that saw it) only where that
  // camera can be at least this share of the reference player's blend from
  // some viewpoint (encoder/encode/blend_share.h); elsewhere it is left to the
  // coder's fill. 0 codes every such texel.
  double least_blend_share = 0.25;
  // kMixing (mode 2, format version 2) is about 12 % smaller; kContext (mode 1)
  // keeps a SPIHT stream readable by version 1 decoders.
  MaskCoding mask_coding = MaskCoding::kMixing;
  MotionCoder motion_coder = MotionCoder::kArith;
  uint16_t key_interval = 1;
  // The body model on a grid ('modl' version 1, format version 10: 0.12 mm
  // positions, 10-bit normals, 8-bit weights; less than half the bytes of its
  // floats). The encoder resamples with the model as decoded. false stores
  // floats, what format versions 1 to 9 decoders read.
  bool quantise_model = true;
  // The texture in chunks ('txhd' + 'txck', format version 11): any prefix of
  // a fragment past its head decodes, so a player fetches the bytes its
  // bandwidth allows with one HTTP range. The same samples, a few hundred
  // bytes more per fragment (docs/encoder.md). false writes 'texr', what
  // format versions 1 to 10 decoders read. Not with the predictive texture.
  bool texture_chunks = true;
  // The surface of every frame (format version 12, SPEC.md 3.5.2): the
  // fitted body moved along its normals to each frame's silhouettes
  // (encoder/shape/surface_tracking.h), carried per fragment and used for the
  // frame's resampling. Needs texture_chunks and silhouettes (footage, not a
  // texture directory). `surface_step_exponent`: values in steps of 2^-e m
  // (8: 3.9 mm, below a pixel of the silhouettes the surface is tracked on).
  bool surface = false;
  SurfaceTrackingOptions surface_tracking;
  uint8_t surface_step_exponent = 8;
  uint32_t threads = 2;
  Metadata metadata;

  // Encoding in shards (docs/scale-out.md). `prepared`: a directory
  // PrepareTake wrote; the take's frames, model and static texture come from
  // it. shards > 0: only shard `shard` of `shards` (GOP-aligned; needs
  // `prepared`, and `poses` when the take was prepared with them, else the
  // shard tracks), a stream of its own that JoinShards puts together.
  std::string prepared;
  uint32_t shard = 0, shards = 0;
  // A shard that tracks: instead of a first-frame search and warm-up before
  // its frames, go on from the poses of this part (shard - 1 of the same
  // split), where a join found the first-frame search wrong.
  std::string after;
  // PrepareTake: the static texture averages this many frames spread over the take.
  uint32_t prepare_frames = 8;
  // PrepareTake without poses: every shard tracks its own frames, and this
  // many frames on each side of them (docs/scale-out.md, "Tracking in shards").
  uint32_t track_warm_up = 8;

  std::string save_textures;  // also write the MVV textures and masks here (PNG)
  std::function<void(const std::string&)> progress;  // one line per frame and stage
};

struct EncodeSummary {
  std::string output;
  uint8_t level = 0;
  uint32_t first_frame = 0, frames = 0, cameras = 0, atlas_size = 0, gops = 0;
  double fps = 25;
  uint64_t file_bytes = 0, texture_bytes = 0, mask_bytes = 0, motion_bytes = 0;
  uint64_t atlas_texels = 0;     // frames * cameras * size^2
  uint64_t visible_texels = 0;   // texels some camera saw, summed over frames and cameras
  std::array<double, 3> psnr{};  // Y, U, V over visible texels, decoded at full length
  double psnr_rgb = 0;           // RGB over visible texels
  int flagged_frames = 0;        // tracking: fits flagged as poor
  double mean_iou = 0;           // tracking: mean silhouette IoU
  std::string pose_source;       // "tracked", "poses FILE", "textures DIR"
  // Seconds spent per stage.
  double read_s = 0, track_s = 0, resample_s = 0, code_s = 0, write_s = 0, total_s = 0;
  // Shape refinement (refine_shape): seconds, and the vertices' mean move per
  // level (metres).
  double refine_s = 0;
  std::vector<double> refine_moves;
  // Texels filled from the nearest frames that saw them, from the static
  // texture and from their twins (mirror_fill; summed over frames), and the
  // static texture's time.
  uint64_t temporal_fill_texels = 0, fallback_texels = 0, mirror_fill_texels = 0;
  double seamless_s = 0;
  // Without masks: texels a player may take from a camera that did not see
  // them (summed over frames and cameras), and those of them left to the fill
  // (least_blend_share).
  uint64_t player_texels = 0, player_texels_left = 0;
  // Texels seen by enough cameras to check their colours, and the samples
  // dropped as seeing something else (summed over frames).
  uint64_t agreement_texels = 0, agreement_dropped = 0;
  // Samples hidden behind something other than the actor (summed over frames
  // and cameras), the frames in which something was found, and its time.
  uint64_t occluded_samples = 0;
  uint32_t occluder_frames = 0;
  // Camera frames found suspect (OccluderOptions::suspect_share), and their
  // samples dropped as no other camera backed them.
  uint32_t suspect_camera_frames = 0;
  uint64_t suspect_dropped = 0;
  double occluder_s = 0;
  // The surface of every frame (surface): its bytes, tracking seconds, the
  // mean |displacement| (metres) and the share of vertices a stereo match
  // spoke for, over frames; the tracker's stereo weight and pull to the
  // previous frame (given, or chosen by the rig).
  uint64_t surface_bytes = 0;
  double surface_s = 0, surface_mean_abs = 0, surface_stereo = 0;
  double surface_stereo_weight = 0, surface_temporal_weight = 0;

  double duration_s() const { return frames / fps; }
  double kbps(uint64_t bytes) const { return bytes * 8.0 / 1000 / duration_s(); }
  double ratio_atlas() const { return 3.0 * atlas_texels / file_bytes; }
  double ratio_visible() const { return 3.0 * visible_texels / file_bytes; }
  std::string Table() const;   // the human-readable summary
  std::string ToJson() const;  // the same figures for scripts
};

StatusOr<EncodeSummary> EncodeCapture(const std::string& capture, const std::string& output,
                                      const EncoderSettings& settings);

struct PrepareSummary {
  std::string directory;
  uint32_t first_frame = 0, frames = 0, gops = 0;
  std::vector<uint32_t> texture_frames;
  double seconds = 0;
};
// The shared pass before shards: the take (settings' frame range, clamped to
// the capture and the poses), its model and static texture, written to
// `directory` (encoder/encode/prepared_take.h). Without poses, the shape is
// tracked on the take's first frames and the static texture's frames are
// fitted each on its own; the shards then track.
StatusOr<PrepareSummary> PrepareTake(const std::string& capture, const std::string& directory,
                                     const EncoderSettings& settings);

// Texture files of a --save-textures directory.
std::string TexturePath(const std::string& dir, const std::string& camera, uint32_t frame);
// Mask PNG values of a texture directory: seen (any other non-zero value
// reads as seen too), and, for streams without masks, usable: a player may
// take the texel from the camera, which did not see it.
constexpr uint8_t kSeenTexel = 255, kUsableTexel = 128;
std::string TextureMaskPath(const std::string& dir, const std::string& camera, uint32_t frame);

}  // namespace fvv

#endif  // FVV_ENCODER_ENCODE_ENCODER_H_
