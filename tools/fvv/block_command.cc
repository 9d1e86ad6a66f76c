#include "tools/fvv/block_command.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/thread_pool.h"
#include "codec/block_codec.h"
#include "codec/block_syntax.h"
#include "codec/colour.h"
#include "conformance/sample/sample_volume.h"
#include "encoder/io/image_io.h"
#include "tools/fvv/codec_options.h"

namespace fvv {
namespace {

constexpr uint64_t kMaxBlockFileBytes = uint64_t{1} << 31;

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

int Fail(const Status& s) {
  std::fprintf(stderr, "fvv: %s\n", s.ToString().c_str());
  return 1;
}

std::string ViewName(const std::string& dir, const char* stem, uint32_t t, uint32_t c,
                     const char* ext) {
  char name[64];
  std::snprintf(name, sizeof(name), "/%s_t%03u_c%02u.%s", stem, t, c, ext);
  return dir + name;
}

// Reads frames x cameras images (ordered frame-major: all cameras of frame 0
// first) into one interleaved RGB buffer, checking they share one size.
Status LoadStack(const std::vector<std::string>& paths, uint32_t frames, uint32_t cameras,
                 Shape4D* shape, std::vector<uint8_t>* rgb) {
  for (size_t i = 0; i < paths.size(); ++i) {
    FVV_ASSIGN_OR_RETURN(Image img, ReadImage(paths[i]));
    if (i == 0) {
      shape->n = {frames, cameras, img.height, img.width};
      if (shape->count() > (uint64_t{1} << 30))
        return LimitExceeded("a block of " + shape->ToString() + " is too large");
      rgb->resize(shape->count() * 3);
    } else if (img.width != shape->width() || img.height != shape->height()) {
      return InvalidArgument(
          paths[i] + " is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
          ", but " + paths[0] + " is " + std::to_string(shape->width()) + "x" +
          std::to_string(shape->height()) + ": all images of a block must have one size");
    }
    const size_t texels = size_t{img.width} * img.height;
    uint8_t* dst = rgb->data() + i * texels * 3;
    for (size_t k = 0; k < texels; ++k)
      for (int c = 0; c < 3; ++c)
        dst[3 * k + c] = img.pixels[k * img.channels + (img.channels == 3 ? c : 0)];
  }
  return Status::Ok();
}

Status LoadMasks(const std::vector<std::string>& paths, const Shape4D& shape, UsedMask* mask) {
  if (paths.size() != size_t{shape.frames()} * shape.cameras())
    return InvalidArgument(std::to_string(paths.size()) + " mask images given for " +
                           std::to_string(size_t{shape.frames()} * shape.cameras()) + " views");
  mask->assign(shape.count(), 0);
  const size_t texels = size_t{shape.width()} * shape.height();
  for (size_t i = 0; i < paths.size(); ++i) {
    FVV_ASSIGN_OR_RETURN(Image img, ReadImage(paths[i]));
    if (img.width != shape.width() || img.height != shape.height())
      return InvalidArgument("mask " + paths[i] + " does not match the image size");
    for (size_t k = 0; k < texels; ++k) (*mask)[i * texels + k] = img.pixels[k * img.channels] != 0;
  }
  return Status::Ok();
}

double RgbPsnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, const UsedMask* mask) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.size() / 3; ++i) {
    if (mask && !(*mask)[i]) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = static_cast<double>(a[3 * i + c]) - b[3 * i + c];
      sum += d * d;
    }
    n += 3;
  }
  return PsnrFromMse(n ? sum / n : 0);
}

struct EncodeArgs {
  std::vector<std::string> inputs, masks;
  std::string output;
  uint32_t frames = 0, cameras = 1;
  CodecOptionArgs codec;
  double bpp = 0, psnr = 0;
  uint64_t bytes = 0;
  bool lossless = false, no_prune = false;
  unsigned threads = 0;
  int fill_iterations = FillOptions{}.iterations;
};

