// Fuzz target: the texture codec end to end. The input picks a small block
// (shape, kernel, entropy coder, colour, chroma, rate) and its RGB samples;
// the block is encoded, and the decoder must reproduce the encoder's own
// reconstruction exactly, the input itself when lossless, and at every
// truncation point of every channel the same samples whether the budget cuts
// the stream or the stream is physically cut there. Any difference aborts.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "codec/block_codec.h"
#include "codec/colour.h"

namespace {

bool SameSamples(const fvv::Block& a, const fvv::Block& b) {
  for (int c = 0; c < 3; ++c) {
    if (a.channels[c].samples != b.channels[c].samples) return false;
  }
  return true;
}

[[noreturn]] void Fail(const char* what) {
  std::fprintf(stderr, "fuzz_block_round_trip: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 6) return 0;
  fvv::Shape4D shape;
  shape.n = {1u + data[0] % 3, 1u + data[1] % 2, 1u + data[2] % 24, 1u + data[3] % 24};
  const uint8_t options = data[4], rate = data[5];
  const bool lossless = (options & 0x80) != 0;
  fvv::EncodeSettings s;
  s.kernel = static_cast<fvv::WaveletKernel>(options % 3);
  if (lossless) {
    s.kernel = (options & 0x40) ? fvv::WaveletKernel::kHaar : fvv::WaveletKernel::kLeGall53;
  }
  s.coder = static_cast<fvv::EntropyCoder>((options >> 2) % 5);
  s.rate_mode = lossless ? fvv::RateMode::kLossless : fvv::RateMode::kBitsPerSample;
  s.rate_value = 0.05 + rate / 32.0;
  s.weights = (options & 0x20) ? fvv::BandWeights::kOwnBand : fvv::BandWeights::kAxisBands;
  const fvv::ColourSpace colour = lossless ? fvv::ColourSpace::kRct : fvv::ColourSpace::kYCbCr601;
  const fvv::ChromaFormat chroma =
      (!lossless && (options & 0x10)) ? fvv::ChromaFormat::k420 : fvv::ChromaFormat::k444;
  // RGB from the rest of the input, repeated to fill the block.
  std::vector<uint8_t> rgb(shape.count() * 3);
  for (size_t i = 0; i < rgb.size(); ++i) {
    rgb[i] = size > 6 ? data[6 + i % (size - 6)] : 128;
  }
  const fvv::Block block = fvv::BlockFromRgb(rgb.data(), shape, colour, chroma);
  fvv::Block encoder_view;
  fvv::EncodeReport report;
  report.decoded = &encoder_view;
  fvv::StatusOr<fvv::EncodedBlock> encoded = fvv::EncodeBlock(block, nullptr, s, &report);
  if (!encoded.ok()) return 0;  // settings the codec refuses (it says why)
  fvv::StatusOr<fvv::Block> whole =
      fvv::DecodeBlock(*encoded, fvv::DecodeBudget(), fvv::SerialRunner);
  if (!whole.ok()) Fail("a stream the encoder wrote does not decode");
  if (!SameSamples(*whole, encoder_view)) Fail("decoder and encoder reconstruct differently");
  if (lossless && !SameSamples(*whole, block)) Fail("lossless coding changed samples");
  // Budgets at every truncation point's bytes and a few more: the decoder
  // splits a budget over the channels in proportion to their sizes (Annex
  // B.2), so the same cut made to the streams themselves must decode alike.
  uint64_t total = 0;
  for (const auto& ch : encoded->channels) total += ch.data.size();
  std::vector<uint64_t> budgets = {1, total / 3, total / 2, total > 0 ? total - 1 : 0};
  for (const auto& ch : encoded->channels) {
    for (const fvv::TruncationPoint& p : ch.points) budgets.push_back(p.bytes);
  }
  for (uint64_t budget : budgets) {
    if (budget == 0 || budget >= total) continue;
    fvv::DecodeBudget by_budget;
    by_budget.max_bytes = budget;
    fvv::StatusOr<fvv::Block> cut_by_budget =
        fvv::DecodeBlock(*encoded, by_budget, fvv::SerialRunner);
    fvv::EncodedBlock cut = *encoded;
    for (auto& ch : cut.channels) {
      ch.data.resize(size_t(ch.data.size() * budget / total));
      ch.points.clear();
    }
    fvv::StatusOr<fvv::Block> cut_by_hand =
        fvv::DecodeBlock(cut, fvv::DecodeBudget(), fvv::SerialRunner);
    if (!cut_by_budget.ok() || !cut_by_hand.ok()) Fail("a truncated stream does not decode");
    if (!SameSamples(*cut_by_budget, *cut_by_hand)) Fail("a budget and the same cut differ");
  }
  return 0;
}
