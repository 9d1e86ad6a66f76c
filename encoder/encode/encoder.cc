#include "encoder/encode/encoder.h"

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
#include "encoder/encode/ordered_queue.h"
#include "encoder/encode/pose_file.h"
#include "encoder/encode/seamless_texture.h"
#include "encoder/track/capture_frames.h"
#include "encoder/track/features.h"
#include "encoder/track/track_capture.h"

namespace fvv {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A camera name as a directory name: itself when it is plain, else by index.
std::string CameraDirName(const std::string& name, uint32_t index) {
  bool plain = !name.empty() && name != "." && name != "..";
  for (char ch : name) {
    plain = plain &&
            (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.');
  }
  char buf[32];
  std::snprintf(buf, sizeof(buf), "camera_%02u", index);
  return plain ? name : buf;
}

std::string FrameFile(const std::string& dir, const std::string& camera, const char* kind,
                      uint32_t frame) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "/%s_%06u.png", kind, frame);
  return dir + "/" + camera + buf;
}

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
  // The body model and atlas for the actor's shape (once); with
  // refine_shape, the model refined on `first` (its pose, images and
  // silhouettes) first.
  Status SetShape(const BodyShape& shape, const RefinementFrame* first) {
    if (!model_.mesh.positions.empty()) return Status::Ok();
    shape_ = shape;
    model_ = MakeGenericBody(shape);
    if (s_.refine_shape) {
      if (!first) return InvalidArgument("--refine-shape needs the capture's images");
      const auto t0 = Clock::now();
      ShapeRefinementReport report;
      StatusOr<BodyModel> refined =
          RefineShape(model_, cameras_, {*first}, s_.refinement, &report, pool_.runner());
      if (!refined.ok()) return refined.status();
      model_ = std::move(refined).value();
      sum_.refine_s = Since(t0);
      for (const auto& l : report.levels) sum_.refine_moves.push_back(l.mean_move);
      char line[160];
      std::snprintf(line, sizeof(line),
                    "encode: shape refined on the first frame in %.1f s (mean move per level:",
                    sum_.refine_s);
      std::string say = line;
      for (double m : sum_.refine_moves) {
        std::snprintf(line, sizeof(line), " %.1f mm", m * 1e3);
        say += line;
      }
      if (s_.progress) s_.progress(say + ")");
    }
    AtlasOptions ao;
    ao.size = s_.atlas_size;
    StatusOr<Atlas> atlas = BuildAtlas(model_.mesh, ao);
    if (!atlas.ok()) return atlas.status();
    model_.mesh = std::move(atlas->mesh);
    map_ = MapAtlasTexels(model_.mesh, s_.atlas_size);
    const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
    span_rgb_.assign(size_t(s_.gop_frames) * sum_.cameras * texels * 3, 0);
    span_mask_.assign(size_t(s_.gop_frames) * sum_.cameras * texels, 0);
    if (s_.fallback_texture || !s_.static_texture.empty()) {
      static_ = std::make_unique<StaticTexture>(s_.atlas_size);
      span_fallback_.assign(s_.gop_frames, {});
      all_seen_.assign(texels, 1);
    }
    if (!s_.save_textures.empty()) FVV_RETURN_IF_ERROR(MakeTextureDirectories());
    return Status::Ok();
  }

  // One frame: `images` and `silhouettes` per camera, or, with `textures`, the
  // atlas textures and masks themselves.
  Status AddFrame(uint32_t frame, const std::vector<double>& dofs, const std::vector<Image>& images,
                  const std::vector<Image>& silhouettes) {
    const auto t0 = Clock::now();
    const Skeleton& skeleton = model_.skeleton;
    const QuantisedPose q = QuantisePose(skeleton.Dofs(), motion_, dofs);
    poses_.push_back(q);
    raw_poses_.push_back(dofs);
    const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
    const uint32_t slot = (frame - first_) % s_.gop_frames;
    const std::vector<Affine> skin =
        SkinningMatrices(skeleton, DequantisePose(skeleton.Dofs(), motion_, q));
    std::vector<Eigen::Vector3f> normals;
    const std::vector<Eigen::Vector3f> positions = SkinPositions(model_.mesh, skin, &normals);
    if (images.empty()) {
      FVV_RETURN_IF_ERROR(ReadTextures(frame, slot));
    } else {
      pool_.Run(sum_.cameras, [&](uint32_t c) {
        const size_t plane = size_t(slot) * sum_.cameras + c;
        ResampleView(map_, model_.mesh, positions, normals, cameras_[c], images[c],
                     silhouettes.empty() ? Image() : silhouettes[c], s_.resample,
                     &span_rgb_[plane * texels * 3], &span_mask_[plane * texels]);
      });
    }
    sum_.resample_s += Since(t0);
    if (static_) AddToStaticTexture(slot, positions);
    if (slot + 1 == s_.gop_frames || frame == last_) FVV_RETURN_IF_ERROR(CodeSpan(slot + 1));
    return Status::Ok();
  }

  Status Finish(const std::string& output) {
    const auto t0 = Clock::now();
    StreamInfo info;
    FileHeader& h = info.header;
    FVV_RETURN_IF_ERROR(FillHeader(&h));
    info.cameras = cameras_;
    info.model = model_;
    info.motion = motion_;
    info.metadata = s_.metadata;
    // An offline encoder knows the whole take: motion statistics up front.
    TrainMotionParams(model_.skeleton, poses_, s_.gop_frames, &info.motion);
    for (FragmentData& f : fragments_) {
      if (f.info.first_camera != 0) continue;
      std::vector<QuantisedPose> poses(poses_.begin() + f.info.first_frame,
                                       poses_.begin() + f.info.first_frame + f.info.frame_count);
      FVV_ASSIGN_OR_RETURN(f.motion, EncodeMotion(model_.skeleton, info.motion, poses));
      sum_.motion_bytes += f.motion.size();
    }
    StatusOr<std::unique_ptr<FileWriter>> writer = FileWriter::Create(output, info);
    if (!writer.ok()) return writer.status();
    for (const FragmentData& f : fragments_) FVV_RETURN_IF_ERROR((*writer)->AddFragment(f));
    FVV_RETURN_IF_ERROR((*writer)->Close());
    sum_.file_bytes = (*writer)->bytes_written();
    sum_.level = h.level;
    sum_.gops = uint32_t(fragments_.size());
    for (int c = 0; c < 3; ++c) {
      sum_.psnr[c] = PsnrFromMse(sse_[c] / std::max<double>(1, samples_[c]));
    }
    sum_.psnr_rgb = PsnrFromMse(sse_rgb_ / std::max<double>(1, 3.0 * sum_.visible_texels));
    if (!s_.save_textures.empty()) FVV_RETURN_IF_ERROR(WriteTexturesJson());
    if (!s_.static_texture.empty()) {
      Image img;
      img.width = img.height = s_.atlas_size;
      img.channels = 3;
      img.pixels = static_->Rgb();
      FVV_RETURN_IF_ERROR(WriteImage(s_.static_texture, img));
    }
    sum_.write_s += Since(t0);
    return Status::Ok();
  }

 private:
  // The samples' fractional bits: whole samples for the predictive codec.
  int SampleFrac() const {
    return s_.texture_codec == TextureCodec::kSpiht4d
               ? UsableSampleFrac(s_.kernel, s_.frac_bits_97, s_.weights, s_.sample_frac)
               : 0;
  }
  Status FillHeader(FileHeader* h) const {
    h->frame_rate_num = uint32_t(std::lround(cap_.frame_rate * 1000));
    h->frame_rate_den = 1000;
    if (std::abs(cap_.frame_rate - std::round(cap_.frame_rate)) < 1e-9) {
      h->frame_rate_num = uint32_t(std::lround(cap_.frame_rate));
      h->frame_rate_den = 1;
    }
    h->frame_count = sum_.frames;
    h->camera_count = uint16_t(sum_.cameras);
    h->atlas_width = h->atlas_height = uint16_t(s_.atlas_size);
    h->gop_frames = s_.gop_frames;
    h->gop_cameras = s_.gop_cameras;
    if (s_.texture_codec == TextureCodec::kPredictive) {
      h->tools = (TextureTools(s_.kernel, s_.coder, ColourSpace::kYCbCr601, s_.chroma, 0,
                               BandWeights::kAxisBands) &
                  (kToolHaar | kToolLeGall53 | kToolCdf97)) |
                 kToolPredictiveTexture;
    } else {
      h->tools = TextureTools(s_.kernel, s_.coder, ColourSpace::kYCbCr601, s_.chroma,
                              KernelFracBits(s_.kernel, s_.frac_bits_97), s_.weights, SampleFrac());
    }
    if (s_.masks) h->tools |= kToolMasks;
    if (s_.key_interval > 1) h->tools |= kToolMotionInterpolation;
    if (s_.motion_coder == MotionCoder::kZstd) h->tools |= kToolMotionZstd;
    h->format_version = RequiredFormatVersion(h->tools, s_.mask_coding);
    // The lowest level whose limits hold the stream.
    for (const LevelLimits& l : AllLevels()) {
      h->level = l.level;
      if (ValidateFileHeader(*h).ok() && ValidateBodyModel(model_, &l).ok()) return Status::Ok();
    }
    const Status header = ValidateFileHeader(*h);
    return InvalidArgument("no level holds this stream: " +
                           (header.ok() ? ValidateBodyModel(model_, &AllLevels().back()).message()
                                        : header.message()));
  }

  // Codes the `frames` frames held for the current time span: one block per
  // camera group.
  // The frame's seamless texture joins the static one; the best-facing camera
  // of every texel is kept for the fallback.
  void AddToStaticTexture(uint32_t slot, const std::vector<Eigen::Vector3f>& positions) {
    const auto t0 = Clock::now();
    const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
    CameraTextures textures{s_.atlas_size, {}, {}}, facing{s_.atlas_size, {}, {}};
    for (uint32_t c = 0; c < sum_.cameras; ++c) {
      const size_t plane = size_t(slot) * sum_.cameras + c;
      textures.rgb.push_back(&span_rgb_[plane * texels * 3]);
      textures.masks.push_back(&span_mask_[plane * texels]);
      facing.rgb.push_back(textures.rgb.back());
      facing.masks.push_back(all_seen_.data());
    }
    const std::vector<int16_t> labels =
        BestCameraLabels(map_, model_.mesh, positions, cameras_, textures);
    static_->Add(BlendSeamless(textures, labels), labels);
    span_fallback_[slot] = BestCameraLabels(map_, model_.mesh, positions, cameras_, facing);
    sum_.seamless_s += Since(t0);
  }

  // Texels of the span's frames that no camera saw take the static texture's
  // colour in their best-facing camera.
  void ApplyFallback(uint32_t frames) {
    const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
    for (uint32_t t = 0; t < frames; ++t) {
      for (uint32_t texel : map_.texel) {
        const int16_t camera = span_fallback_[t][texel];
        if (camera < 0 || !static_->Has(texel)) continue;
        bool seen = false;
        for (uint32_t c = 0; c < sum_.cameras && !seen; ++c) {
          seen = span_mask_[(size_t(t) * sum_.cameras + c) * texels + texel] != 0;
        }
        if (seen) continue;
        const size_t plane = size_t(t) * sum_.cameras + uint32_t(camera);
        static_->Get(texel, &span_rgb_[(plane * texels + texel) * 3]);
        span_mask_[plane * texels + texel] = 1;
        ++sum_.fallback_texels;
      }
    }
  }

  Status CodeSpan(uint32_t frames) {
    if (s_.fallback_texture && static_) ApplyFallback(frames);
    const uint32_t span_first =
        first_ + uint32_t(fragments_.size() / CameraGroups()) * s_.gop_frames;
    // Saved as coded (fallback texels included), so other codecs compared on
    // them code the same content, and --textures encodes them again.
    if (!s_.save_textures.empty()) {
      for (uint32_t t = 0; t < frames; ++t) FVV_RETURN_IF_ERROR(SaveTextures(span_first + t, t));
    }
    const auto t0 = Clock::now();
    const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
    for (uint32_t g = 0; g < CameraGroups(); ++g) {
      FragmentData frag;
      frag.info.gop_index = uint32_t(fragments_.size());
      frag.info.first_frame = span_first - first_;
      frag.info.frame_count = uint16_t(frames);
      frag.info.first_camera = uint16_t(g * s_.gop_cameras);
      frag.info.camera_count =
          uint16_t(std::min<uint32_t>(s_.gop_cameras, sum_.cameras - g * s_.gop_cameras));
      Shape4D shape;
      shape.n = {frames, frag.info.camera_count, s_.atlas_size, s_.atlas_size};
      std::vector<uint8_t> rgb(shape.count() * 3);
      UsedMask used(shape.count());
      for (uint32_t t = 0; t < frames; ++t) {
        for (uint32_t c = 0; c < frag.info.camera_count; ++c) {
          const size_t src = size_t(t) * sum_.cameras + frag.info.first_camera + c;
          const size_t dst = size_t(t) * frag.info.camera_count + c;
          std::copy_n(&span_rgb_[src * texels * 3], texels * 3, &rgb[dst * texels * 3]);
          std::copy_n(&span_mask_[src * texels], texels, &used[dst * texels]);
        }
      }
      const Block block =
          BlockFromRgb(rgb.data(), shape, ColourSpace::kYCbCr601, s_.chroma, SampleFrac());
      if (s_.texture_codec == TextureCodec::kPredictive) {
        FVV_RETURN_IF_ERROR(CodePredictive(block, rgb, used, shape, &frag));
        fragments_.push_back(std::move(frag));
        continue;
      }
      EncodeSettings es;
      es.kernel = s_.kernel;
      es.frac_bits_97 = s_.frac_bits_97;
      es.coder = s_.coder;
      es.weights = s_.weights;
      es.rate_mode = s_.rate_mode;
      es.rate_value = s_.rate_value;
      es.fill = s_.fill;
      es.prune_isolated = s_.prune_isolated;
      es.runner = pool_.runner();
      Block decoded;
      EncodeReport report;
      report.decoded = &decoded;  // what a decoder reconstructs at full length
      FVV_ASSIGN_OR_RETURN(frag.texture,
                           EncodeBlock(block, s_.masks ? &used : nullptr, es, &report));
      if (s_.masks) {
        frag.masks = EncodeMasks(used.data(), shape, s_.mask_coding);
        frag.mask_mode = s_.mask_coding;
      }
      sum_.texture_bytes += frag.texture.total_bytes();
      sum_.mask_bytes += frag.masks.size();
      Measure(block, decoded, used, rgb);
      fragments_.push_back(std::move(frag));
    }
    sum_.code_s += Since(t0);
    return Status::Ok();
  }

  // One GOP with the predictive scheme; the same rate targets as SPIHT's.
  Status CodePredictive(const Block& block, std::vector<uint8_t>& rgb, const UsedMask& used,
                        const Shape4D& shape, FragmentData* frag) {
    PredictiveGop gop;
    gop.frames = shape.frames(), gop.cameras = shape.cameras();
    gop.width = shape.width(), gop.height = shape.height();
    gop.rgb = std::move(rgb);
    gop.mask = used;
    PredictiveEncodeOptions o;
    o.kernel = s_.kernel;
    o.runner = pool_.runner();
    if (s_.rate_mode == RateMode::kPsnr) {
      o.target_psnr = s_.rate_value;
    } else if (s_.rate_mode == RateMode::kTotalBytes) {
      o.target_bytes = uint64_t(s_.rate_value);
    } else if (s_.rate_mode == RateMode::kBitsPerSample) {
      o.target_bytes = uint64_t(std::ceil(s_.rate_value * double(shape.count()) / 8));
    }
    PredictiveDecoded rec;
    FVV_ASSIGN_OR_RETURN(frag->predictive_texture, EncodePredictive(gop, o, &rec));
    frag->predictive = true;
    frag->masks = EncodeMasks(used.data(), shape, s_.mask_coding);
    frag->mask_mode = s_.mask_coding;
    sum_.texture_bytes += frag->predictive_texture.Bytes();
    sum_.mask_bytes += frag->masks.size();
    Block decoded = block;
    const size_t texels = size_t(gop.width) * gop.height;
    for (int k = 0; k < 3; ++k) {
      for (size_t tc = 0; tc < rec.yuv.size(); ++tc) {
        std::copy(rec.yuv[tc][k].begin(), rec.yuv[tc][k].end(),
                  decoded.channels[k].samples.begin() + tc * texels);
      }
    }
    Measure(block, decoded, used, gop.rgb);
    return Status::Ok();
  }

  // Y, U, V errors against the block coded; RGB errors against the texels as
  // resampled (what a player shows against what the cameras saw).
  void Measure(const Block& block, const Block& decoded, const UsedMask& used,
               const std::vector<uint8_t>& a) {
    UsedMask chroma_used;
    const UsedMask* cmask = &used;
    if (block.chroma == ChromaFormat::k420) {
      chroma_used = DownsampleMask(used, block.shape(), block.channels[1].shape);
      cmask = &chroma_used;
    }
    for (int c = 0; c < 3; ++c) {
      const UsedMask& m = c == 0 ? used : *cmask;
      uint64_t count = 0;
      for (uint8_t u : m) count += u != 0;
      sse_[c] += ChannelMse(block.channels[c], decoded.channels[c], &m, block.sample_frac) * count;
      samples_[c] += count;
    }
    std::vector<uint8_t> b(a.size());
    BlockToRgb(decoded, b.data());
    for (size_t i = 0; i < used.size(); ++i) {
      if (!used[i]) continue;
      ++sum_.visible_texels;
      for (int k = 0; k < 3; ++k) {
        const double d = double(a[3 * i + k]) - b[3 * i + k];
        sse_rgb_ += d * d;
      }
    }
  }

  uint32_t CameraGroups() const { return (sum_.cameras + s_.gop_cameras - 1) / s_.gop_cameras; }

  Status SaveTextures(uint32_t frame, uint32_t slot) {
    const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
    for (uint32_t c = 0; c < sum_.cameras; ++c) {
      const size_t plane = size_t(slot) * sum_.cameras + c;
      Image tex{s_.atlas_size, s_.atlas_size, 3, {}};
      tex.pixels.assign(&span_rgb_[plane * texels * 3], &span_rgb_[(plane + 1) * texels * 3]);
      Image mask{s_.atlas_size, s_.atlas_size, 1, std::vector<uint8_t>(texels)};
      for (size_t i = 0; i < texels; ++i) mask.pixels[i] = span_mask_[plane * texels + i] ? 255 : 0;
      FVV_RETURN_IF_ERROR(WritePng(TexturePath(s_.save_textures, camera_dirs_[c], frame), tex));
      FVV_RETURN_IF_ERROR(
          WritePng(TextureMaskPath(s_.save_textures, camera_dirs_[c], frame), mask));
    }
    return Status::Ok();
  }

  Status ReadTextures(uint32_t frame, uint32_t slot) {
    const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
    std::vector<Status> errors(sum_.cameras);
    pool_.Run(sum_.cameras, [&](uint32_t c) {
      const size_t plane = size_t(slot) * sum_.cameras + c;
      const std::string tp = TexturePath(s_.textures, camera_dirs_[c], frame);
      const std::string mp = TextureMaskPath(s_.textures, camera_dirs_[c], frame);
      StatusOr<Image> tex = ReadImage(tp);
      StatusOr<Image> mask = tex.ok() ? ReadImage(mp) : tex;
      if (!mask.ok()) {
        errors[c] = mask.status();
        return;
      }
      for (const auto* im : {&*tex, &*mask}) {
        if (im->width != s_.atlas_size || im->height != s_.atlas_size) {
          errors[c] = InvalidArgument((im == &*tex ? tp : mp) + ": " + std::to_string(im->width) +
                                      "x" + std::to_string(im->height) + ", the atlas is " +
                                      std::to_string(s_.atlas_size) + " square");
          return;
        }
      }
      for (size_t i = 0; i < texels; ++i) {
        const bool seen = mask->pixels[i * mask->channels] != 0;
        span_mask_[plane * texels + i] = seen;
        for (int k = 0; k < 3; ++k) {
          span_rgb_[(plane * texels + i) * 3 + k] =
              tex->channels == 3 ? tex->pixels[i * 3 + k] : tex->pixels[i];
        }
      }
    });
    for (const Status& e : errors) FVV_RETURN_IF_ERROR(e);
    return Status::Ok();
  }

  Status MakeTextureDirectories() const {
    for (const std::string& dir : camera_dirs_) {
      FVV_RETURN_IF_ERROR(MakeDirectories(s_.save_textures + "/" + dir));
    }
    return Status::Ok();
  }

  // textures.json: what the textures are (atlas, cameras, frames) and the
  // poses and body shape they were resampled with, so `--textures` can encode
  // them again (it is also a valid poses file).
  Status WriteTexturesJson() const {
    nlohmann::json j;
    j["generator"] = "fvv encode --save-textures";
    j["atlas_size"] = s_.atlas_size;
    j["first_frame"] = first_;
    j["frame_count"] = sum_.frames;
    j["cameras"] = camera_dirs_;
    j["texture_pattern"] = "<camera>/texture_%06d.png";
    j["mask_pattern"] = "<camera>/mask_%06d.png";
    j["dof_names"] = GenericDofNames();
    j["body_shape"] = BodyShapeToJson(shape_);
    nlohmann::json frames = nlohmann::json::array();
    for (size_t i = 0; i < raw_poses_.size(); ++i) {
      frames.push_back({{"frame", first_ + i}, {"dofs", raw_poses_[i]}});
    }
    j["frames"] = frames;
    const std::string text = j.dump(1) + "\n";
    return WriteFileAtomic(s_.save_textures + "/textures.json",
                           reinterpret_cast<const uint8_t*>(text.data()), text.size());
  }

  const Capture& cap_;
  const EncoderSettings& s_;
  ThreadPool pool_;
  uint32_t first_, last_;
  EncodeSummary sum_;
  std::vector<Camera> cameras_;
  std::vector<std::string> camera_dirs_;
  MotionParams motion_;
  BodyShape shape_;
  BodyModel model_;
  TexelMap map_;
  std::vector<uint8_t> span_rgb_, span_mask_;        // (slot, camera, y, x)
  std::unique_ptr<StaticTexture> static_;            // with fallback_texture or static_texture
  std::vector<std::vector<int16_t>> span_fallback_;  // per slot: best-facing camera per texel
  std::vector<uint8_t> all_seen_;                    // texels x 1: "every camera" masks
  std::vector<QuantisedPose> poses_;
  std::vector<std::vector<double>> raw_poses_;
  std::vector<FragmentData> fragments_;
  std::array<double, 3> sse_{};
  std::array<uint64_t, 3> samples_{};
  double sse_rgb_ = 0;
};