int RunEncode(const EncodeArgs& a) {
  const uint32_t views = static_cast<uint32_t>(a.inputs.size());
  uint32_t frames = a.frames ? a.frames : views / std::max(1u, a.cameras);
  if (a.cameras == 0 || size_t{frames} * a.cameras != views)
    return Fail(
        InvalidArgument(std::to_string(views) + " images cannot form " + std::to_string(frames) +
                        " frames x " + std::to_string(a.cameras) +
                        " cameras (give --frames and --cameras whose product is the image count)"));
  const int targets = (a.bpp > 0) + (a.bytes > 0) + (a.psnr > 0) + a.lossless;
  if (targets > 1)
    return Fail(InvalidArgument("give at most one of --bpp, --bytes, --psnr, --lossless"));

  EncodeSettings settings;
  settings.kernel = a.codec.Kernel();
  settings.frac_bits_97 = a.codec.precision_97;
  settings.coder = a.codec.Coder();
  settings.weights = a.codec.Weights();
  settings.fill.iterations = a.fill_iterations;
  settings.prune_isolated = !a.no_prune;
  if (a.lossless) {
    settings.rate_mode = RateMode::kLossless;
    if (settings.kernel == WaveletKernel::kCdf97) settings.kernel = WaveletKernel::kLeGall53;
  } else if (a.bytes > 0) {
    settings.rate_mode = RateMode::kTotalBytes;
    settings.rate_value = static_cast<double>(a.bytes);
  } else if (a.psnr > 0) {
    settings.rate_mode = RateMode::kPsnr;
    settings.rate_value = a.psnr;
  } else {
    settings.rate_mode = RateMode::kBitsPerSample;
    settings.rate_value = a.bpp > 0 ? a.bpp : 0.25;
  }
  ThreadPool pool(a.threads);
  settings.runner = pool.runner();

  const auto t_load = std::chrono::steady_clock::now();
  Shape4D shape;
  std::vector<uint8_t> rgb;
  Status s = LoadStack(a.inputs, frames, a.cameras, &shape, &rgb);
  if (!s.ok()) return Fail(s);
  UsedMask mask;
  if (!a.masks.empty()) {
    s = LoadMasks(a.masks, shape, &mask);
    if (!s.ok()) return Fail(s);
  }
  const UsedMask* mask_ptr = a.masks.empty() ? nullptr : &mask;
  const ColourSpace colour = a.lossless ? ColourSpace::kRct : ColourSpace::kYCbCr601;
  const ChromaFormat chroma = a.codec.Chroma();
  if (a.lossless && chroma != ChromaFormat::k444)
    return Fail(InvalidArgument("--lossless needs --chroma 444"));
  const int sample_frac = UsableSampleFrac(settings.kernel, settings.frac_bits_97, settings.weights,
                                           a.codec.sample_bits);
  const Block block = BlockFromRgb(rgb.data(), shape, colour, chroma, sample_frac);
  std::fprintf(stderr, "fvv block encode: %s, kernel %s, coder %s, loaded in %.2f s\n",
               shape.ToString().c_str(), KernelName(settings.kernel), CoderName(settings.coder),
               Seconds(t_load));

  const auto t_enc = std::chrono::steady_clock::now();
  EncodeReport report;
  auto encoded = EncodeBlock(block, mask_ptr, settings, &report);
  if (!encoded.ok()) return Fail(encoded.status());
  const double enc_s = Seconds(t_enc);
  const std::vector<uint8_t> file = WriteBlockFile(*encoded);
  s = WriteFileAtomic(a.output, file.data(), file.size());
  if (!s.ok()) return Fail(s);

  // Verify by decoding, and report quality over used texels.
  const auto t_dec = std::chrono::steady_clock::now();
  auto decoded = DecodeBlock(*encoded, DecodeBudget{}, settings.runner);
  if (!decoded.ok()) return Fail(decoded.status());
  const double dec_s = Seconds(t_dec);
  std::vector<uint8_t> out_rgb(rgb.size());
  BlockToRgb(*decoded, out_rgb.data());
  const double samples = static_cast<double>(shape.count());
  const double bpp = encoded->total_bytes() * 8.0 / samples;
  std::printf("wrote %s: %llu bytes (Y %llu, U %llu, V %llu), %.4f bpp, ratio %.1f:1\n",
              a.output.c_str(), static_cast<unsigned long long>(file.size()),
              static_cast<unsigned long long>(report.channel_bytes[0]),
              static_cast<unsigned long long>(report.channel_bytes[1]),
              static_cast<unsigned long long>(report.channel_bytes[2]), bpp, 24.0 / bpp);
  std::printf(
      "PSNR over %s texels: RGB %.2f dB, Y %.2f dB; encode %.2f s (%.1f Msamples/s), "
      "decode %.3f s (%.1f Msamples/s)\n",
      mask_ptr ? "used" : "all", RgbPsnr(rgb, out_rgb, mask_ptr),
      PsnrFromMse(ChannelMse(block.channels[0], decoded->channels[0], mask_ptr, sample_frac)),
      enc_s, samples / enc_s / 1e6, dec_s, samples / dec_s / 1e6);
  return 0;
}

