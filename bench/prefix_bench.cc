// What a fetched byte budget decodes: the same capture coded with the texture
// in chunks (format version 11), each fragment fetched as one prefix, against
// 'texr' (format version <= 10) cut as SPEC.md Annex B.2 splits a budget over
// the channels (three ranges a fragment). Both streams hold the same samples
// at full length; the bench decodes each at a ladder of budgets and reports,
// per budget, the bytes a player fetches (heads included) and the RGB PSNR
// of every decoded atlas texel against the whole decode, or with --textures
// against the encoder's atlas textures over the texels its masks mark (what
// `fvv encode --save-textures` wrote: the RD that matters), then the chunked
// stream's PSNR beside the whole-texture stream's at the same fetched bytes
// (interpolated in log bytes).
//
//   prefix_bench CHUNKED.fvv WHOLE.fvv [--frames N] [--textures DIR]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "container/file_reader.h"
#include "encoder/io/image_io.h"
#include "fvv/fvv_decoder.hpp"

namespace {

struct Point {
  double fetched = 0;  // bytes a player fetches, all fragments of the frames decoded
  double psnr = 0;     // RGB over every atlas texel, against the whole decode
};

struct Stream {
  std::string path;
  std::vector<fvv::IndexEntry> index;
  std::vector<uint64_t> texture;  // texture bytes per fragment
  uint32_t frames = 0, gop_frames = 1, groups = 1, cameras = 1;
  bool chunked = false;
};

bool Load(const std::string& path, Stream* s) {
  auto source = fvv::FileSource::Open(path);
  if (!source.ok()) return false;
  auto reader = fvv::FileReader::Open(source->get());
  if (!reader.ok()) {
    std::fprintf(stderr, "%s: %s\n", path.c_str(), reader.status().ToString().c_str());
    return false;
  }
  s->path = path;
  s->index = (*reader)->info().index;
  const fvv::FileHeader& h = (*reader)->info().header;
  s->frames = h.frame_count;
  s->gop_frames = h.gop_frames;
  s->groups = h.camera_groups();
  s->cameras = h.camera_count;
  s->chunked = (h.tools & fvv::kToolTextureChunks) != 0;
  for (size_t i = 0; i < s->index.size(); ++i) {
    auto f = (*reader)->ReadFragment(i);
    if (!f.ok()) return false;
    s->texture.push_back(fvv::TextureBytes(*f));
  }
  return true;
}

// Decodes frames [0, frames) at `budget`; the RGB views of every frame.
std::vector<std::vector<uint8_t>> Decode(const Stream& s, uint64_t budget, uint32_t frames) {
  fvv::DecoderPtr dec = fvv::MakeDecoder();
  std::vector<std::vector<uint8_t>> out;
  if (fvv_decoder_open_file(dec.get(), s.path.c_str()) != FVV_OK) return out;
  fvv_decode_budget b{};
  b.max_bytes_per_gop = budget;
  for (uint32_t t = 0; t < frames; ++t) {
    fvv::FramePtr f = fvv::DecodeFrame(dec.get(), t, &b);
    if (!f) {
      std::fprintf(stderr, "%s: %s\n", s.path.c_str(), fvv_decoder_error(dec.get()));
      std::exit(1);
    }
    const size_t n = size_t{f->width} * f->height * 3;
    std::vector<uint8_t> frame;
    for (uint32_t c = 0; c < f->camera_count; ++c) {
      frame.insert(frame.end(), f->views[c].pixels, f->views[c].pixels + n);
    }
    out.push_back(std::move(frame));
  }
  return out;
}

// Over the bytes `used` marks (every byte when it is empty).
double Psnr(const std::vector<std::vector<uint8_t>>& a, const std::vector<std::vector<uint8_t>>& b,
            const std::vector<std::vector<uint8_t>>& used = {}) {
  double sum = 0, n = 0;
  for (size_t t = 0; t < a.size(); ++t) {
    for (size_t i = 0; i < a[t].size(); ++i) {
      if (!used.empty() && !used[t][i]) continue;
      const double d = double(a[t][i]) - b[t][i];
      sum += d * d;
      n += 1;
    }
  }
  return sum == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 / (sum / std::max(1.0, n)));
}

// The encoder's atlas textures and masks of frames [0, frames), laid out as
// Decode lays out its views; false when a file is missing or of another size.
bool LoadTextures(const std::string& dir, uint32_t frames, uint32_t cameras, size_t texels,
                  std::vector<std::vector<uint8_t>>* rgb, std::vector<std::vector<uint8_t>>* used) {
  for (uint32_t t = 0; t < frames; ++t) {
    std::vector<uint8_t> frame, mask;
    for (uint32_t c = 0; c < cameras; ++c) {
      char name[64];
      std::snprintf(name, sizeof(name), "/cam%02u/texture_%06u.png", c, t);
      auto image = fvv::ReadImage(dir + name);
      std::snprintf(name, sizeof(name), "/cam%02u/mask_%06u.png", c, t);
      auto m = fvv::ReadImage(dir + name);
      if (!image.ok() || !m.ok() || image->pixels.size() != texels * 3 || image->channels != 3) {
        std::fprintf(stderr, "%s: no %zu-texel RGB texture and mask for frame %u camera %u\n",
                     dir.c_str(), texels, t, c);
        return false;
      }
      frame.insert(frame.end(), image->pixels.begin(), image->pixels.end());
      for (size_t i = 0; i < texels; ++i) {
        const uint8_t u = m->pixels[i * size_t(m->channels)] != 0;
        mask.insert(mask.end(), {u, u, u});
      }
    }
    rgb->push_back(std::move(frame));
    used->push_back(std::move(mask));
  }
  return true;
}