Status CheckSettings(const EncoderSettings& s) {
  if (s.atlas_size < 16 || s.atlas_size > 4096) {
    return InvalidArgument("atlas size " + std::to_string(s.atlas_size) + " is not in 16..4096");
  }
  if (s.gop_frames < 1) return InvalidArgument("GOP frames must be >= 1");
  if (!ValidFracBits97(s.frac_bits_97)) {
    return InvalidArgument("9/7 sample precision " + std::to_string(s.frac_bits_97) +
                           " is not in " + std::to_string(kMinFracBits97) + ".." +
                           std::to_string(kMaxFracBits97) + " fractional bits");
  }
  if (s.texture_codec == TextureCodec::kPredictive) {
    if (!s.masks) {
      return InvalidArgument("the predictive texture codec needs masks (they are its supports)");
    }
    if (s.chroma != ChromaFormat::k444) {
      return InvalidArgument("the predictive texture codec codes 4:4:4 only");
    }
  }
  if (!s.poses.empty() && !s.textures.empty()) {
    return InvalidArgument("give poses or textures, not both (textures carry their poses)");
  }
  if (!s.save_textures.empty() && !s.textures.empty()) {
    return InvalidArgument("--save-textures with --textures would copy the input");
  }
  if (!std::isfinite(s.rate_value) || s.rate_value <= 0) {
    return InvalidArgument("the rate (bpp, bytes or PSNR) must be positive");
  }
  if (s.threads < 1 || s.threads > 256) return InvalidArgument("threads must be 1..256");
  return Status::Ok();
}

