// The C API of include/fvv/fvv_encoder.h over fvv::EncodeCapture: enum and
// range checks, status codes and messages.
#include <new>
#include <string>

#include "encoder/encode/encoder.h"
#include "fvv/fvv_encoder.h"

struct fvv_encoder {
  fvv::EncoderSettings settings;
  std::string error;
};

namespace {

thread_local std::string g_settings_error;

fvv::Status ToSettings(const fvv_encoder_settings& c, fvv::EncoderSettings* s) {
  using fvv::InvalidArgument;
  if (c.atlas_size < 16 || c.atlas_size > 4096)
    return InvalidArgument("atlas_size is not 16..4096");
  if (c.gop_frames < 1 || c.gop_frames > 65535 || c.gop_cameras > 65535) {
    return InvalidArgument("gop_frames must be 1..65535 and gop_cameras 0..65535");
  }
  if (c.texture_codec > FVV_TEXTURE_PREDICTIVE)
    return InvalidArgument("texture_codec is not an fvv_texture_codec");
  if (c.kernel > FVV_KERNEL_HAAR) return InvalidArgument("kernel is not an fvv_kernel");
  if (c.precision_97 > uint32_t(fvv::kMaxFracBits97) || !fvv::ValidFracBits97(int(c.precision_97)))
    return InvalidArgument("precision_97 is not 2..6");
  if (c.coder > FVV_CODER_ARITH4) return InvalidArgument("coder is not an fvv_entropy_coder");
  if (c.weights > FVV_WEIGHTS_AXIS_BANDS)
    return InvalidArgument("weights is not an fvv_band_weights");
  if (c.sample_bits > uint32_t(fvv::kMaxSampleFrac))
    return InvalidArgument("sample_bits is not 0.." + std::to_string(fvv::kMaxSampleFrac));
  if (c.prune > 1) return InvalidArgument("prune is not 0 or 1");
  if (c.quantise_model > 1) return InvalidArgument("quantise_model is not 0 or 1");
  if (c.texture_chunks > 1) return InvalidArgument("texture_chunks is not 0 or 1");
  if (c.surface > 1) return InvalidArgument("surface is not 0 or 1");
  if (c.surface && !c.texture_chunks) {
    return InvalidArgument(
        "surface needs texture_chunks (the surface rides in the texture's chunks)");
  }
  if (c.occluders > 1) return InvalidArgument("occluders is not 0 or 1");
  if (c.temporal_fill_frames > 100000)
    return InvalidArgument("temporal_fill_frames is over 100000");
  if (!(c.least_blend_share >= 0 && c.least_blend_share <= 1))
    return InvalidArgument("least_blend_share is not 0..1");
  if (c.chroma > FVV_CHROMA_420_NEAREST) return InvalidArgument("chroma is not an fvv_chroma");
  if (c.mask_mode > FVV_MASKS_CODED_V1) return InvalidArgument("mask_mode is not an fvv_mask_mode");
  if (c.rate_mode > FVV_RATE_BYTES_PER_GOP)
    return InvalidArgument("rate_mode is not an fvv_rate_mode");
  if (!(c.rate_value > 0) || c.rate_value > 1e15)
    return InvalidArgument("rate_value must be positive");
  if (c.key_interval < 1 || c.key_interval > 65535)
    return InvalidArgument("key_interval must be 1..65535");
  if (c.threads < 1 || c.threads > 256) return InvalidArgument("threads must be 1..256");
  if (c.first_frame > c.last_frame) return InvalidArgument("first_frame is after last_frame");
  s->atlas_size = c.atlas_size;
  s->gop_frames = uint16_t(c.gop_frames);
  s->gop_cameras = uint16_t(c.gop_cameras);
  static const fvv::WaveletKernel kKernels[] = {
      fvv::WaveletKernel::kCdf97, fvv::WaveletKernel::kLeGall53, fvv::WaveletKernel::kHaar};
  s->kernel = kKernels[c.kernel];
  s->frac_bits_97 = int(c.precision_97);
  s->coder = c.coder == FVV_CODER_BINARY   ? fvv::EntropyCoder::kBinary
             : c.coder == FVV_CODER_ARITH2 ? fvv::EntropyCoder::kNeighbourContexts
             : c.coder == FVV_CODER_ARITH3 ? fvv::EntropyCoder::kSetSignContexts
             : c.coder == FVV_CODER_ARITH4 ? fvv::EntropyCoder::kQuadtree
                                           : fvv::EntropyCoder::kArith;
  s->weights = c.weights == FVV_WEIGHTS_AXIS_BANDS ? fvv::BandWeights::kAxisBands
                                                   : fvv::BandWeights::kOwnBand;
  s->sample_frac = int(c.sample_bits);
  s->prune_isolated = c.prune != 0;
  s->quantise_model = c.quantise_model != 0;
  s->texture_chunks = c.texture_chunks != 0;
  s->surface = c.surface != 0;
  s->occluders.enabled = c.occluders != 0;
  s->temporal_fill_frames = c.temporal_fill_frames;
  s->least_blend_share = c.least_blend_share;
  s->chroma = c.chroma == FVV_CHROMA_444 ? fvv::ChromaFormat::k444 : fvv::ChromaFormat::k420;
  s->chroma_upsampling = c.chroma == FVV_CHROMA_420_NEAREST ? fvv::ChromaUpsampling::kNearest
                                                            : fvv::ChromaUpsampling::kBilinear;
  s->masks = c.mask_mode != FVV_MASKS_NONE;
  s->mask_coding =
      c.mask_mode == FVV_MASKS_CODED_V1 ? fvv::MaskCoding::kContext : fvv::MaskCoding::kMixing;
  s->texture_codec = c.texture_codec == FVV_TEXTURE_PREDICTIVE ? fvv::TextureCodec::kPredictive
                                                               : fvv::TextureCodec::kSpiht4d;
  static const fvv::RateMode kModes[] = {fvv::RateMode::kPsnr, fvv::RateMode::kBitsPerSample,
                                         fvv::RateMode::kTotalBytes};
  s->rate_mode = kModes[c.rate_mode];
  s->rate_value = c.rate_value;
  s->key_interval = uint16_t(c.key_interval);
  s->threads = c.threads;
  s->first_frame = c.first_frame;
  s->last_frame = c.last_frame;
  s->poses = c.poses ? c.poses : "";
  s->textures = c.textures ? c.textures : "";
  s->save_textures = c.save_textures ? c.save_textures : "";
  if (c.progress) {
    auto* fn = c.progress;
    void* user = c.progress_user;
    s->progress = [fn, user](const std::string& line) { fn(user, line.c_str()); };
  }
  s->metadata = {{"generator", "fvv encoder library"}};
  return fvv::Status::Ok();
}

fvv_status Report(fvv_encoder* e, const fvv::Status& s) {
  if (e) e->error = s.ok() ? std::string() : s.ToString();
  return static_cast<fvv_status>(s.code());
}

}  // namespace

