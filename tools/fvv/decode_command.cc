#include "tools/fvv/decode_command.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "conformance/lib/reference_output.h"
#include "container/writer.h"
#include "encoder/io/image_io.h"
#include "fvv/fvv_decoder.hpp"

namespace fvv {
namespace {

struct DecodeArgs {
  std::string input, output_dir, frames, format = "png";
  uint64_t bytes = 0;
  double max_ms = 0;
  unsigned threads = 0;
};

int Fail(const std::string& message) {
  std::fprintf(stderr, "fvv: %s\n", message.c_str());
  return 1;
}

// "A:B" (inclusive), "A:" or "A".
bool ParseRange(const std::string& s, uint32_t count, uint32_t* first, uint32_t* last) {
  if (s.empty()) {
    *first = 0;
    *last = count - 1;
    return count > 0;
  }
  const size_t colon = s.find(':');
  char* end = nullptr;
  const unsigned long a = std::strtoul(s.c_str(), &end, 10);
  if (end == s.c_str()) return false;
  unsigned long b = a;
  if (colon != std::string::npos) {
    const std::string rest = s.substr(colon + 1);
    b = rest.empty() ? count - 1 : std::strtoul(rest.c_str(), &end, 10);
    if (!rest.empty() && *end != '\0') return false;
  } else if (*end != '\0') {
    return false;
  }
  if (a > b || b >= count) return false;
  *first = static_cast<uint32_t>(a);
  *last = static_cast<uint32_t>(b);
  return true;
}

std::string Name(const std::string& dir, const char* stem, uint32_t f, uint32_t c,
                 const std::string& ext) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "/%s_f%05u_c%02u.%s", stem, f, c, ext.c_str());
  return dir + buf;
}

// Exit status for a stream the decoder rejects: its pinned status code (2..6),
// so conformance runners can check the kind of error; 1 for anything else.
int StreamErrorExit(fvv_status status) {
  return status >= FVV_TRUNCATED && status <= FVV_CHECKSUM_MISMATCH ? static_cast<int>(status) : 1;
}

// --format conformance: the reference decoder's conformance output (SPEC.md
// Annex B), whole stream, for comparing decoders file by file.
int RunConformanceOutput(const DecodeArgs& a) {
  if (!a.frames.empty() || a.max_ms > 0) {
    return Fail(
        "--format conformance decodes whole streams under a byte budget: no --frames or "
        "--max-ms");
  }
  const auto stream = ReadFileBytes(a.input, kMaxConformanceFileBytes);
  if (!stream.ok()) return Fail(stream.status().ToString());
  if (Status s = MakeDirectories(a.output_dir); !s.ok()) return Fail(s.ToString());
  ReferenceDecodeOptions options;
  options.bytes_per_fragment = a.bytes;
  options.threads = a.threads == 0 ? 2 : a.threads;
  size_t files = 0;
  const OutputSink to_dir = DirectorySink(a.output_dir);
  const Status s = ReferenceDecode(stream->data(), stream->size(), options,
                                   [&](const std::string& name, const std::vector<uint8_t>& bytes) {
                                     ++files;
                                     return to_dir(name, bytes);
                                   });
  if (!s.ok()) {
    std::fprintf(stderr, "fvv: %s: %s\n", a.input.c_str(), s.ToString().c_str());
    return s.code() == StatusCode::kIoError ? 1
                                            : StreamErrorExit(static_cast<fvv_status>(s.code()));
  }
  std::printf("wrote the conformance output (%zu files) -> %s\n", files, a.output_dir.c_str());
  return 0;
}