// Bytes a player fetches for the fragments of frames [0, frames) at `budget`:
// a chunked fragment's prefix; a 'texr' fragment's bytes other than its
// texture, plus each channel's share of the budget (Annex B.2).
double Fetched(const Stream& s, uint64_t budget, uint32_t frames) {
  const size_t fragments = size_t((frames + s.gop_frames - 1) / s.gop_frames) * s.groups;
  double total = 0;
  for (size_t i = 0; i < fragments && i < s.index.size(); ++i) {
    const fvv::IndexEntry& e = s.index[i];
    if (budget == 0) {
      total += double(e.size);
    } else if (s.chunked) {
      total += double(std::min(budget, e.size));
    } else {
      total += double(e.size - s.texture[i] + std::min(budget, s.texture[i]));
    }
  }
  return total;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s CHUNKED.fvv WHOLE.fvv [--frames N]\n", argv[0]);
    return 2;
  }
  Stream chunked, whole;
  if (!Load(argv[1], &chunked) || !Load(argv[2], &whole)) return 1;
  if (!chunked.chunked || whole.chunked) {
    std::fprintf(stderr, "the first stream must have the texture in chunks, the second not\n");
    return 2;
  }
  uint32_t frames = std::min(chunked.frames, whole.frames);
  std::string textures;
  for (int i = 3; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--frames") == 0) {
      frames = std::min<uint32_t>(frames, std::atoi(argv[i + 1]));
    } else if (std::strcmp(argv[i], "--textures") == 0) {
      textures = argv[i + 1];
    }
  }
  auto ref_chunked = Decode(chunked, 0, frames);
  auto ref_whole = Decode(whole, 0, frames);
  std::printf("same samples at full length: %s\n",
              Psnr(ref_chunked, ref_whole) >= 99 ? "yes" : "NO");
  std::vector<std::vector<uint8_t>> used;
  if (!textures.empty()) {
    std::vector<std::vector<uint8_t>> source;
    const size_t texels = ref_whole[0].size() / 3 / whole.cameras;
    if (!LoadTextures(textures, frames, whole.cameras, texels, &source, &used)) return 1;
    std::printf(
        "PSNR against the atlas textures in %s over the texels their masks mark; whole "
        "decode: %.2f dB\n",
        textures.c_str(), Psnr(ref_whole, source, used));
    ref_chunked = ref_whole = source;
  }
  const double all_chunked = Fetched(chunked, 0, frames), all_whole = Fetched(whole, 0, frames);
  std::printf("whole fragments: %.0f bytes with chunks, %.0f without (+%.2f %%)\n", all_chunked,
              all_whole, 100.0 * (all_chunked / all_whole - 1));
  // Budgets as shares of the mean fragment's texture.
  uint64_t mean = 0, head = 0;
  for (size_t i = 0; i < whole.texture.size(); ++i) mean += whole.texture[i];
  mean /= std::max<size_t>(1, whole.texture.size());
  for (const fvv::IndexEntry& e : chunked.index) head = std::max<uint64_t>(head, e.head_size);
  const double shares[] = {0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 1.0};
  std::vector<Point> a, b;
  for (double share : shares) {
    const uint64_t texture = std::max<uint64_t>(1, uint64_t(share * double(mean)));
    a.push_back({Fetched(chunked, head + texture, frames),
                 Psnr(Decode(chunked, head + texture, frames), ref_chunked, used)});
    b.push_back(
        {Fetched(whole, texture, frames), Psnr(Decode(whole, texture, frames), ref_whole, used)});
  }
  std::printf("\n%-10s %14s %12s %14s %12s\n", "share", "chunks bytes", "chunks dB", "texr bytes",
              "texr dB");
  for (size_t k = 0; k < a.size(); ++k) {
    std::printf("%-10.2f %14.0f %12.2f %14.0f %12.2f\n", shares[k], a[k].fetched, a[k].psnr,
                b[k].fetched, b[k].psnr);
  }
  std::printf("\nat the chunked stream's fetched bytes (texr interpolated in log bytes):\n");
  std::printf("%14s %12s %12s %10s\n", "bytes", "chunks dB", "texr dB", "gain dB");
  for (const Point& p : a) {
    if (p.fetched < b.front().fetched || p.fetched > b.back().fetched) continue;
    size_t k = 1;
    while (k + 1 < b.size() && b[k].fetched < p.fetched) ++k;
    const double x0 = std::log(b[k - 1].fetched), x1 = std::log(b[k].fetched);
    const double w = x1 > x0 ? (std::log(p.fetched) - x0) / (x1 - x0) : 0;
    const double texr = b[k - 1].psnr + w * (b[k].psnr - b[k - 1].psnr);
    std::printf("%14.0f %12.2f %12.2f %+10.2f\n", p.fetched, p.psnr, texr, p.psnr - texr);
  }
  return 0;
}
