#include "container/file_header.h"

#include <cstdio>
#include <string>

namespace fvv {

const char* CodingToolName(uint32_t tool_bit) {
  switch (tool_bit) {
    case kToolHaar:
      return "haar";
    case kToolLeGall53:
      return "53";
    case kToolCdf97:
      return "97";
    case kToolSpihtBinary:
      return "spiht-binary";
    case kToolSpihtArith:
      return "spiht-arith";
    case kToolChroma420:
      return "chroma-420";
    case kToolReversibleColour:
      return "rct";
    case kToolMasks:
      return "masks";
    case kToolVertexVisibility:
      return "vertex-visibility";
    case kToolMotionInterpolation:
      return "motion-interpolation";
    case kToolMotionZstd:
      return "motion-zstd";
    case kToolPredictiveTexture:
      return "predictive-texture";
    case kToolSpihtArith2:
      return "spiht-arith2";
    case kToolSpihtArith3:
      return "spiht-arith3";
    case kToolQuadtreeArith4:
      return "quadtree-arith4";
    case kToolChromaBilinear:
      return "chroma-bilinear";
    case kToolQuantisedModel:
      return "quantised-model";
    case kToolOwnBandWeights:
      return "own-band-weights";
    case kToolSamplePrecision:
      return "sample-precision";
    case kToolTexturePrecision:
      return "texture-precision";
    case kToolTextureChunks:
      return "texture-chunks";
    case kToolSurface:
      return "surface";
    default:
      return "unknown";
  }
}

const std::vector<LevelLimits>& AllLevels() {
  // Level n doubles the atlas side of level n-1; GOP samples stay within the
  // codec's 2^30 and fragments within what a player buffers comfortably.
  static const std::vector<LevelLimits> levels = {
      {1, 512, 8, 8, 8, 512ull * 512 * 64, 512ull * 512 * 8 * 30, 8ull << 20, 64, 65536, 131072},
      {2, 1024, 16, 16, 16, 1024ull * 1024 * 64, 1024ull * 1024 * 16 * 30, 32ull << 20, 128, 262144,
       524288},
      {3, 2048, 32, 16, 32, 2048ull * 2048 * 64, 2048ull * 2048 * 32 * 30, 128ull << 20, 256,
       1048576, 2097152},
      {4, 4096, 64, 32, 64, 4096ull * 4096 * 64, 4096ull * 4096 * 64 * 60, 512ull << 20, 256,
       1048576, 2097152},
  };
  return levels;
}

const LevelLimits* FindLevel(uint8_t level) {
  for (const auto& l : AllLevels()) {
    if (l.level == level) return &l;
  }
  return nullptr;
}

uint16_t RequiredFormatVersion(uint32_t tools) {
  if (tools & kToolSurface) return 12;
  if (tools & kToolTextureChunks) return 11;
  if (tools & kToolQuantisedModel) return 10;
  if (tools & kToolChromaBilinear) return 9;
  if (tools & kToolQuadtreeArith4) return 8;
  if (tools & kToolSamplePrecision) return 7;
  if (tools & kToolOwnBandWeights) return 6;
  if (tools & kToolSpihtArith3) return 5;
  if (tools & kToolSpihtArith2) return 4;
  if (tools & kToolTexturePrecision) return 3;
  return (tools & kToolPredictiveTexture) ? 2 : 1;
}

uint32_t ProfileTools(Profile profile) { return profile == Profile::kMain ? kAllKnownTools : 0; }

const LevelLimits& LimitsOf(const FileHeader& h) { return *FindLevel(h.level); }

Status CheckGopSamplesClaim(const FileHeader& h, uint64_t max_gop_samples) {
  const uint64_t samples = uint64_t{h.atlas_width} * h.atlas_height * h.gop_frames * h.gop_cameras;
  if (max_gop_samples == 0 || samples <= max_gop_samples) return Status::Ok();
  return LimitExceeded("file header: GOPs of " + std::to_string(samples) +
                       " samples, more than this decoder holds (" +
                       std::to_string(max_gop_samples) + "; SPEC.md 5.1)");
}

std::vector<uint8_t> WriteFileHeaderBox(const FileHeader& h) {
  ByteWriter w;
  w.U16(h.format_version);
  w.U8(static_cast<uint8_t>(h.profile));
  w.U8(h.level);
  w.U32(h.tools);
  w.U32(h.frame_rate_num);
  w.U32(h.frame_rate_den);
  w.U32(h.frame_count);
  w.U16(h.camera_count);
  w.U16(h.atlas_width);
  w.U16(h.atlas_height);
  w.U16(h.gop_frames);
  w.U16(h.gop_cameras);
  w.U64(h.index_offset);
  return MakeBox(box::kFileHeader, 0, kBoxFlagEssential, w.bytes());
}

Status ValidateFileHeader(const FileHeader& h) {
  const std::string at = "file header: ";
  if (h.format_version == 0 || h.format_version > kFormatVersion) {
    return Unsupported(at + "format version " + std::to_string(h.format_version) +
                       " (this decoder reads version " + std::to_string(kFormatVersion) + ")");
  }
  if (h.profile != Profile::kMain) {
    return Unsupported(at + "unknown profile " + std::to_string(int(h.profile)));
  }
  const LevelLimits* lim = FindLevel(h.level);
  if (lim == nullptr) return Unsupported(at + "unknown level " + std::to_string(h.level));
  if ((h.tools & ~kAllKnownTools) != 0) {
    char bits[16];
    std::snprintf(bits, sizeof(bits), "0x%x", static_cast<unsigned>(h.tools & ~kAllKnownTools));
    return Unsupported(at + "unknown coding tools " + bits);
  }
  if ((h.tools & ~ProfileTools(h.profile)) != 0) {
    return LimitExceeded(at + "tools outside the profile");
  }
  if (RequiredFormatVersion(h.tools) > h.format_version) {
    // A version 1 decoder would not know the bit; this one knows it is newer.
    return Corrupt(at + "tools of format version " +
                   std::to_string(RequiredFormatVersion(h.tools)) + " in a version " +
                   std::to_string(h.format_version) + " stream");
  }
  if ((h.tools & kToolPredictiveTexture) && !(h.tools & kToolMasks)) {
    return Corrupt(at + "predictive texture without masks (its supports are the masks)");
  }
  if ((h.tools & kToolSamplePrecision) && !(h.tools & kToolOwnBandWeights)) {
    return Corrupt(at +
                   "sample-precision declared without own-band-weights ('texr' version 3 "
                   "extends version 2)");
  }
  if ((h.tools & kToolOwnBandWeights) && (h.tools & kToolPredictiveTexture)) {
    return Corrupt(at +
                   "own-band-weights declared with predictive texture (it sets the weights "
                   "of 'texr')");
  }
  if ((h.tools & kToolChromaBilinear) &&
      (!(h.tools & kToolChroma420) || (h.tools & kToolPredictiveTexture))) {
    return Corrupt(at +
                   "chroma-bilinear declared without 4:2:0 SPIHT texture (it sets how 'texr' "
                   "4:2:0 chroma is upsampled)");
  }
  if ((h.tools & kToolTexturePrecision) &&
      (!(h.tools & kToolCdf97) || (h.tools & kToolPredictiveTexture))) {
    return Corrupt(at +
                   "texture-precision declared without 9/7 SPIHT texture (it sets the "
                   "9/7's sample precision in 'texr')");
  }
  if ((h.tools & kToolTextureChunks) && (h.tools & kToolPredictiveTexture)) {
    return Corrupt(at +
                   "texture-chunks declared with predictive texture (it lays out the 'texr' "
                   "channel streams in chunks)");
  }
  if ((h.tools & kToolSurface) && !(h.tools & kToolTextureChunks)) {
    return Corrupt(at +
                   "surface declared without texture-chunks (its values travel in the "
                   "texture's chunks)");
  }
  if (h.frame_rate_num == 0 || h.frame_rate_den == 0) {
    return Corrupt(at + "frame rate " + std::to_string(h.frame_rate_num) + "/" +
                   std::to_string(h.frame_rate_den) + " is not positive");
  }
  if (h.fps() > 240) return LimitExceeded(at + "frame rate above 240 fps");
  if (h.camera_count == 0) return Corrupt(at + "camera count is 0");
  if (h.atlas_width == 0 || h.atlas_height == 0) return Corrupt(at + "atlas size is 0");
  if (h.gop_frames == 0 || h.gop_cameras == 0) return Corrupt(at + "GOP shape has a 0 axis");
  const std::string lv = " (level " + std::to_string(h.level) + " allows ";
  if (h.atlas_width > lim->max_atlas_side || h.atlas_height > lim->max_atlas_side) {
    return LimitExceeded(at + "atlas " + std::to_string(h.atlas_width) + "x" +
                         std::to_string(h.atlas_height) + lv + std::to_string(lim->max_atlas_side) +
                         ")");
  }
  if (h.camera_count > lim->max_cameras) {
    return LimitExceeded(at + std::to_string(h.camera_count) + " cameras" + lv +
                         std::to_string(lim->max_cameras) + ")");
  }
  if (h.gop_frames > lim->max_gop_frames || h.gop_cameras > lim->max_gop_cameras) {
    return LimitExceeded(at + "GOP " + std::to_string(h.gop_frames) + "x" +
                         std::to_string(h.gop_cameras) + lv + std::to_string(lim->max_gop_frames) +
                         "x" + std::to_string(lim->max_gop_cameras) + ")");
  }
  const uint64_t texels = uint64_t{h.atlas_width} * h.atlas_height;
  if (texels * h.gop_frames * h.gop_cameras > lim->max_gop_samples) {
    return LimitExceeded(at + "GOP samples" + lv + std::to_string(lim->max_gop_samples) + ")");
  }
  const double rate = double(texels) * h.camera_count * h.fps();
  if (rate > double(lim->max_samples_per_second)) {
    return LimitExceeded(at + "samples per second " + std::to_string(uint64_t(rate)) + lv +
                         std::to_string(lim->max_samples_per_second) + ")");
  }
  return Status::Ok();
}

Status ReadFileHeader(const BoxHeader& box, const uint8_t* payload, FileHeader* h) {
  if (box.version != 0) {
    return Unsupported(BoxContext(box) + "version " + std::to_string(box.version) +
                       " (this decoder reads version 0)");
  }
  ByteReader r(payload, box.payload_bytes());
  h->format_version = r.U16();
  h->profile = static_cast<Profile>(r.U8());
  h->level = r.U8();
  h->tools = r.U32();
  h->frame_rate_num = r.U32();
  h->frame_rate_den = r.U32();
  h->frame_count = r.U32();
  h->camera_count = r.U16();
  h->atlas_width = r.U16();
  h->atlas_height = r.U16();
  h->gop_frames = r.U16();
  h->gop_cameras = r.U16();
  h->index_offset = r.U64();
  FVV_RETURN_IF_ERROR(CheckFullyRead(r, box));
  return ValidateFileHeader(*h);
}

}  // namespace fvv