void Say(const EncoderSettings& s, const std::string& line) {
  if (s.progress) s.progress(line);
}

}  // namespace

std::string TexturePath(const std::string& dir, const std::string& camera, uint32_t frame) {
  return FrameFile(dir, camera, "texture", frame);
}
std::string TextureMaskPath(const std::string& dir, const std::string& camera, uint32_t frame) {
  return FrameFile(dir, camera, "mask", frame);
}

StatusOr<EncodeSummary> EncodeCapture(const std::string& capture_path, const std::string& output,
                                      const EncoderSettings& s_in) {
  const auto start = Clock::now();
  FVV_RETURN_IF_ERROR(CheckSettings(s_in));
  StatusOr<Capture> cap = LoadCapture(capture_path);
  if (!cap.ok()) return cap.status();
  if (cap->cameras.size() > 65535) return InvalidArgument("more than 65535 cameras");
  EncoderSettings s = s_in;
  if (s.gop_cameras == 0) s.gop_cameras = uint16_t(cap->cameras.size());

  // Poses given (a file, or the textures' own record), or tracked below.
  std::optional<PoseSequence> given;
  if (!s.poses.empty() || !s.textures.empty()) {
    StatusOr<PoseSequence> p =
        LoadPoseFile(s.poses.empty() ? s.textures + "/textures.json" : s.poses);
    if (!p.ok()) return p.status();
    given = std::move(*p);
  }
  uint32_t first = s.first_frame, last = std::min(s.last_frame, cap->frame_count - 1);
  if (given) {
    first = std::max(first, given->first_frame);
    last = std::min<uint32_t>(last, given->first_frame + uint32_t(given->poses.size()) - 1);
  }
  if (first > last) {
    return InvalidArgument(
        "no frames to encode: frames " + std::to_string(s.first_frame) + ".." +
        (s.last_frame == UINT32_MAX ? std::string("end") : std::to_string(s.last_frame)) +
        " of a capture of " + std::to_string(cap->frame_count) +
        (given ? " with poses for frames " + std::to_string(given->first_frame) + ".." +
                     std::to_string(given->first_frame + given->poses.size() - 1)
               : std::string()));
  }
  if (!s.textures.empty() && given->atlas_size != s.atlas_size) {
    // The textures must have been made for this atlas.
    return InvalidArgument(s.textures + "/textures.json: atlas_size is not " +
                           std::to_string(s.atlas_size) + " (pass --atlas to match)");
  }

  // Feature points for shape refinement's features term (optional).
  std::optional<FeatureSet> features;
  if (!s.features.empty()) {
    std::vector<Camera> cams;
    for (const auto& c : cap->cameras) cams.push_back(c.calibration);
    StatusOr<FeatureSet> f = LoadFeatures(s.features, cams, cap->frame_count);
    if (!f.ok()) return f.status();
    features = std::move(*f);
  }
  const auto FeaturesOf = [&](uint32_t frame) {
    std::map<std::string, Eigen::Vector3d> out;
    if (!features || !features->frames.count(frame)) return out;
    std::vector<Camera> cams;
    for (const auto& c : cap->cameras) cams.push_back(c.calibration);
    for (const auto& [name, p] : TriangulateFeatures(features->frames.at(frame), cams)) {
      out[name] = p.position;
    }
    return out;
  };
  Session session(*cap, output, s, first, last);
  EncodeSummary& sum = session.summary();
  const uint32_t total = last - first + 1;
  auto progress = [&](uint32_t frame, const std::string& extra) {
    const uint32_t done = frame - first + 1;
    const double elapsed = Since(start);
    char line[256];
    std::snprintf(line, sizeof(line), "encode: frame %u (%u/%u)%s  %.2f s/frame, ETA %.0f s", frame,
                  done, total, extra.c_str(), elapsed / done, elapsed / done * (total - done));
    Say(s, line);
  };

  if (given) {
    sum.pose_source = s.textures.empty() ? "poses " + s.poses : "textures " + s.textures;
    std::unique_ptr<CaptureFrames> frames;
    if (s.textures.empty()) {
      StatusOr<std::unique_ptr<CaptureFrames>> f =
          CaptureFrames::Open(*cap, s.extract_silhouettes, &session.pool());
      if (!f.ok()) return f.status();
      frames = std::move(*f);
    } else if (s.refine_shape) {
      return InvalidArgument("--refine-shape needs the capture's images, not --textures");
    }
    for (uint32_t f = first; f <= last; ++f) {
      std::vector<Image> images, sils;
      if (frames) {
        const auto t0 = Clock::now();
        FVV_RETURN_IF_ERROR(frames->Read(f, &images, &sils));
        sum.read_s += Since(t0);
      }
      if (f == first) {
        const RefinementFrame refine{given->poses[f - given->first_frame], images, sils,
                                     FeaturesOf(f)};
        FVV_RETURN_IF_ERROR(session.SetShape(given->shape, frames ? &refine : nullptr));
      }
      FVV_RETURN_IF_ERROR(session.AddFrame(f, given->poses[f - given->first_frame], images, sils));
      progress(f, "");
    }
  } else {
    sum.pose_source = "tracked";
    TrackCaptureOptions to;
    to.first = first;
    to.last = last;
    to.extract = s.extract_silhouettes;
    to.tracker = s.tracker;
    to.smoothing = s.pose_smoothing;
    // Resampling and coding a frame run on a thread of their own, beside the
    // tracking of the next frames (at most one GOP and a frame queued), in
    // frame order, so the output is what a sequential run writes.
    OrderedQueue behind_tracking(s.gop_frames + 1);
    to.on_frame = [&](uint32_t f, const FrameFit& fit, const Tracker& tracker,
                      const std::vector<Image>& images, const std::vector<Image>& sils) -> Status {
      if (!session.HasShape()) {  // the shape: once, before any frame is resampled
        const RefinementFrame refine{fit.dofs, images, sils, FeaturesOf(f)};
        FVV_RETURN_IF_ERROR(session.SetShape(tracker.shape(), &refine));
      }
      char extra[96];
      std::snprintf(extra, sizeof(extra), "  IoU %.3f%s", fit.iou,
                    fit.poor ? ("  FLAGGED: " + fit.note).c_str() : "");
      return behind_tracking.Push(
          [&session, &progress, f, dofs = fit.dofs, images, sils, line = std::string(extra)] {
            FVV_RETURN_IF_ERROR(session.AddFrame(f, dofs, images, sils));
            progress(f, line);
            return Status::Ok();
          });
    };
    StatusOr<TrackCaptureResult> tracked = TrackCapture(capture_path, to);
    FVV_RETURN_IF_ERROR(behind_tracking.Finish());
    if (!tracked.ok()) return tracked.status();
    sum.read_s = tracked->silhouette_seconds;
    sum.track_s = tracked->fit_seconds;
    sum.flagged_frames = tracked->flagged;
    sum.mean_iou = tracked->mean_iou;
  }
  Say(s, "encode: writing " + output);
  FVV_RETURN_IF_ERROR(session.Finish(output));
  sum.total_s = Since(start);
  return sum;
}

