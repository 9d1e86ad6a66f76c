#include "tools/fvv/encode_command.h"

#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "container/surface_displacement.h"
#include "encoder/encode/encoder.h"
#include "encoder/encode/prepared_take.h"
#include "tools/fvv/codec_options.h"
#include "tools/fvv/frame_range.h"
#include "tools/fvv/persons_option.h"
#include "tools/fvv/shard_option.h"
#include "tools/fvv/smooth_option.h"

namespace fvv {
namespace {

struct EncodeArgs {
  std::string capture, output, poses, textures, save_textures, summary_json, frames, static_texture,
      features, prepare, prepared, shard, after;
  uint32_t prepare_frames = EncoderSettings{}.prepare_frames;
  uint32_t warm_up = EncoderSettings{}.track_warm_up;
  CodecOptionArgs codec;
  std::string motion_coder = "arith", texture_codec = "spiht", mask_coder = "mixing";
  bool kernel_given = false, gop_cameras_given = false, atlas_given = false,
       gop_frames_given = false, warm_up_given = false;
  double bpp = 0, psnr = 0;
  double least_blend_share = EncoderSettings{}.least_blend_share;
  uint64_t bytes = 0;
  uint32_t atlas = 512, threads = 2;
  uint16_t gop_frames = 8, gop_cameras = 1, key_interval = 1;
  bool masks = false, no_masks = false, extract = false, fixed_shape = false, quiet = false,
       refine_shape = false, no_fallback = false, no_mirror_fill = false, no_prune = false,
       model_floats = false, whole_texture = false, surface = false, no_occluders = false;
  int surface_step = EncoderSettings{}.surface_step_exponent;
  double surface_prior = EncoderSettings{}.surface_tracking.prior;
  double surface_temporal = EncoderSettings{}.surface_tracking.temporal;
  double surface_stereo = EncoderSettings{}.surface_tracking.stereo;
  std::optional<int> margin;  // by the silhouettes' source
  double agreement = EncoderSettings{}.agreement.max_difference;
  double occluder_clearance = ResampleOptions{}.occluder_clearance;
  double suspect_share = OccluderOptions{}.suspect_share;
  double smooth = TrackCaptureOptions{}.smoothing.sigma_frames;
  int fill_iterations = FillOptions{}.iterations;
  uint32_t temporal_fill = EncoderSettings{}.temporal_fill_frames;
  std::vector<std::string> meta;
  std::string track_cameras = "auto";  // a count, "all", or "auto"
  std::string persons = "auto", models;
};

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

int RunEncode(const EncodeArgs& a) {
  EncoderSettings s;
  s.poses = a.poses;
  s.textures = a.textures;
  s.save_textures = a.save_textures;
  const Status range = ParseFrameRange(a.frames, &s.first_frame, &s.last_frame);
  if (!range.ok()) return Fail(range);
  s.extract_silhouettes = a.extract;
  s.tracker.adapt_shape = !a.fixed_shape;
  StatusOr<uint32_t> track_cameras = ParseTrackingCameras(a.track_cameras);
  if (!track_cameras.ok()) return Fail(track_cameras.status());
  s.track_cameras = *track_cameras;
  s.persons = PersonsSetting(a.persons);
  s.person_models = a.models;
  s.pose_smoothing.sigma_frames = a.smooth;
  s.refine_shape = a.refine_shape;
  s.fallback_texture = !a.no_fallback;
  s.mirror_fill = !a.no_mirror_fill;
  s.temporal_fill_frames = a.temporal_fill;
  s.static_texture = a.static_texture;
  s.features = a.features;
  if (!a.features.empty() && !a.refine_shape) {
    std::fprintf(stderr, "fvv: --features is for --refine-shape\n");
    return 1;
  }
  s.resample.silhouette_margin = a.margin;
  s.agreement.max_difference = a.agreement;
  s.occluders.enabled = !a.no_occluders;
  s.resample.occluder_clearance = a.occluder_clearance;
  s.occluders.suspect_share = a.suspect_share;
  s.atlas_size = a.atlas;
  s.gop_frames = a.gop_frames;
  s.gop_cameras = a.gop_cameras;
  s.kernel = a.codec.Kernel();
  s.frac_bits_97 = a.codec.precision_97;
  s.coder = a.codec.Coder();
  s.weights = a.codec.Weights();
  s.sample_frac = a.codec.sample_bits;
  s.chroma = a.codec.Chroma();
  s.chroma_upsampling = a.codec.Upsampling();
  s.fill.iterations = a.fill_iterations;
  s.prune_isolated = !a.no_prune;
  s.quantise_model = !a.model_floats;
  s.texture_chunks = !a.whole_texture;
  s.surface = a.surface;
  s.surface_step_exponent = static_cast<uint8_t>(a.surface_step);
  s.surface_tracking.prior = a.surface_prior;
  s.surface_tracking.temporal = a.surface_temporal;
  s.surface_tracking.stereo = a.surface_stereo;
  if (a.texture_codec == "predictive") {
    // Its defaults: all cameras in one GOP (it predicts across them) and the
    // 5/3 kernel (better than the 9/7 with BISK: docs/encoder.md).
    s.texture_codec = TextureCodec::kPredictive;
    if (!a.gop_cameras_given) s.gop_cameras = 0;
    if (!a.kernel_given) s.kernel = WaveletKernel::kLeGall53;
  }
  const int targets = (a.bpp > 0) + (a.bytes > 0) + (a.psnr > 0);
  if (targets > 1) return Fail(InvalidArgument("give at most one of --bpp, --bytes, --psnr"));
  if (a.bpp > 0) {
    s.rate_mode = RateMode::kBitsPerSample, s.rate_value = a.bpp;
  } else if (a.bytes > 0) {
    s.rate_mode = RateMode::kTotalBytes, s.rate_value = double(a.bytes);
  } else if (a.psnr > 0) {
    s.rate_mode = RateMode::kPsnr, s.rate_value = a.psnr;
  }
  // The predictive codec's supports are its masks: it codes them unless told not to.
  s.masks = a.masks || (s.texture_codec == TextureCodec::kPredictive && !a.no_masks);
  s.least_blend_share = a.least_blend_share;
  s.mask_coding = MaskCoderFromName(a.mask_coder);
  s.motion_coder = a.motion_coder == "zstd" ? MotionCoder::kZstd : MotionCoder::kArith;
  s.key_interval = a.key_interval;
  s.threads = a.threads;
  s.tracker.threads = a.threads;  // tracking too: a shard of one thread uses one core
  s.metadata = {{"generator", "fvv encode"}, {"capture", a.capture}};
  for (const std::string& kv : a.meta) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      return Fail(InvalidArgument("--meta " + kv + " is not KEY=VALUE"));
    }
    s.metadata.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  if (!a.quiet) {
    s.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  }
  s.prepared = a.prepared;
  s.prepare_frames = a.prepare_frames;
  s.track_warm_up = a.warm_up;
  s.after = a.after;
  if (a.warm_up_given && (a.prepare.empty() || !a.poses.empty())) {
    return Fail(InvalidArgument(
        "--warm-up belongs to --prepare without --poses (shards that track their own frames)"));
  }
  if (!a.prepared.empty() && (!a.atlas_given || !a.gop_frames_given)) {
    // The atlas and GOP length the take was prepared for, unless given.
    StatusOr<PreparedTake> take = LoadPreparedTakeDescription(a.prepared);
    if (!take.ok()) return Fail(take.status());
    if (!a.atlas_given) s.atlas_size = take->atlas_size;
    if (!a.gop_frames_given) s.gop_frames = uint16_t(take->gop_frames);
  }
  if (!a.shard.empty()) {
    const Status shard = ParseShard(a.shard, &s.shard, &s.shards);
    if (!shard.ok()) return Fail(shard);
  }
  if (!a.prepare.empty()) {
    if (!a.output.empty()) return Fail(InvalidArgument("--prepare writes a directory, not -o"));
    StatusOr<PrepareSummary> p = PrepareTake(a.capture, a.prepare, s);
    if (!p.ok()) return Fail(p.status());
    std::printf(
        "prepared take: %s\n  frames %u..%u (%u), %u GOPs of %u frames\n"
        "  static texture from %zu frames, %.1f s\n",
        p->directory.c_str(), p->first_frame, p->first_frame + p->frames - 1, p->frames, p->gops,
        unsigned(s.gop_frames), p->texture_frames.size(), p->seconds);
    if (a.poses.empty()) {
      std::printf(
          "  shards track their own frames, with %u frames' warm-up on each side\n"
          "  next: fvv encode %s --prepared %s --shard K/N -o part_K.fvv, then fvv join\n",
          s.track_warm_up, a.capture.c_str(), p->directory.c_str());
    } else {
      std::printf(
          "  next: fvv encode %s --poses %s --prepared %s --shard K/N -o part_K.fvv, "
          "then fvv join\n",
          a.capture.c_str(), a.poses.c_str(), p->directory.c_str());
    }
    return 0;
  }
  if (a.output.empty()) return Fail(InvalidArgument("-o/--output is required"));
  StatusOr<EncodeSummary> r = EncodeCapture(a.capture, a.output, s);
  if (!r.ok()) return Fail(r.status());
  std::printf("%s", r->Table().c_str());
  if (!a.save_textures.empty()) {
    std::printf("  textures and masks before coding: %s (textures.json describes them)\n",
                a.save_textures.c_str());
  }
  if (!a.summary_json.empty()) {
    const std::string text = r->ToJson();
    const Status w =
        WriteFileAtomic(a.summary_json, reinterpret_cast<const uint8_t*>(text.data()), text.size());
    if (!w.ok()) return Fail(w);
  }
  return 0;
}

}  // namespace

