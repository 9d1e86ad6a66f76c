// Writes the seed corpus of every fuzz target into DIR/<target>/ (usage:
// fuzz_make_seeds fuzz/corpus). The seeds are small valid inputs covering each
// coding tool, so the fuzzers start from deep inside the syntax.
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "codec/block_syntax.h"
#include "codec/colour.h"
#include "codec/mask.h"
#include "conformance/sample/sample_stream.h"
#include "container/writer.h"
#include "fuzz/fuzz_skeleton.h"

namespace fvv {
namespace {

bool Write(const std::string& path, const std::vector<uint8_t>& bytes) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  return std::fclose(f) == 0 && ok;
}

std::vector<uint8_t> Prefixed(std::vector<uint8_t> prefix, const std::vector<uint8_t>& body) {
  prefix.insert(prefix.end(), body.begin(), body.end());
  return prefix;
}

int Run(const std::string& dir) {
  for (const char* t : {"", "/fuzz_decode", "/fuzz_stream_reader", "/fuzz_motion", "/fuzz_mask",
                        "/fuzz_block", "/fuzz_decoder_api"}) {
    mkdir((dir + t).c_str(), 0755);
  }
  int n = 0;
  auto put = [&](const std::string& target, const std::string& name,
                 const std::vector<uint8_t>& bytes) {
    if (!Write(dir + "/" + target + "/" + name, bytes)) {
      std::fprintf(stderr, "cannot write %s/%s/%s\n", dir.c_str(), target.c_str(), name.c_str());
      std::exit(1);
    }
    ++n;
  };
  struct Variant {
    const char* name;
    void (*apply)(SampleStreamOptions*);
  };
  const Variant variants[] = {
      {"default", [](SampleStreamOptions*) {}},
      {"precision_97", [](SampleStreamOptions* o) { o->frac_bits_97 = kFracBits97; }},
      {"arith2",
       [](SampleStreamOptions* o) {
         o->frac_bits_97 = kFracBits97;
         o->coder = EntropyCoder::kNeighbourContexts;
       }},
      {"arith3",
       [](SampleStreamOptions* o) {
         o->frac_bits_97 = kFracBits97;
         o->coder = EntropyCoder::kSetSignContexts;
       }},
      {"own_band_weights",
       [](SampleStreamOptions* o) {
         o->frac_bits_97 = kFracBits97;
         o->coder = EntropyCoder::kSetSignContexts;
         o->weights = BandWeights::kOwnBand;
       }},
      {"sample_precision",
       [](SampleStreamOptions* o) {
         o->frac_bits_97 = kFracBits97;
         o->coder = EntropyCoder::kSetSignContexts;
         o->weights = BandWeights::kOwnBand;
         o->sample_frac = 3;
       }},
      {"arith4",
       [](SampleStreamOptions* o) {
         o->frac_bits_97 = kFracBits97;
         o->coder = EntropyCoder::kQuadtree;
         o->weights = BandWeights::kOwnBand;
         o->sample_frac = 3;
       }},
      {"haar_binary",
       [](SampleStreamOptions* o) {
         o->kernel = WaveletKernel::kHaar;
         o->coder = EntropyCoder::kBinary;
       }},
      {"lossless_53",
       [](SampleStreamOptions* o) {
         o->kernel = WaveletKernel::kLeGall53;
         o->lossless = true;
       }},
      {"chroma420_nomask",
       [](SampleStreamOptions* o) {
         o->chroma = ChromaFormat::k420;
         o->masks = false;
       }},
      {"chroma_bilinear",
       [](SampleStreamOptions* o) {
         o->chroma = ChromaFormat::k420;
         o->upsampling = ChromaUpsampling::kBilinear;
       }},
      {"quantised_model", [](SampleStreamOptions* o) { o->quantise_model = true; }},
      {"motion_zstd_interp",
       [](SampleStreamOptions* o) {
         o->motion_coder = MotionCoder::kZstd;
         o->key_interval = 2;
       }},
      {"predictive_53",
       [](SampleStreamOptions* o) {
         o->kernel = WaveletKernel::kLeGall53;
         o->predictive = true;
       }},
      {"masks_mixing", [](SampleStreamOptions* o) { o->mask_coding = MaskCoding::kMixing; }},
      {"texture_chunks",
       [](SampleStreamOptions* o) {
         o->frac_bits_97 = kFracBits97;
         o->coder = EntropyCoder::kQuadtree;
         o->weights = BandWeights::kOwnBand;
         o->sample_frac = 3;
         o->texture_chunks = true;
       }},
      {"surface",
       [](SampleStreamOptions* o) {
         o->coder = EntropyCoder::kQuadtree;
         o->texture_chunks = true;
         o->surface = true;
         o->gop_cameras = 1;
       }},
      {"end_index_vvis",
       [](SampleStreamOptions* o) {
         o->fast_start = false;
         o->vertex_visibility = true;
       }},
  };
  for (const Variant& v : variants) {
    SampleStreamOptions o = TinySampleOptions();
    v.apply(&o);
    auto stream = MakeSampleStream(o);
    if (!stream.ok()) {
      std::fprintf(stderr, "%s: %s\n", v.name, stream.status().ToString().c_str());
      return 1;
    }
    auto bytes = WriteStreamToMemory(stream->info, stream->fragments);
    if (!bytes.ok()) return 1;
    put("fuzz_decode", v.name, Prefixed({0}, *bytes));
    put("fuzz_stream_reader", v.name, Prefixed({7}, *bytes));
    put("fuzz_decoder_api", v.name, Prefixed({100, 0}, *bytes));
    put("fuzz_decoder_ranges", v.name, Prefixed({3, 128}, *bytes));
    const FragmentData& f = stream->fragments[0];
    const uint8_t mode = static_cast<uint8_t>((o.motion_coder == MotionCoder::kZstd ? 1 : 0) |
                                              ((o.key_interval - 1) << 1));
    put("fuzz_motion", v.name, Prefixed({mode, uint8_t(f.info.frame_count - 1)}, f.motion));
    if (!f.masks.empty()) {
      const Shape4D s = f.info.TextureShape(stream->info.header);
      put("fuzz_mask", v.name,
          Prefixed({uint8_t((s.frames() - 1) | (f.mask_mode == MaskCoding::kMixing ? 0x10 : 0)),
                    uint8_t(s.cameras() - 1), uint8_t(s.height() - 1), uint8_t(s.width() - 1)},
                   f.masks));
    }
    EncodedBlock block = f.texture;
    put("fuzz_block", std::string(v.name) + ".fvb", WriteBlockFile(block));
  }
  std::printf("wrote %d seeds under %s\n", n, dir.c_str());
  return 0;
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  return fvv::Run(argv[1]);
}