extern "C" {

void fvv_encoder_default_settings(fvv_encoder_settings* settings) {
  if (!settings) return;
  *settings = fvv_encoder_settings{};
  settings->atlas_size = 512;
  settings->gop_frames = 8;
  settings->gop_cameras = 1;
  settings->kernel = FVV_KERNEL_CDF97;
  settings->precision_97 = fvv::kFracBits97;
  settings->sample_bits = fvv::kDefaultSampleFrac;
  settings->prune = 1;
  settings->quantise_model = 1;
  settings->texture_chunks = 1;
  settings->surface = 0;
  settings->occluders = fvv::EncoderSettings{}.occluders.enabled ? 1 : 0;
  settings->temporal_fill_frames = fvv::EncoderSettings{}.temporal_fill_frames;
  settings->least_blend_share = fvv::EncoderSettings{}.least_blend_share;
  settings->coder = FVV_CODER_ARITH3;
  settings->chroma = FVV_CHROMA_444;
  settings->mask_mode = FVV_MASKS_NONE;
  settings->texture_codec = FVV_TEXTURE_SPIHT;
  settings->rate_mode = FVV_RATE_PSNR;
  settings->rate_value = 36;
  settings->key_interval = 1;
  settings->threads = 2;
  settings->first_frame = 0;
  settings->last_frame = UINT32_MAX;
}

const char* fvv_encoder_settings_error(void) { return g_settings_error.c_str(); }

fvv_status fvv_encoder_create(const fvv_encoder_settings* settings, fvv_encoder** encoder) {
  g_settings_error.clear();
  if (!encoder) return FVV_INVALID_ARGUMENT;
  *encoder = nullptr;
  fvv_encoder_settings c;
  fvv_encoder_default_settings(&c);
  if (settings) c = *settings;
  fvv::EncoderSettings s;
  const fvv::Status ok = ToSettings(c, &s);
  if (!ok.ok()) {
    g_settings_error = ok.ToString();
    return static_cast<fvv_status>(ok.code());
  }
  *encoder = new (std::nothrow) fvv_encoder{std::move(s), std::string()};
  return *encoder ? FVV_OK : FVV_OUT_OF_MEMORY;
}

void fvv_encoder_destroy(fvv_encoder* encoder) { delete encoder; }

const char* fvv_encoder_error(const fvv_encoder* encoder) {
  return encoder ? encoder->error.c_str() : "";
}

fvv_status fvv_encoder_add_metadata(fvv_encoder* encoder, const char* key, const char* value) {
  if (!encoder) return FVV_INVALID_ARGUMENT;
  if (!key || !*key || !value)
    return Report(encoder, fvv::InvalidArgument("metadata needs a key and a value"));
  encoder->settings.metadata.emplace_back(key, value);
  return Report(encoder, fvv::Status::Ok());
}

fvv_status fvv_encoder_encode_capture(fvv_encoder* encoder, const char* capture, const char* output,
                                      fvv_encode_report* report) {
  if (!encoder) return FVV_INVALID_ARGUMENT;
  if (!capture || !output) {
    return Report(encoder, fvv::InvalidArgument("capture and output paths are required"));
  }
  try {
    fvv::StatusOr<fvv::EncodeSummary> r = fvv::EncodeCapture(capture, output, encoder->settings);
    if (!r.ok()) return Report(encoder, r.status());
    if (report) {
      *report = fvv_encode_report{};
      report->frames = r->frames;
      report->cameras = r->cameras;
      report->atlas_size = r->atlas_size;
      report->gops = r->gops;
      report->level = r->level;
      report->file_bytes = r->file_bytes;
      report->texture_bytes = r->texture_bytes;
      report->mask_bytes = r->mask_bytes;
      report->motion_bytes = r->motion_bytes;
      report->visible_texels = r->visible_texels;
      report->psnr_y = r->psnr[0];
      report->psnr_u = r->psnr[1];
      report->psnr_v = r->psnr[2];
      report->psnr_rgb = r->psnr_rgb;
      report->ratio_atlas = r->ratio_atlas();
      report->ratio_visible = r->ratio_visible();
      report->seconds = r->total_s;
    }
    return Report(encoder, fvv::Status::Ok());
  } catch (const std::bad_alloc&) {
    return Report(encoder, fvv::Status(fvv::StatusCode::kOutOfMemory, "out of memory"));
  }
}

}  // extern "C"