void AddEncodeCommand(CLI::App* app, int* exit_code) {
  auto a = std::make_shared<EncodeArgs>();
  CLI::App* e = app->add_subcommand("encode",
                                    "Encode a capture into a .fvv stream: motion capture, atlas "
                                    "resampling, 4D-SPIHT (or predictive BISK) textures");
  e->footer(
      "Rate: one of --psnr (default 36 dB, weighted YUV over visible texels, per GOP), --bpp "
      "(bits per atlas texel of a GOP block, seen or not) or --bytes (per GOP).\n"
      "Poses: tracked from the capture's silhouettes unless --poses gives them (fvv track's "
      "poses.json, or a synthetic capture's truth.json or directory). --textures encodes atlas "
      "textures made by --save-textures (or by a studio's own pipeline in that layout).\n"
      "Shards (docs/scale-out.md): fvv encode cap --poses p.json --prepare prep/, then on any "
      "machines fvv encode cap --poses p.json --prepared prep/ --shard K/N -o part_K.fvv, then "
      "fvv join part_*.fvv -o cap.fvv. Without --poses, --prepare tracks the actor's shape and "
      "every shard tracks its own frames.\n"
      "Example: fvv encode cap -o cap.fvv --save-textures tex/");
  e->add_option("capture", a->capture, "Capture directory or capture.json")->required();
  e->add_option("-o,--output", a->output, "The .fvv file to write (not with --prepare)");
  e->add_option("--poses", a->poses, "Use these poses instead of tracking");
  e->add_option("--textures", a->textures,
                "Encode these atlas textures and masks (a --save-textures directory)")
      ->check(CLI::ExistingDirectory);
  e->add_option("--save-textures", a->save_textures,
                "Also write the atlas textures and masks before coding (PNG) here");
  e->add_option("--frames", a->frames, "Frame range A:B (default all)");
  e->add_option("--psnr", a->psnr, "Target PSNR in dB");
  e->add_option("--bpp", a->bpp, "Target bits per atlas texel");
  e->add_option("--bytes", a->bytes, "Target bytes per GOP");
  e->add_option("--atlas", a->atlas, "Atlas side in texels (16..4096)")->capture_default_str();
  e->add_option("--gop-frames", a->gop_frames, "Frames per GOP")->capture_default_str();
  e->add_option("--gop-cameras", a->gop_cameras, "Cameras per GOP")->capture_default_str();
  AddCodecOptions(e, &a->codec);
  AddFillOption(e, &a->fill_iterations);
  AddPruneOption(e, &a->no_prune);
  AddTextureCodecOption(e, &a->texture_codec);
  AddMaskCoderOption(e, &a->mask_coder);
  auto* masks =
      e->add_flag("--masks", a->masks, "Code the shape masks (which camera saw which texel)");
  e->add_flag("--no-masks", a->no_masks,
              "Code no shape masks: players take each camera's visibility from the decoded "
              "geometry (depth maps of the posed model)")
      ->excludes(masks);
  e->add_option("--least-blend-share", a->least_blend_share,
                "Without masks: code a texel a camera did not see but a player may take from "
                "it only where that camera can be at least this share of the player's blend "
                "from some viewpoint (0..1; 0 codes them all)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  e->add_flag("--model-floats", a->model_floats,
              "Store the body model as 32-bit floats (what format versions 1 to 9 decoders "
              "read) instead of on a grid (0.12 mm positions, 10-bit normals, 8-bit weights)");
  e->add_flag("--whole-texture", a->whole_texture,
              "Write each fragment's texture as one 'texr' box (what format versions 1 to 10 "
              "decoders read) instead of in chunks, where any prefix of a fragment past its "
              "head decodes (format version 11; a few hundred bytes more per fragment)");
  e->add_flag("--surface", a->surface,
              "Carry the surface of every frame (format version 12): the fitted body moved "
              "along its normals to each frame's silhouettes, so clothing and hair follow the "
              "footage; textures are resampled from it. Players that ignore it draw the fitted "
              "body");
  e->add_option("--surface-step", a->surface_step,
                "With --surface: the displacements' step, 2^-N metres (8: 3.9 mm)")
      ->check(CLI::Range(int(kMinSurfaceStepExponent), int(kMaxSurfaceStepExponent)))
      ->capture_default_str();
  e->add_option("--surface-prior", a->surface_prior,
                "With --surface: how strongly each frame's surface is held to the fitted body "
                "where the silhouettes say little (docs/encoder.md: stronger suits tracked poses)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  e->add_option("--surface-temporal", a->surface_temporal,
                "With --surface: how strongly each frame's surface is held to the previous "
                "frame's (0: not held, though each frame starts from the one before). Default: "
                "by the rig, 0 where it suits stereo and stereo is on, else 1 (docs/encoder.md)")
      ->check(CLI::Range(0.0, 100.0));
  e->add_option("--surface-stereo", a->surface_stereo,
                "With --surface: the weight of stereo (a patch matched between neighbouring "
                "cameras) where no silhouette speaks for the surface (0: silhouettes alone). "
                "Default: by the rig, 10 where every camera has two neighbours within 52 degrees "
                "and a pixel covers under 8 mm at the actor, else 0 (docs/encoder.md)")
      ->check(CLI::Range(0.0, 100.0));
  e->add_option("--motion-coder", a->motion_coder, "Motion track entropy coder")
      ->check(CLI::IsMember({"arith", "zstd"}))
      ->capture_default_str();
  e->add_option("--key-interval", a->key_interval,
                "Motion key-frame interval (> 1: frames between are interpolated)")
      ->capture_default_str();
  e->add_option("--silhouette-margin", a->margin,
                "Pixels the image silhouettes grow by before a camera's samples are taken; "
                "negative shrinks them. Default: " +
                    std::to_string(kSilhouetteMargin) +
                    " for given or subtracted silhouettes; for the person network's masks, minus "
                    "half its mask cell: the person's extent in pixels / " +
                    std::to_string(int(kPersonExtentPerMarginPixel)) +
                    ", at least 1 (their outline pixels hold some of the background: "
                    "docs/encoder.md)")
      ->check(CLI::Range(-32, 32));
  e->add_option("--agreement", a->agreement,
                "Drop a camera's sample of a surface point where every other camera that saw the "
                "point differs from it by more than this many levels (mean over R, G, B): "
                "something stood in front of the actor. 0 (the default) keeps every sample; 40 "
                "is a start (docs/encoder.md)")
      ->check(CLI::Range(0.0, 255.0))
      ->capture_default_str();
  e->add_flag("--no-occluders", a->no_occluders,
              "Sample the actor's surface even where the silhouettes hold something else in "
              "front of it (by default a hull of what else stands there is carved from them, and "
              "what it hides is left out)");
  e->add_option("--occluder-clearance", a->occluder_clearance,
                "Metres something else must stand in front of a surface point to hide it")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  e->add_option("--suspect-share", a->suspect_share,
                "A camera whose silhouette holds more than this share (of what the actor's model "
                "covers) of foreground the model does not explain is checked against the other "
                "cameras in that frame: its samples no other camera's colour backs are dropped (a "
                "person mask that took in someone close in front of that camera). 0: off")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  e->add_flag("--extract", a->extract,
              "Background subtraction even when the capture lists silhouettes");
  e->add_flag("--fixed-shape", a->fixed_shape, "Tracking keeps the generic body's proportions");
  AddPersonsOptions(e, "for tracking and for the textures", &a->persons, &a->models);
  e->add_option("--track-cameras", a->track_cameras,
                "Without --poses: the cameras the fit reads, a count (chosen to see the actor "
                "whole and stand apart), all, or auto (" +
                    std::to_string(kDefaultTrackingCameras) + " of a rig of over " +
                    std::to_string(kAutoTrackingAbove) + ", else all). Every camera is textured")
      ->capture_default_str();
  AddSmoothOption(e, &a->smooth);
  e->add_flag("--no-fallback-texture", a->no_fallback,
              "Leave texels no camera of a frame sees to the codec's fill, instead of the "
              "actor's seamless static texture");
  e->add_option("--temporal-fill", a->temporal_fill,
                "A texel no camera of a frame sees takes the mean colour of the frames of its GOP, "
                "at most this many frames away, that saw it, before the static texture (0: off)")
      ->check(CLI::Range(0u, 100000u))
      ->capture_default_str();
  e->add_flag("--no-mirror-fill", a->no_mirror_fill,
              "After the static texture, leave a texel no camera has seen so far to the fill "
              "from the texels around it, instead of the colour of its mirror on the other side "
              "of the body (where it lies deep inside what the cameras missed)");
  e->add_option("--static-texture", a->static_texture,
                "Also write the actor's static seamless texture (atlas layout) to this image");
  e->add_option("--features", a->features,
                "With --refine-shape: feature points (JSON, joint centres per camera image) for "
                "the refinement's features term")
      ->check(CLI::ExistingFile);
  e->add_flag("--refine-shape", a->refine_shape,
              "Refine the body model's surface to the actor on the first frame (silhouettes, "
              "stereo) before resampling; the stream stores the refined model");
  e->add_option("--prepare", a->prepare,
                "Shards: write the take's shared model and static texture to this directory "
                "and stop (with --poses, the shards use them; without, each shard tracks)");
  e->add_option("--warm-up", a->warm_up,
                "With --prepare and no --poses: frames each shard tracks before and after its "
                "own, so that its poses at the borders are a whole-take run's")
      ->capture_default_str();
  e->add_option("--prepare-frames", a->prepare_frames,
                "With --prepare: frames the static texture averages, spread over the take")
      ->capture_default_str();
  e->add_option("--prepared", a->prepared,
                "Encode with a prepared take (its frames, model, static texture; its atlas size "
                "and GOP frames unless given)");
  e->add_option("--shard", a->shard,
                "With --prepared: encode only shard K of N (K from 0; whole GOPs), a stream "
                "`fvv join` puts together with the others");
  e->add_option("--after", a->after,
                "With --shard K/N of a take prepared without poses: go on from the poses of "
                "this part (K-1) instead of a first-frame search, where fvv join found the two "
                "disagreeing at their border")
      ->check(CLI::ExistingFile);
  e->add_option("--threads", a->threads, "Worker threads")->capture_default_str();
  e->add_option("--meta", a->meta, "Metadata KEY=VALUE (repeatable)");
  e->add_option("--summary-json", a->summary_json, "Also write the summary as JSON here");
  e->add_flag("-q,--quiet", a->quiet, "No per-frame progress");
  e->callback([a, e, exit_code] {
    a->kernel_given = e->count("--kernel") > 0;
    a->gop_cameras_given = e->count("--gop-cameras") > 0;
    a->atlas_given = e->count("--atlas") > 0;
    a->gop_frames_given = e->count("--gop-frames") > 0;
    a->warm_up_given = e->count("--warm-up") > 0;
    *exit_code = RunEncode(*a);
  });
}

}  // namespace fvv