int RunDecode(const DecodeArgs& a) {
  if (a.format == "conformance") return RunConformanceOutput(a);
  fvv_decoder_settings settings;
  fvv_decoder_default_settings(&settings);
  settings.threads = a.threads;
  DecoderPtr dec = MakeDecoder(&settings);
  if (!dec) return Fail("cannot create a decoder");
  if (const fvv_status st = fvv_decoder_open_file(dec.get(), a.input.c_str()); st != FVV_OK) {
    Fail(fvv_decoder_error(dec.get()));
    return StreamErrorExit(st);
  }
  fvv_stream_info info;
  fvv_decoder_get_info(dec.get(), &info);
  // A live stream's header has no frame count: its frames are its fragments'.
  const uint32_t frames =
      info.frame_count != 0 ? info.frame_count : fvv_decoder_frames_available(dec.get());
  uint32_t first, last;
  if (frames == 0) return Fail(a.input + ": the stream has no frames");
  if (!ParseRange(a.frames, frames, &first, &last)) {
    return Fail("--frames " + a.frames +
                ": not a range A:B within 0:" + std::to_string(frames - 1));
  }
  // --bytes is the prefix of each fragment a decoder is given (SPEC.md Annex
  // B.2): with the texture in chunks, one that ends inside a fragment's head is
  // Truncated, as the conformance suite has it (the library's budget would
  // decode the head alone).
  for (uint32_t i = 0; a.bytes != 0 && i < fvv_decoder_fragment_count(dec.get()); ++i) {
    fvv_fragment_info f;
    if (fvv_decoder_get_fragment(dec.get(), i, &f) != FVV_OK || f.head_size == f.size) continue;
    if (a.bytes < f.head_size) {
      Fail(a.input + ": --bytes " + std::to_string(a.bytes) + " ends inside fragment " +
           std::to_string(i) + "'s head of " + std::to_string(f.head_size) +
           " bytes (a prefix decodes from the end of its head on, SPEC.md 3.5.1)");
      return StreamErrorExit(FVV_TRUNCATED);
    }
  }
  if (Status s = MakeDirectories(a.output_dir); !s.ok()) return Fail(s.ToString());
  fvv_decode_budget budget{};
  budget.max_bytes_per_gop = a.bytes;
  budget.max_ms_per_gop = a.max_ms;
  budget.format = FVV_FORMAT_RGB8;
  nlohmann::json poses;
  uint64_t bytes = 0, available = 0;
  uint32_t min_planes[3] = {99, 99, 99};
  double ms = 0;
  bool complete = true;
  uint32_t gops = 0, last_gop = UINT32_MAX;
  for (uint32_t f = first; f <= last; ++f) {
    fvv_status status;
    FramePtr frame = DecodeFrame(dec.get(), f, &budget, &status);
    if (!frame) {
      Fail(a.input + ": frame " + std::to_string(f) + ": " + fvv_decoder_error(dec.get()));
      return StreamErrorExit(status);
    }
    const uint32_t gop = f / info.gop_frames;
    if (gop != last_gop) {  // the report is per GOP; count each once
      last_gop = gop;
      ++gops;
      bytes += frame->report.bytes_decoded;
      available += frame->report.bytes_available;
      ms += frame->report.decode_ms;
      for (int c = 0; c < 3; ++c)
        min_planes[c] = std::min(min_planes[c], frame->report.bitplanes[c]);
      complete = complete && frame->report.complete;
    }
    for (uint32_t c = 0; c < frame->camera_count; ++c) {
      Image img;
      img.width = frame->width;
      img.height = frame->height;
      img.channels = 3;
      img.pixels.assign(frame->views[c].pixels,
                        frame->views[c].pixels + size_t{img.width} * img.height * 3);
      Status s = WriteImage(Name(a.output_dir, "tex", f, c, a.format), img);
      if (s.ok() && frame->views[c].mask) {
        Image mask;
        mask.width = frame->width;
        mask.height = frame->height;
        mask.channels = 1;
        mask.pixels.resize(size_t{mask.width} * mask.height);
        for (size_t i = 0; i < mask.pixels.size(); ++i) {
          mask.pixels[i] = frame->views[c].mask[i] ? 255 : 0;
        }
        s = WriteImage(Name(a.output_dir, "mask", f, c, a.format), mask);
      }
      if (!s.ok()) return Fail(s.ToString());
    }
    nlohmann::json bones = nlohmann::json::array();
    for (uint32_t b = 0; b < frame->bone_count; ++b) {
      bones.push_back(
          std::vector<float>(frame->bone_world + 16 * b, frame->bone_world + 16 * b + 16));
    }
    poses.push_back({{"frame", f}, {"bone_world", bones}});
  }
  const std::string pose_path = a.output_dir + "/poses.json";
  const std::string text = nlohmann::json({{"frames", poses}}).dump(1);
  Status s = WriteFileAtomic(pose_path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (!s.ok()) return Fail(s.ToString());
  std::printf(
      "decoded frames %u..%u (%u GOPs, %u cameras, %ux%u) in %.1f ms: %llu of %llu texture bytes "
      "(%.1f%%), bitplanes Y %u U %u V %u, %s -> %s\n",
      first, last, gops, info.camera_count, info.atlas_width, info.atlas_height, ms,
      static_cast<unsigned long long>(bytes), static_cast<unsigned long long>(available),
      available ? 100.0 * bytes / available : 100.0, min_planes[0], min_planes[1], min_planes[2],
      complete ? "complete" : "truncated", a.output_dir.c_str());
  return 0;
}

}  // namespace

void AddDecodeCommand(CLI::App* app, int* exit_code) {
  auto args = std::make_shared<DecodeArgs>();
  CLI::App* d = app->add_subcommand(
      "decode",
      "Decode a .fvv stream with the decoder library: per-frame, per-camera atlas textures "
      "(tex_fFFFFF_cCC) and masks (mask_...), poses.json, and a one-line report; or, with "
      "--format conformance, the reference decoder's conformance output (conformance/README.md). "
      "Exit status: 0, or the status code of a rejected stream (2 truncated, 3 corrupt, 4 limit "
      "exceeded, 5 unsupported, 6 checksum mismatch), or 1 for other errors");
  d->add_option("file", args->input, ".fvv stream")->required()->check(CLI::ExistingFile);
  d->add_option("-o,--output", args->output_dir, "Output directory")->required();
  auto* bytes = d->add_option("--bytes", args->bytes,
                              "Decode at most this many texture bytes of each GOP fragment "
                              "(with the texture in chunks, format version 11: the first this "
                              "many bytes of each fragment, its head included)");
  d->add_option("--max-ms", args->max_ms, "Stop each GOP's texture decoding after this many ms")
      ->excludes(bytes)
      ->check(CLI::PositiveNumber);
  d->add_option("--frames", args->frames, "Frames to decode: A:B (inclusive), A: or A");
  d->add_option("--format", args->format,
                "png or exr images; or conformance: the raw decoded samples, masks and motion "
                "that conformance hashes (whole stream; --bytes applies)")
      ->check(CLI::IsMember({"png", "exr", "conformance"}))
      ->capture_default_str();
  d->add_option("--threads", args->threads, "Worker threads (0 = all cores)")
      ->capture_default_str();
  d->callback([args, exit_code] { *exit_code = RunDecode(*args); });
}

}  // namespace fvv