std::string EncodeSummary::Table() const {
  std::string out;
  char line[256];
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof(line), fmt, args...);
    out += line;
  };
  add("%s: %u frames (from %u) x %u cameras, atlas %ux%u, %u GOPs, level %u, pose source: %s\n",
      output.c_str(), frames, first_frame, cameras, atlas_size, atlas_size, gops, level,
      pose_source.c_str());
  add("  size              %12llu bytes   %9.1f kbps\n", (unsigned long long)file_bytes,
      kbps(file_bytes));
  add("    textures        %12llu bytes   %9.1f kbps\n", (unsigned long long)texture_bytes,
      kbps(texture_bytes));
  add("    masks           %12llu bytes   %9.1f kbps\n", (unsigned long long)mask_bytes,
      kbps(mask_bytes));
  add("    motion          %12llu bytes   %9.2f kbps\n", (unsigned long long)motion_bytes,
      kbps(motion_bytes));
  add("    model, headers  %12llu bytes\n",
      (unsigned long long)(file_bytes - texture_bytes - mask_bytes - motion_bytes));
  add("  compression       %8.1f:1 vs 24-bit RGB atlases, %.1f:1 vs visible texels (%.1f %% "
      "of atlas texels seen)\n",
      ratio_atlas(), ratio_visible(), 100.0 * visible_texels / std::max<uint64_t>(1, atlas_texels));
  add("  PSNR (visible)    Y %.2f dB  U %.2f dB  V %.2f dB  RGB %.2f dB\n", psnr[0], psnr[1],
      psnr[2], psnr_rgb);
  if (pose_source == "tracked") {
    add("  tracking          mean IoU %.3f, %d frame(s) flagged\n", mean_iou, flagged_frames);
  }
  if (fallback_texels > 0 || seamless_s > 0) {
    add("  seamless texture  %.3f s per frame; %llu texel(s) no camera saw filled from it\n",
        seamless_s / std::max(1u, frames), (unsigned long long)fallback_texels);
  }
  if (!refine_moves.empty()) {
    add("  shape refinement  %.1f s on the first frame, mean vertex move %.1f mm\n", refine_s, [&] {
      double sum = 0;
      for (double m : refine_moves) sum += m;
      return sum * 1e3;
    }());
  }
  const double f = std::max(1u, frames);
  add("  seconds per frame read %.3f  track %.3f  resample %.3f  code %.3f  write %.3f  "
      "total %.3f (%.2f frames/s)\n",
      read_s / f, track_s / f, resample_s / f, code_s / f, write_s / f, total_s / f,
      f / std::max(1e-9, total_s));
  return out;
}

