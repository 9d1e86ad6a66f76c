// The texture-codec options shared by `fvv block encode`, `fvv sample` and
// `fvv encode`: --kernel, --precision, --sample-bits, --coder, --weights, --chroma,
// declared and parsed in one place.
#ifndef FVV_TOOLS_FVV_CODEC_OPTIONS_H_
#define FVV_TOOLS_FVV_CODEC_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <string>

#include "codec/block_codec.h"
#include "codec/mask.h"

namespace fvv {

struct CodecOptionArgs {
  std::string kernel = "97", coder = "arith3", weights = "own", chroma = "444";
  int precision_97 = kFracBits97;
  int sample_bits = kDefaultSampleFrac;

  WaveletKernel Kernel() const {
    return kernel == "haar" ? WaveletKernel::kHaar
           : kernel == "53" ? WaveletKernel::kLeGall53
                            : WaveletKernel::kCdf97;
  }
  EntropyCoder Coder() const {
    return coder == "binary"   ? EntropyCoder::kBinary
           : coder == "arith"  ? EntropyCoder::kArith
           : coder == "arith2" ? EntropyCoder::kNeighbourContexts
           : coder == "arith4" ? EntropyCoder::kQuadtree
                               : EntropyCoder::kSetSignContexts;
  }
  BandWeights Weights() const {
    return weights == "axis" ? BandWeights::kAxisBands : BandWeights::kOwnBand;
  }
  ChromaFormat Chroma() const { return chroma == "444" ? ChromaFormat::k444 : ChromaFormat::k420; }
  ChromaUpsampling Upsampling() const {
    return chroma == "420-nearest" ? ChromaUpsampling::kNearest : ChromaUpsampling::kBilinear;
  }
};

// `streams`: the options write .fvv streams, whose 4:2:0 rule a tool bit sets;
// block files have one rule, nearest (docs/block_file.md).
inline void AddCodecOptions(CLI::App* app, CodecOptionArgs* a, bool streams = true) {
  app->add_option("--kernel", a->kernel, "Wavelet kernel")
      ->check(CLI::IsMember({"haar", "53", "97"}))
      ->capture_default_str();
  app->add_option("--precision", a->precision_97,
                  "Fractional bits of the 9/7 transform's samples (SPEC.md 9.6): 5 needs a "
                  "format version 3 decoder; 2 is what older decoders read (about 1.6 dB lower "
                  "at 20:1 on the demo atlas textures)")
      ->check(CLI::Range(kMinFracBits97, kMaxFracBits97))
      ->capture_default_str();
  app->add_option("--coder", a->coder,
                  "Significance coding: arith3 (SPIHT's sets across bands, range coded with set "
                  "and sign contexts; needs a format version 5 decoder), arith4 (a quadtree per "
                  "subband; needs a format version 8 decoder; better on still, textured images: "
                  "+0.05-0.13 dB on Kodak), arith2 (what version 4 decoders read, about 0.1 dB "
                  "below arith3), arith (what older decoders read, about 0.2-0.3 dB lower on "
                  "atlas textures), binary (raw SPIHT decisions)")
      ->check(CLI::IsMember({"binary", "arith", "arith2", "arith3", "arith4"}))
      ->capture_default_str();
  app->add_option("--weights", a->weights,
                  "Subband weights (SPEC.md 9.3): own (each coefficient weighted by the "
                  "synthesis norm of its own band; needs a format version 6 decoder), axis "
                  "(what older decoders read; 0.1-0.4 dB lower at equal bytes)")
      ->check(CLI::IsMember({"own", "axis"}))
      ->capture_default_str();
  app->add_option("--sample-bits", a->sample_bits,
                  "Fractional bits of the coded YCbCr samples (SPEC.md 9.6) with the 9/7 and own "
                  "weights, at most --precision: 3 needs a format version 7 decoder; 0 is what "
                  "older decoders read (1.9 dB lower at 20:1 on the demo atlas textures, 0.1 "
                  "dB at 1 bpp on Kodak)")
      ->check(CLI::Range(0, kMaxSampleFrac))
      ->capture_default_str();
  if (streams) {
    app->add_option("--chroma", a->chroma,
                    "Chroma resolution: 444, 420 (halved both ways, upsampled bilinearly by "
                    "players; needs a format version 9 decoder), 420-nearest (the same samples "
                    "replicated over their 2x2 cells, what older decoders read; 0.2-0.5 dB lower "
                    "RGB at 120:1 and 280:1 on the demo atlas textures)")
        ->check(CLI::IsMember({"444", "420", "420-nearest"}))
        ->capture_default_str();
  } else {
    app->add_option("--chroma", a->chroma,
                    "Chroma resolution: 444, 420 (halved both ways, replicated over their 2x2 "
                    "cells on decoding)")
        ->check(CLI::IsMember({"444", "420"}))
        ->capture_default_str();
  }
}

// --fill-iterations for the SPIHT encoders that take masks (`fvv encode`,
// `fvv block encode`); `iterations` holds its value and its default.
inline void AddFillOption(CLI::App* app, int* iterations) {
  app->add_option("--fill-iterations", *iterations,
                  "Sparse-fill projections for texels the masks mark unused (0: the pyramid "
                  "fill alone; each costs a forward and an inverse transform per channel)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
}

// --no-prune for the SPIHT encoders that cut streams to a target (`fvv encode`,
// `fvv block encode`); `no_prune` holds its value.
inline void AddPruneOption(CLI::App* app, bool* no_prune) {
  app->add_flag("--no-prune", *no_prune,
                "With --bpp or --bytes, keep coefficients that only the last coded bitplane "
                "would make significant with no significant neighbour (by default they are "
                "zeroed and the block coded again, kept if it decodes better: about +0.1 dB at "
                "120:1 on the demo atlas textures, for a second SPIHT encode)");
}

// --texture-codec for the stream writers (`fvv encode`, `fvv sample`).
inline void AddTextureCodecOption(CLI::App* app, std::string* codec) {
  app->add_option("--texture-codec", *codec,
                  "spiht: 4D wavelet + 4D SPIHT per GOP ('texr'); predictive: T00 + R0(t) + "
                  "R(t,c) with shape-adaptive BISK ('ptex', format version 2; needs masks, "
                  "4:4:4; default kernel 5/3)")
      ->check(CLI::IsMember({"spiht", "predictive"}))
      ->capture_default_str();
}

// --mask-coder for the stream writers; `coder` holds its value.
inline void AddMaskCoderOption(CLI::App* app, std::string* coder) {
  app->add_option("--mask-coder", *coder,
                  "mixing: mask mode 2, two context models mixed per texel (format version 2, "
                  "about 12 % smaller); context: mask mode 1, readable by version 1 decoders")
      ->check(CLI::IsMember({"mixing", "context"}))
      ->capture_default_str();
}
inline MaskCoding MaskCoderFromName(const std::string& coder) {
  return coder == "context" ? MaskCoding::kContext : MaskCoding::kMixing;
}

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_CODEC_OPTIONS_H_
