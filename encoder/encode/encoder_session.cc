// The encoder session's body model and atlas, its frame loop (resampling,
// the static and fallback texture) and the stream it writes at the end.
#include "encoder/encode/encoder_session.h"

#include "encoder/capture/calibration.h"
#include "encoder/capture/colour_gain.h"
#include "encoder/encode/blend_share.h"
#include "encoder/encode/mirror_texels.h"

namespace fvv {
namespace encoding {

// The body model and atlas for the actor's shape (once); with
// refine_shape, the model refined on `first` (its pose, images and
// silhouettes) first.
Status Session::SetShape(const BodyShape& shape, const RefinementFrame* first) {
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
    std::snprintf(
        line, sizeof(line),
        "encode: shape refined on the first frame in %.1f s (mean move per level:", sum_.refine_s);
    std::string say = line;
    for (const auto& l : report.levels) {
      std::snprintf(line, sizeof(line),
                    l.dropped ? " the %.0f mm level undone (it diverged)" : " %.1f mm",
                    (l.dropped ? l.range : l.mean_move) * 1e3);
      say += line;
    }
    if (s_.progress) s_.progress(say + ")");
  }
  AtlasOptions ao;
  ao.size = s_.atlas_size;
  StatusOr<Atlas> atlas = BuildAtlas(model_.mesh, ao);
  if (!atlas.ok()) return atlas.status();
  model_.mesh = std::move(atlas->mesh);
  FVV_RETURN_IF_ERROR(StoreModelAsDecoded());
  return AllocateForModel();
}

Status Session::UsePrepared(const PreparedTake& take) {
  if (HasShape()) return Internal("the session's model is already set");
  if (take.atlas_size != s_.atlas_size) {
    return InvalidArgument("the take was prepared for a " + std::to_string(take.atlas_size) +
                           " atlas, not " + std::to_string(s_.atlas_size) + " (pass --atlas " +
                           std::to_string(take.atlas_size) + ")");
  }
  shape_ = take.shape;
  model_ = take.model;
  FVV_RETURN_IF_ERROR(StoreModelAsDecoded());
  FVV_RETURN_IF_ERROR(AllocateForModel());
  if (static_) {
    static_->Set(take.static_rgb, take.static_coverage);
    static_fixed_ = true;
  }
  return Status::Ok();
}

// With a quantised model every later step (atlas map, skinning, resampling)
// uses the mesh a player decodes.
Status Session::StoreModelAsDecoded() {
  if (!s_.quantise_model) {
    model_.quantisation = ModelQuantisation();  // its values as they are, in floats
    return Status::Ok();
  }
  return QuantiseModel(DefaultModelQuantisation(s_.atlas_size), &model_);
}

Status Session::AllocateForModel() {
  map_ = MapAtlasTexels(model_.mesh, s_.atlas_size);
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  span_rgb_.assign(size_t(s_.gop_frames) * sum_.cameras * texels * 3, 0);
  span_mask_.assign(size_t(s_.gop_frames) * sum_.cameras * texels, 0);
  if (!s_.masks) {
    span_usable_.assign(span_mask_.size(), 0);
    span_positions_.assign(s_.gop_frames, {});
    span_normals_.assign(s_.gop_frames, {});
  }
  if (s_.fallback_texture || !s_.static_texture.empty()) {
    static_ = std::make_unique<StaticTexture>(s_.atlas_size);
    span_fallback_.assign(s_.gop_frames, {});
    all_seen_.assign(texels, 1);
    // What only the fills read is made only where they apply.
    const bool fills = AppliesFills();
    if (fills && (s_.temporal_fill_frames > 0 || s_.mirror_fill)) {
      span_seamless_.assign(s_.gop_frames, {});
      span_labels_.assign(s_.gop_frames, {});
    }
    if (fills && s_.mirror_fill) mirror_ = MirrorTexels(map_, model_.mesh);
  }
  if (!s_.save_textures.empty()) FVV_RETURN_IF_ERROR(MakeTextureDirectories());
  return Status::Ok();
}

// One frame: `images` and `silhouettes` per camera, or, with `textures`, the
// atlas textures and masks themselves.
Status Session::AddFrame(uint32_t frame, const std::vector<double>& dofs,
                         const std::vector<Image>& images, const std::vector<Image>& silhouettes) {
  const QuantisedPose q = QuantisePose(model_.skeleton.Dofs(), motion_, dofs);
  poses_.push_back(q);
  raw_poses_.push_back(dofs);
  const uint32_t slot = (frame - first_) % s_.gop_frames;
  FVV_ASSIGN_OR_RETURN(const std::vector<Eigen::Vector3f> positions,
                       Resample(frame, slot, q, images, silhouettes, s_.surface));
  if (static_) AddToStaticTexture(slot, positions);
  if (slot + 1 == s_.gop_frames || frame == last_) FVV_RETURN_IF_ERROR(CodeSpan(slot + 1));
  return Status::Ok();
}

Status Session::AddStaticFrame(uint32_t frame, const std::vector<double>& dofs,
                               const std::vector<Image>& images,
                               const std::vector<Image>& silhouettes) {
  if (!static_ || static_fixed_) return Internal("no static texture to add a frame to");
  const QuantisedPose q = QuantisePose(model_.skeleton.Dofs(), motion_, dofs);
  FVV_ASSIGN_OR_RETURN(const std::vector<Eigen::Vector3f> positions,
                       Resample(frame, 0, q, images, silhouettes, false));
  AddToStaticTexture(0, positions);
  return Status::Ok();
}

StatusOr<const Mesh*> Session::TrackSurface(uint32_t slot, const std::vector<Affine>& skin,
                                            const std::vector<Image>& images,
                                            const std::vector<Image>& silhouettes) {
  const auto t0 = Clock::now();
  if (!surface_tracker_) {
    surface_tracker_ = std::make_unique<SurfaceTracker>(model_.mesh, s_.surface_tracking);
    surface_mesh_ = model_.mesh;
    span_surface_.resize(s_.gop_frames);
  }
  SurfaceTrackingReport report;
  FVV_ASSIGN_OR_RETURN(
      const std::vector<float> d,
      surface_tracker_->Track(skin, cameras_, silhouettes, images, &report, pool_.runner()));
  // Quantised with hysteresis: a value keeps the previous frame's until the
  // surface has moved a step past it, so that still parts code as repeats
  // (the temporal residuals, mostly zero, are what the zstd frame shrinks).
  std::vector<int32_t>& values = span_surface_[slot];
  const double steps_per_m = std::ldexp(1.0, s_.surface_step_exponent);
  const bool first = surface_values_.size() != d.size();
  surface_values_.resize(d.size());
  for (size_t v = 0; v < d.size(); ++v) {
    const double x = std::clamp<double>(d[v] * steps_per_m, -kMaxSurfaceValue, kMaxSurfaceValue);
    if (first || std::abs(x - surface_values_[v]) >= 1.0) {
      surface_values_[v] = int32_t(std::lround(x));
    }
  }
  values = surface_values_;
  std::vector<float> bind;
  SurfacePositions(model_.mesh, values.data(), s_.surface_step_exponent, &bind);
  for (size_t v = 0; v < surface_mesh_.positions.size(); ++v) {
    surface_mesh_.positions[v] = {bind[3 * v], bind[3 * v + 1], bind[3 * v + 2]};
  }
  sum_.surface_mean_abs += report.mean_abs / sum_.frames;
  sum_.surface_stereo += report.stereo / sum_.frames;
  sum_.surface_stereo_weight = report.stereo_weight;
  sum_.surface_temporal_weight = report.temporal_weight;
  sum_.surface_s += Since(t0);
  return &surface_mesh_;
}

StatusOr<std::vector<Eigen::Vector3f>> Session::Resample(uint32_t frame, uint32_t slot,
                                                         const QuantisedPose& q,
                                                         const std::vector<Image>& images,
                                                         const std::vector<Image>& silhouettes,
                                                         bool track_surface) {
  const Skeleton& skeleton = model_.skeleton;
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  const std::vector<Affine> skin =
      SkinningMatrices(skeleton, DequantisePose(skeleton.Dofs(), motion_, q));
  const Mesh* surface = &model_.mesh;
  if (track_surface) {
    if (images.empty() || silhouettes.empty()) {
      return InvalidArgument("frame " + std::to_string(frame) +
                             ": the surface needs the cameras' silhouettes");
    }
    FVV_ASSIGN_OR_RETURN(surface, TrackSurface(slot, skin, images, silhouettes));
  }
  const auto t0 = Clock::now();
  std::vector<Eigen::Vector3f> normals;
  std::vector<Eigen::Vector3f> positions = SkinPositions(*surface, skin, &normals);
  if (images.empty()) {
    FVV_RETURN_IF_ERROR(ReadTextures(frame, slot));
  } else {
    std::vector<OccluderDepth> occluders;
    OccluderReport found;
    if (!silhouettes.empty() && s_.occluders.enabled) {
      const auto t1 = Clock::now();
      occluders = FindOccluders(cameras_, silhouettes, surface->triangles, positions, s_.occluders,
                                &found, pool_.runner());
      sum_.occluder_frames += found.voxels > 0;
      sum_.occluder_s += Since(t1);
    }
    std::vector<uint64_t> hidden(sum_.cameras, 0);
    ResampleOptions resample = s_.resample;
    resample.person_masks = person_masks_;
    pool_.Run(sum_.cameras, [&](uint32_t c) {
      const size_t plane = size_t(slot) * sum_.cameras + c;
      ResampleView(map_, *surface, positions, normals, cameras_[c], images[c],
                   silhouettes.empty() ? Image() : silhouettes[c], resample,
                   &span_rgb_[plane * texels * 3], &span_mask_[plane * texels],
                   span_usable_.empty() ? nullptr : &span_usable_[plane * texels],
                   occluders.empty() ? nullptr : &occluders[c], &hidden[c]);
      // In the rig's common colour, before the cameras compare colours.
      ApplyColourGain(cap_.cameras[c].colour_gain, &span_rgb_[plane * texels * 3], texels);
    });
    for (uint64_t h : hidden) sum_.occluded_samples += h;
    // The cameras check each other's colours (in parts of the atlas's
    // texels, side by side): every camera with --agreement, the suspect ones.
    const auto check = [&](const SampleAgreementOptions& options, const uint8_t* suspects) {
      constexpr uint32_t kParts = 16;
      const size_t first = size_t(slot) * sum_.cameras * texels, count = map_.texel.size();
      std::vector<SampleAgreementCount> parts(kParts);
      pool_.Run(kParts, [&](uint32_t k) {
        const size_t a = count * k / kParts, b = count * (k + 1) / kParts;
        parts[k] =
            DropDisagreeingSamples(sum_.cameras, texels, map_.texel.data() + a, b - a,
                                   &span_rgb_[first * 3], &span_mask_[first], options, suspects);
      });
      SampleAgreementCount all;
      for (const SampleAgreementCount& a : parts) all.voted += a.voted, all.dropped += a.dropped;
      return all;
    };
    if (s_.agreement.max_difference > 0) {
      const SampleAgreementCount a = check(s_.agreement, nullptr);
      sum_.agreement_texels += a.voted;
      sum_.agreement_dropped += a.dropped;
    }
    std::vector<uint8_t> suspects(sum_.cameras, 0);
    bool any_suspect = false;
    for (size_t c = 0; c < found.unexplained_share.size() && c < suspects.size(); ++c) {
      suspects[c] =
          s_.occluders.suspect_share > 0 && found.unexplained_share[c] > s_.occluders.suspect_share;
      any_suspect = any_suspect || suspects[c];
      sum_.suspect_camera_frames += suspects[c];
    }
    if (any_suspect) {
      sum_.suspect_dropped += check({s_.occluders.suspect_difference, 2}, suspects.data()).dropped;
    }
  }
  // The blend-share rule needs the posed surface; a texture directory already
  // marks what the encoder chose to code, and is coded as it is.
  if (!span_positions_.empty()) {
    span_positions_[slot] = images.empty() ? std::vector<Eigen::Vector3f>() : positions;
    span_normals_[slot] = images.empty() ? std::vector<Eigen::Vector3f>() : normals;
  }
  sum_.resample_s += Since(t0);
  return positions;
}

Status Session::Finish(const std::string& output) {
  const auto t0 = Clock::now();
  StreamInfo info;
  FileHeader& h = info.header;
  FVV_RETURN_IF_ERROR(FillHeader(&h));
  info.cameras = cameras_;
  info.model = model_;
  info.motion = motion_;
  info.metadata = s_.metadata;
  info.metadata.insert(info.metadata.end(), extra_metadata_.begin(), extra_metadata_.end());
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

Status Session::FillHeader(FileHeader* h) const {
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
  if (ChromaUpsamplingOf() == ChromaUpsampling::kBilinear) h->tools |= kToolChromaBilinear;
  if (s_.masks) h->tools |= kToolMasks;
  if (s_.key_interval > 1) h->tools |= kToolMotionInterpolation;
  if (s_.motion_coder == MotionCoder::kZstd) h->tools |= kToolMotionZstd;
  if (model_.quantisation.quantised) h->tools |= kToolQuantisedModel;
  if (s_.surface) h->tools |= kToolSurface;
  if (s_.texture_chunks && s_.texture_codec != TextureCodec::kPredictive) {
    h->tools |= kToolTextureChunks;
  }
  h->format_version = RequiredFormatVersion(h->tools, s_.mask_coding);
  // The lowest level whose limits hold the stream.
  for (const LevelLimits& l : AllLevels()) {
    h->level = l.level;
    if (ValidateFileHeader(*h).ok() && ValidateBodyModel(model_, &l).ok()) return Status::Ok();
  }
  const Status header = ValidateFileHeader(*h);
  return InvalidArgument(
      "no level holds this stream: " +
      (header.ok() ? ValidateBodyModel(model_, &AllLevels().back()).message() : header.message()));
}

// Codes the `frames` frames held for the current time span: one block per
// camera group.
// The frame's seamless texture joins the static one; the best-facing camera
// of every texel is kept for the fallback.
void Session::AddToStaticTexture(uint32_t slot, const std::vector<Eigen::Vector3f>& positions) {
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
  if (!static_fixed_ || !span_labels_.empty()) {
    std::vector<int16_t> labels =
        BestCameraLabels(map_, model_.mesh, positions, cameras_, textures);
    std::vector<uint8_t> blend = BlendSeamless(textures, labels);
    if (!static_fixed_) static_->Add(blend, labels);
    if (!span_labels_.empty())
      span_seamless_[slot] = std::move(blend), span_labels_[slot] = std::move(labels);
  }
  if (AppliesFills()) {
    span_fallback_[slot] = BestCameraLabels(map_, model_.mesh, positions, cameras_, facing);
  }
  sum_.seamless_s += Since(t0);
}

// Texels of the span's frames that no camera saw take the colour of the
// nearest frames that saw them, else the static texture's, in their
// best-facing camera.
void Session::ApplyFallback(uint32_t frames) {
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  if (!span_labels_.empty()) {
    sum_.temporal_fill_texels += FillFromNearestFrames(
        frames, sum_.cameras, texels, map_.texel, span_seamless_, span_labels_, span_fallback_,
        s_.temporal_fill_frames, span_rgb_.data(), span_mask_.data());
  }

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
  if (!mirror_.empty()) FillFromMirrors(frames);
}

// Texels no camera has seen in any frame so far, deep inside what the
// cameras missed, take their mirror's colour as the frame's seamless texture
// holds it, in their best-facing camera.
void Session::FillFromMirrors(uint32_t frames) {
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  const uint32_t gap = MirrorFillGap(s_.atlas_size);
  std::vector<uint8_t> held(texels), seen(texels);
  for (uint32_t t = 0; t < frames; ++t) {
    if (span_labels_[t].empty()) continue;
    std::fill(held.begin(), held.end(), 0);
    for (uint32_t c = 0; c < sum_.cameras; ++c) {
      const uint8_t* mask = &span_mask_[(size_t(t) * sum_.cameras + c) * texels];
      for (size_t i = 0; i < texels; ++i) held[i] |= mask[i] != 0;
    }
    for (size_t i = 0; i < texels; ++i) seen[i] = span_labels_[t][i] >= 0;
    for (const auto& [entry, other] : MirrorFillTargets(map_, mirror_, held, seen, gap)) {
      const uint32_t texel = map_.texel[entry], from = map_.texel[other];
      const int16_t camera = span_fallback_[t][texel];
      if (camera < 0) continue;
      const size_t plane = size_t(t) * sum_.cameras + uint32_t(camera);
      std::copy_n(&span_seamless_[t][size_t(from) * 3], 3,
                  &span_rgb_[(plane * texels + texel) * 3]);
      span_mask_[plane * texels + texel] = 1;
      ++sum_.mirror_fill_texels;
    }
  }
}

void Session::FillForPlayers(uint32_t frames) {
  const size_t texels = size_t(s_.atlas_size) * s_.atlas_size;
  const uint32_t n = sum_.cameras;
  std::vector<Eigen::Vector3f> centres;
  for (const Camera& c : cameras_) centres.push_back(CameraCentre(c).cast<float>());
  std::vector<uint64_t> offered(frames, 0), left(frames, 0);
  pool_.Run(frames, [&](uint32_t t) {
    const size_t first = size_t(t) * n * texels;
    const bool shares = s_.least_blend_share > 0 && !span_positions_[t].empty();
    const std::vector<Eigen::Vector3f>& positions = span_positions_[t];
    const std::vector<Eigen::Vector3f>& normals = span_normals_[t];
    std::vector<Eigen::Vector3f> to_camera(n);
    std::vector<double> weight(n);  // each camera's facing weight (BlendFacingWeight)
    std::vector<uint8_t> takes(n);
    for (size_t e = 0; e < map_.texel.size(); ++e) {
      const uint32_t texel = map_.texel[e];
      int sum[3] = {0, 0, 0}, count = 0, unseen = 0;
      for (uint32_t c = 0; c < n; ++c) {
        const size_t i = first + c * texels + texel;
        takes[c] = span_usable_[i];
        unseen += !span_mask_[i] && span_usable_[i];
        if (!span_mask_[i]) continue;
        for (int k = 0; k < 3; ++k) sum[k] += span_rgb_[i * 3 + k];
        ++count;
      }
      if (!unseen) continue;
      offered[t] += unseen;
      if (shares && count > 0) {
        Eigen::Vector3f p, nrm;
        TexelSurfacePoint(map_, model_.mesh.triangles, positions, normals, e, &p, &nrm);
        for (uint32_t c = 0; c < n; ++c) {
          to_camera[c] = (centres[c] - p).normalized();
          weight[c] = BlendFacingWeight(nrm.dot(to_camera[c]));
        }
      }
      for (uint32_t c = 0; c < n; ++c) {
        const size_t i = first + c * texels + texel;
        if (span_mask_[i] || !span_usable_[i]) continue;
        // Nothing to show, or a colour that barely shows from any viewpoint:
        // left to the codec's fill.
        if (count == 0 ||
            (shares && LargestBlendShareOfWeights(c, n, to_camera.data(), weight.data(),
                                                  takes.data()) < s_.least_blend_share)) {
          span_usable_[i] = 0;
          ++left[t];
          continue;
        }
        for (int k = 0; k < 3; ++k) span_rgb_[i * 3 + k] = uint8_t((sum[k] + count / 2) / count);
      }
    }
  });
  for (uint32_t t = 0; t < frames; ++t) {
    sum_.player_texels += offered[t];
    sum_.player_texels_left += left[t];
  }
}

}  // namespace encoding
}  // namespace fvv