std::string EncodeSummary::ToJson() const {
  nlohmann::json j = {
      {"output", output},
      {"level", level},
      {"first_frame", first_frame},
      {"frames", frames},
      {"cameras", cameras},
      {"atlas_size", atlas_size},
      {"gops", gops},
      {"poses", pose_source},
      {"bytes",
       {{"file", file_bytes},
        {"texture", texture_bytes},
        {"masks", mask_bytes},
        {"motion", motion_bytes}}},
      {"kbps",
       {{"file", kbps(file_bytes)},
        {"texture", kbps(texture_bytes)},
        {"masks", kbps(mask_bytes)},
        {"motion", kbps(motion_bytes)}}},
      {"atlas_texels", atlas_texels},
      {"visible_texels", visible_texels},
      {"ratio_atlas", ratio_atlas()},
      {"ratio_visible", ratio_visible()},
      {"psnr", {{"y", psnr[0]}, {"u", psnr[1]}, {"v", psnr[2]}, {"rgb", psnr_rgb}}},
      {"tracking", {{"mean_iou", mean_iou}, {"flagged", flagged_frames}}},
      {"seamless_texture", {{"seconds", seamless_s}, {"fallback_texels", fallback_texels}}},
      {"shape_refinement",
       {{"refined", !refine_moves.empty()},
        {"seconds", refine_s},
        {"mean_move_per_level_m", refine_moves}}},
      {"seconds",
       {{"read", read_s},
        {"track", track_s},
        {"resample", resample_s},
        {"code", code_s},
        {"write", write_s},
        {"total", total_s}}}};
  return j.dump(1) + "\n";
}

}  // namespace fvv