struct DecodeArgs {
  std::string input, output_dir, format = "png";
  uint64_t bytes = 0;
  double max_ms = 0;
  unsigned threads = 0;
  // The memory a block takes follows from its header, not its size on disk: a
  // few hundred bytes may declare 2^30 samples (12 GB of coefficients).
  uint64_t max_samples = uint64_t{1} << 27;
};

int RunDecode(const DecodeArgs& a) {
  auto data = ReadFileBytes(a.input, kMaxBlockFileBytes);
  if (!data.ok()) return Fail(data.status());
  auto encoded = ReadBlockFile(data->data(), data->size());
  if (!encoded.ok())
    return Fail(Status(encoded.status().code(), a.input + ": " + encoded.status().message()));
  if (encoded->params.shape.count() > a.max_samples) {
    return Fail(LimitExceeded(a.input + ": a block of " + encoded->params.shape.ToString() + ", " +
                              std::to_string(encoded->params.shape.count()) +
                              " samples, is above --max-samples " + std::to_string(a.max_samples)));
  }
  ThreadPool pool(a.threads);
  DecodeBudget budget;
  budget.max_bytes = a.bytes;
  budget.max_ms = a.max_ms;
  DecodeReport report;
  auto block = DecodeBlock(*encoded, budget, pool.runner(), &report);
  if (!block.ok()) return Fail(block.status());
  Status s = MakeDirectories(a.output_dir);
  if (!s.ok()) return Fail(s);
  const Shape4D& shape = block->shape();
  std::vector<uint8_t> rgb(shape.count() * 3);
  BlockToRgb(*block, rgb.data());
  const size_t view = size_t{shape.width()} * shape.height() * 3;
  for (uint32_t t = 0; t < shape.frames(); ++t)
    for (uint32_t c = 0; c < shape.cameras(); ++c) {
      Image img;
      img.width = shape.width();
      img.height = shape.height();
      img.channels = 3;
      const uint8_t* src = rgb.data() + (size_t{t} * shape.cameras() + c) * view;
      img.pixels.assign(src, src + view);
      s = WriteImage(ViewName(a.output_dir, "view", t, c, a.format.c_str()), img);
      if (!s.ok()) return Fail(s);
    }
  std::printf(
      "decoded %s in %.1f ms: read %llu of %llu bytes, bitplanes Y %d U %d V %d, %s -> %s\n",
      shape.ToString().c_str(), report.ms, static_cast<unsigned long long>(report.bytes_read),
      static_cast<unsigned long long>(encoded->total_bytes()), report.planes_completed[0],
      report.planes_completed[1], report.planes_completed[2],
      report.complete ? "complete" : (report.hit_deadline ? "stopped at time budget" : "truncated"),
      a.output_dir.c_str());
  return 0;
}

struct SampleArgs {
  std::string output_dir;
  uint32_t frames = 4, cameras = 4, width = 256, height = 256;
};

int RunSample(const SampleArgs& a) {
  Status s = MakeDirectories(a.output_dir);
  if (!s.ok()) return Fail(s);
  for (uint32_t t = 0; t < a.frames; ++t)
    for (uint32_t c = 0; c < a.cameras; ++c) {
      s = WritePng(ViewName(a.output_dir, "view", t, c, "png"),
                   SampleView(t, c, a.width, a.height));
      if (s.ok())
        s = WritePng(ViewName(a.output_dir, "mask", t, c, "png"),
                     SampleMask(t, c, a.width, a.height));
      if (!s.ok()) return Fail(s);
    }
  std::printf("wrote %u views and masks of %ux%u (frames x cameras = %u x %u) to %s\n",
              a.frames * a.cameras, a.width, a.height, a.frames, a.cameras, a.output_dir.c_str());
  return 0;
}

}  // namespace

void AddBlockCommands(CLI::App* app, int* exit_code) {
  CLI::App* block =
      app->add_subcommand("block", "The texture codec alone: code images as one 4D block");
  block->require_subcommand(1);

  auto enc = std::make_shared<EncodeArgs>();
  CLI::App* e = block->add_subcommand(
      "encode",
      "Code a stack of PNG/EXR images of one size (frame-major: all cameras of frame 0 "
      "first) as one 4D block (frames x cameras x height x width)");
  e->add_option("images", enc->inputs, "Input images (PNG or EXR)")
      ->required()
      ->check(CLI::ExistingFile);
  e->add_option("-o,--output", enc->output, "Output block file (.fvb)")->required();
  e->add_option("--frames", enc->frames, "Frames in the block (default: images / cameras)");
  e->add_option("--cameras", enc->cameras, "Cameras in the block")->capture_default_str();
  AddCodecOptions(e, &enc->codec, false);
  e->add_option("--bpp", enc->bpp, "Target bits per texel, all channels together (default 0.25)")
      ->check(CLI::PositiveNumber);
  e->add_option("--bytes", enc->bytes, "Target total bytes")->check(CLI::PositiveNumber);
  e->add_option("--psnr", enc->psnr, "Target PSNR in dB (RGB-weighted YUV, over used texels)")
      ->check(CLI::PositiveNumber);
  e->add_flag("--lossless", enc->lossless, "Lossless (reversible colour, 5/3 or Haar kernel)");
  e->add_option("--mask", enc->masks, "Used-texel masks, one per image (non-zero = used)")
      ->check(CLI::ExistingFile);
  AddFillOption(e, &enc->fill_iterations);
  AddPruneOption(e, &enc->no_prune);
  e->add_option("--threads", enc->threads, "Worker threads (0 = all cores)")->capture_default_str();
  e->callback([enc, exit_code] { *exit_code = RunEncode(*enc); });

  auto dec = std::make_shared<DecodeArgs>();
  CLI::App* d =
      block->add_subcommand("decode", "Decode a block file to images, optionally truncated");
  d->add_option("input", dec->input, "Block file (.fvb)")->required()->check(CLI::ExistingFile);
  d->add_option("-o,--output", dec->output_dir, "Output directory (view_tTTT_cCC.png)")->required();
  d->add_option("--bytes", dec->bytes, "Decode at most this many bytes (all channels together)");
  d->add_option("--max-ms", dec->max_ms, "Stop SPIHT decoding after this many milliseconds");
  d->add_option("--max-samples", dec->max_samples,
                "Refuse blocks of more samples per channel (about 15 bytes of memory each)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 30))
      ->capture_default_str();
  d->add_option("--format", dec->format, "Image format")
      ->check(CLI::IsMember({"png", "exr"}))
      ->capture_default_str();
  d->add_option("--threads", dec->threads, "Worker threads (0 = all cores)")->capture_default_str();
  d->callback([dec, exit_code] { *exit_code = RunDecode(*dec); });

  auto smp = std::make_shared<SampleArgs>();
  CLI::App* s = block->add_subcommand(
      "sample", "Write the built-in multi-view test volume (views and masks)");
  s->add_option("-o,--output", smp->output_dir, "Output directory")->required();
  s->add_option("--frames", smp->frames, "Frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  s->add_option("--cameras", smp->cameras, "Cameras")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  s->add_option("--width", smp->width, "Width")->capture_default_str()->check(CLI::Range(1, 8192));
  s->add_option("--height", smp->height, "Height")
      ->capture_default_str()
      ->check(CLI::Range(1, 8192));
  s->callback([smp, exit_code] { *exit_code = RunSample(*smp); });
}

}  // namespace fvv
