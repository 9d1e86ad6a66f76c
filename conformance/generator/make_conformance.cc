// Makes the conformance suite's cases (conformance/README.md): valid streams
// from the sample encoder with one coding tool or boundary per case, edge cases
// made by editing boxes, and invalid streams a decoder must reject. Each case
// gets stream.fvv and a test.json whose expectations come from the reference
// decoder (fvv conform --bless does the same for hand-made cases).
//
// Released cases never change: existing case directories are left alone
// unless --force. Usage: fvv_make_conformance OUT_DIR [--only NAME] [--force]
#include <sys/stat.h>
#include <zstd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "conformance/generator/stream_edit.h"
#include "conformance/lib/runner.h"
#include "conformance/sample/sample_stream.h"
#include "container/file_header.h"
#include "container/file_reader.h"
#include "container/writer.h"
#include "encoder/io/image_io.h"
#include "fvv/fvv_types.h"

namespace fvv {
namespace {

struct CaseSpec {
  std::string name, description;
  std::vector<std::string> sections;  // beyond the ones every stream exercises
  SampleStreamOptions options;
  std::vector<uint64_t> budgets;  // truncation budgets besides whole streams
  // The budgets count from the stream's largest fragment head (texture-chunks:
  // a prefix shorter than a head is an error, SPEC.md 3.5.1).
  bool budgets_past_head = false;
  // Valid edge cases and invalid streams: edits of the sample stream's boxes.
  std::function<Status(std::vector<EditBox>*)> edit;
  StatusCode error = StatusCode::kOk;  // kOk: the stream is valid
  uint64_t error_budget = 0;           // invalid: decoded at this budget (0 = whole)
  // Raw cut or damage after joining (truncation, box sizes): applied last.
  std::function<void(std::vector<EditBox>*, std::vector<uint8_t>*)> raw;
};

SampleStreamOptions Base(uint32_t frames, uint16_t cameras, uint16_t w, uint16_t h,
                         uint16_t gop_frames, uint16_t gop_cameras) {
  SampleStreamOptions o;
  o.frames = frames;
  o.cameras = cameras;
  o.atlas_width = w;
  o.atlas_height = h;
  o.gop_frames = gop_frames;
  o.gop_cameras = gop_cameras;
  o.metadata = {{"generator", "fvv_make_conformance"}};
  return o;
}

SampleStreamOptions Tiny() {
  SampleStreamOptions o = TinySampleOptions();
  o.metadata = {{"generator", "fvv_make_conformance"}};
  return o;
}

// Table 1's names; a bit it does not define as "bitN".
std::vector<std::string> ToolNames(uint32_t tools) {
  std::vector<std::string> names;
  for (int n = 0; n < 32; ++n) {
    const uint32_t bit = 1u << n;
    if (!(tools & bit)) continue;
    const std::string name = CodingToolName(bit);
    names.push_back(name == "unknown" ? "bit" + std::to_string(n) : name);
  }
  return names;
}

// "3.10" after "3.9"; duplicates dropped.
std::vector<std::string> SortedSections(std::vector<std::string> s) {
  const auto key = [](const std::string& section) {
    std::vector<int> parts;
    for (size_t i = 0; i < section.size();) {
      size_t next = section.find('.', i);
      if (next == std::string::npos) next = section.size();
      const std::string part = section.substr(i, next - i);
      // Annex parts ("B.2") after the sections.
      parts.push_back(std::isalpha(static_cast<unsigned char>(part[0])) ? 1000 + part[0]
                                                                        : std::atoi(part.c_str()));
      i = next + 1;
    }
    return parts;
  };
  std::sort(s.begin(), s.end(),
            [&](const std::string& a, const std::string& b) { return key(a) < key(b); });
  s.erase(std::unique(s.begin(), s.end()), s.end());
  return s;
}

// Sections every decodable stream exercises, plus the tools' own.
std::vector<std::string> Sections(const StreamInfo& info, const CaseSpec& spec) {
  std::vector<std::string> s = {"2",   "3.1", "3.2", "3.3", "3.4", "3.5", "5",
                                "6.1", "6.2", "6.3", "6.4", "9.1", "9.2", "9.3"};
  const uint32_t t = info.header.tools;
  if (t & kToolPredictiveTexture) {
    // No SPIHT: the BISK streams use the range decoder and the inverse lifting.
    s.erase(std::find(s.begin(), s.end(), "9.1"), s.end());
    s.insert(s.end(), {"4", "9.4", "9.6", "9.7", "9.8"});
  } else {
    if (t & (kToolSpihtArith | kToolSpihtArith2 | kToolSpihtArith3 | kToolQuadtreeArith4))
      s.push_back("9.4");
    // Their count-adaptive probabilities.
    if (t & (kToolSpihtArith3 | kToolQuadtreeArith4)) s.push_back("7.2");
    if (t & kToolQuadtreeArith4) s.push_back("9.9");
    s.insert(s.end(), {"9.5", "9.6", "9.7"});
  }
  if (t & kToolMasks) s.push_back("7");
  if (t & kToolVertexVisibility) s.push_back("8");
  if (!info.metadata.empty()) s.push_back("3.7");
  s.push_back("3.6");
  for (const std::string& extra : spec.sections) s.push_back(extra);
  return SortedSections(s);
}

bool Exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

Status MakeCase(const CaseSpec& spec, const std::string& dir, bool force) {
  if (Exists(dir + "/test.json") && !force) {
    std::printf("kept     %s (released; --force to remake)\n", spec.name.c_str());
    return Status::Ok();
  }
  FVV_ASSIGN_OR_RETURN(SampleStream sample, MakeSampleStream(spec.options));
  FVV_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes,
                       WriteStreamToMemory(sample.info, sample.fragments));
  FVV_ASSIGN_OR_RETURN(std::vector<EditBox> boxes, SplitBoxes(bytes));
  if (spec.edit) {
    FVV_RETURN_IF_ERROR(spec.edit(&boxes));
    bytes = JoinBoxes(boxes);
  }
  if (spec.raw) spec.raw(&boxes, &bytes);
  if (bytes.size() > (1u << 20)) {
    return InvalidArgument(spec.name + ": stream of " + std::to_string(bytes.size()) +
                           " bytes (cases stay under 1 MiB)");
  }
  if (mkdir(dir.c_str(), 0755) != 0 && !Exists(dir)) return IoError("cannot create " + dir);
  FVV_RETURN_IF_ERROR(WriteFileAtomic(dir + "/stream.fvv", bytes.data(), bytes.size()));
  ConformanceCase c;
  c.dir = dir;
  c.name = spec.name;
  c.description = spec.description;
  // What the stream's own header says, after any edit: an invalid case's
  // header is often the point of it.
  const std::vector<uint8_t>& h = boxes[size_t(FindBox(boxes, box::kFileHeader))].payload;
  c.format_version = int(LoadLe(h, fvvh::kFormatVersion, 2));
  c.profile = int(LoadLe(h, fvvh::kProfile, 1));
  c.level = int(LoadLe(h, fvvh::kLevel, 1));
  c.tools = ToolNames(uint32_t(LoadLe(h, fvvh::kTools, 4)));
  // The version that knows every tool of the case, the sample's or the
  // edited header's (a header's version outside 1..current is the case's
  // error, which every decoder must give).
  c.decoder_version = sample.info.header.format_version;
  if (c.format_version >= 1 && c.format_version <= FVV_FORMAT_VERSION) {
    c.decoder_version = std::max(c.decoder_version, c.format_version);
  }
  c.spec_sections = Sections(sample.info, spec);
  if (spec.error != StatusCode::kOk) {
    c.expect_error = true;
    c.error = spec.error;
    c.error_bytes_per_fragment = spec.error_budget;
    c.spec_sections = SortedSections(spec.sections);
  }
  std::vector<uint64_t> budgets = spec.budgets;
  if (spec.budgets_past_head) {
    MemorySource source(bytes.data(), bytes.size());
    FVV_ASSIGN_OR_RETURN(const std::unique_ptr<FileReader> reader, FileReader::Open(&source));
    uint64_t head = 0;
    for (const IndexEntry& e : reader->info().index) head = std::max<uint64_t>(head, e.head_size);
    for (uint64_t& b : budgets) b += head;
  }
  FVV_RETURN_IF_ERROR(BlessCase(&c, budgets, /*force=*/true));
  std::printf("made     %-34s %7zu bytes\n", spec.name.c_str(), bytes.size());
  return Status::Ok();
}

// ---- valid cases -----------------------------------------------------------

std::vector<CaseSpec> ValidCases() {
  std::vector<CaseSpec> v;
  const auto add = [&v](std::string name, std::string description, SampleStreamOptions o,
                        std::vector<uint64_t> budgets, std::vector<std::string> sections = {}) {
    CaseSpec s;
    s.name = std::move(name);
    s.description = std::move(description);
    s.options = std::move(o);
    s.budgets = std::move(budgets);
    s.sections = std::move(sections);
    v.push_back(std::move(s));
    return &v.back();
  };
  SampleStreamOptions o = Base(8, 4, 64, 64, 4, 2);
  add("basic_97_arith", "9/7 kernel, arithmetic SPIHT, masks; 2x2 GOP grid", o, {1, 64, 700});

  o = Base(6, 3, 48, 40, 4, 2);
  o.kernel = WaveletKernel::kHaar;
  o.coder = EntropyCoder::kBinary;
  add("kernel_haar_binary", "Haar kernel, binary SPIHT; partial GOPs on both axes", o, {40, 300});
  o.kernel = WaveletKernel::kLeGall53;
  o.coder = EntropyCoder::kArith;
  add("kernel_53_arith", "5/3 kernel, arithmetic SPIHT", o, {40, 300});
  o.kernel = WaveletKernel::kCdf97;
  o.coder = EntropyCoder::kBinary;
  add("kernel_97_binary", "9/7 kernel, binary SPIHT", o, {40, 300});

  o = Base(4, 2, 24, 20, 2, 2);
  o.lossless = true;
  o.kernel = WaveletKernel::kLeGall53;
  add("lossless_53_rct",
      "lossless: 5/3 with the reversible colour transform, whole streams "
      "reproduce the source exactly",
      o, {100, 1000});
  o.kernel = WaveletKernel::kHaar;
  o.coder = EntropyCoder::kBinary;
  add("lossless_haar_rct_binary", "lossless: Haar, RCT, binary SPIHT", o, {100, 1000});

  o = Base(5, 2, 37, 23, 4, 2);
  o.chroma = ChromaFormat::k420;
  add("chroma_420_odd", "4:2:0 chroma on an odd-sized atlas (37x23: chroma 19x12)", o, {30, 200});

  o = Base(10, 5, 40, 24, 4, 2);
  add("gop_partial", "10 frames x 5 cameras in 4x2 GOPs: short last span, one-camera last group", o,
      {50});
  o = Base(6, 1, 32, 32, 3, 1);
  add("gop_one_camera", "a single camera", o, {50});
  o = Base(1, 3, 32, 16, 1, 3);
  add("gop_one_frame", "a single frame", o, {50});
  o = Base(3, 2, 16, 16, 1, 1);
  add("gop_1x1", "GOPs of one frame and one camera (6 fragments)", o, {10});
  o = Base(2, 2, 1, 1, 2, 2);
  o.bpp = 8;
  add("atlas_1x1", "a 1x1 atlas: every axis but time and cameras of size 1", o, {1});
  o = Base(3, 2, 1, 50, 3, 2);
  o.chroma = ChromaFormat::k420;
  add("atlas_column_420", "a 1x50 atlas with 4:2:0 chroma (chroma 1x25)", o, {10});
  // Format version 9: 4:2:0 chroma upsampled bilinearly (tool bit 18), at an
  // odd atlas's edges and in a chroma plane one sample wide.
  o = Base(5, 2, 37, 23, 4, 2);
  o.chroma = ChromaFormat::k420;
  o.upsampling = ChromaUpsampling::kBilinear;
  add("chroma_bilinear_odd",
      "format version 9: 4:2:0 chroma upsampled bilinearly on an odd-sized atlas (37x23: chroma "
      "19x12, edge samples repeated)",
      o, {30, 200});
  o = Base(3, 2, 1, 50, 3, 2);
  o.chroma = ChromaFormat::k420;
  o.upsampling = ChromaUpsampling::kBilinear;
  add("chroma_bilinear_column",
      "format version 9: a 1x50 atlas with 4:2:0 chroma upsampled bilinearly (chroma 1x25: the "
      "row neighbour is the sample itself)",
      o, {10});
  // Format version 10: the body model on the reference encoder's grid.
  o = Base(6, 2, 32, 32, 4, 2);
  o.quantise_model = true;
  add("quantised_model",
      "format version 10: the body model on a grid ('modl' version 1: positions in steps of "
      "2^-13 m, atlas coordinates of 2^-11, 10-bit octahedral normals, 8-bit skin weights)",
      o, {100});
  o = Base(8, 3, 32, 32, 4, 3);
  o.masks = false;
  add("no_masks", "no shape masks: every texel used", o, {100});
  o = Base(9, 2, 32, 32, 4, 2);
  o.motion_coder = MotionCoder::kZstd;
  add("motion_zstd", "motion track coded with zstd", o, {});
  o = Base(10, 2, 32, 32, 8, 2);
  o.key_interval = 3;
  add("motion_interpolation", "motion key interval 3: interpolated frames (fixed-point slerp)", o,
      {});
  o.motion_coder = MotionCoder::kZstd;
  o.key_interval = 4;
  add("motion_interpolation_zstd", "key interval 4 with the zstd motion coder", o, {});

  o = Base(9, 2, 32, 32, 4, 2);
  o.fast_start = false;
  add("index_end", "the index at the end, where the header (written last) points", o, {});
  auto* no_index =
      add("no_index", "no index at all: readers rebuild it by walking the boxes", o, {});
  no_index->edit = [](std::vector<EditBox>* boxes) { return DropIndex(boxes); };
  auto* live = add("live",
                   "a live stream: frame count 0 in the header and no index; readers count the "
                   "frames from the fragments (9 frames: the last time span is short)",
                   o, {}, {"3.1", "3.6"});
  live->edit = [](std::vector<EditBox>* boxes) {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));
    StoreLe(&(*boxes)[size_t(FindBox(*boxes, box::kFileHeader))].payload, fvvh::kFrameCount, 0, 4);
    return Status::Ok();
  };

  o = Base(5, 2, 32, 32, 4, 2);
  auto* skip = add("unknown_boxes_and_largesize",
                   "non-essential unknown boxes at top level and in a fragment, which decoders "
                   "skip; box headers in the 64-bit size form",
                   o, {}, {"2"});
  skip->edit = [](std::vector<EditBox>* boxes) -> Status {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));
    EditBox unknown;
    unknown.type = MakeFourCC("xtra");
    unknown.version = 3;
    unknown.payload = {1, 2, 3, 4, 5};
    boxes->insert(boxes->begin() + 1, unknown);
    (*boxes)[FindBox(*boxes, box::kModel)].large = true;
    boxes->push_back(unknown);  // after the last fragment
    const int frag = FindBox(*boxes, box::kFragment, 1);
    (*boxes)[frag].large = true;
    return EditFragment(&(*boxes)[frag], [&unknown](std::vector<EditBox>* subs) {
      EditBox inner = unknown;
      inner.type = MakeFourCC("xsub");
      subs->insert(subs->begin() + 2, inner);
      (*subs)[FindBox(*subs, box::kTexture)].large = true;
    });
  };

  o = Base(3, 2, 16, 16, 3, 2);
  o.metadata = {
      {"title", "Conformance: metadata"},
      {"empty", ""},
      {"", "empty key"},
      {"utf-8", "\xC3\xA9t\xC3\xA9 \xE2\x80\x94 \xE6\x97\xA5\xE6\x9C\xAC \xF0\x9F\x8E\xA5"},
      {"title", "a repeated key"}};
  add("metadata", "metadata with empty keys and values, repeated keys, multi-byte UTF-8", o, {});
  o = Base(4, 3, 32, 32, 2, 3);
  o.vertex_visibility = true;
  add("vertex_visibility", "fragments carry per-vertex visibility (vvis)", o, {});

  // Profile/level boundaries: each at its level's limits (5, table).
  o = Base(8, 8, 512, 512, 8, 8);
  o.frame_rate_num = 30;
  o.bpp = 0.01;
  o.level = 1;
  add("level1_limits",
      "level 1 at its limits: 512x512 atlas, 8 cameras, GOP 8x8 (2^24 samples), "
      "512^2 x 8 x 30 samples/s",
      o, {5000}, {"5"});
  o = Base(16, 16, 1024, 4, 16, 16);
  o.frame_rate_num = 30;
  o.level = 2;
  o.bpp = 0.05;
  add("level2_limits", "level 2 limits on atlas side (1024), cameras (16), GOP 16x16", o, {2000},
      {"5"});
  o = Base(16, 32, 2048, 2, 16, 32);
  o.frame_rate_num = 30;
  o.level = 3;
  o.bpp = 0.05;
  add("level3_limits", "level 3 limits on atlas side (2048), cameras (32), GOP 16x32", o, {2000},
      {"5"});
  o = Base(32, 1, 4096, 1, 32, 1);
  o.frame_rate_num = 60;
  o.level = 4;
  o.bpp = 0.1;
  add("level4_frames", "level 4 limits on atlas side (4096) and GOP frames (32), 60 fps", o, {500},
      {"5"});
  o = Base(1, 64, 8, 8, 1, 64);
  o.level = 4;
  add("level4_cameras", "level 4 limits on cameras and GOP cameras (64)", o, {200}, {"5"});

  // Format version 2: the predictive texture (9.8).
  o = Base(6, 3, 40, 32, 4, 3);
  o.predictive = true;
  o.kernel = WaveletKernel::kLeGall53;
  o.bpp = 1.0;
  add("predictive_53",
      "predictive texture (T00, R0, R with shape-adaptive BISK), 5/3; a short last span", o,
      {200, 1000});
  o = Base(4, 2, 24, 20, 4, 2);
  o.predictive = true;
  o.lossless = true;
  o.kernel = WaveletKernel::kHaar;
  add("predictive_haar_lossless", "predictive texture, Haar, whole streams: lossless in YCbCr", o,
      {100, 800});
  o = Base(5, 5, 33, 17, 4, 3);
  o.predictive = true;
  o.bpp = 0.8;
  add("predictive_97_partial",
      "predictive texture, 9/7, odd atlas (33x17), partial GOPs on both axes", o, {150});

  // Format version 2: mask mode 2 (7.2).
  o = Base(9, 4, 48, 40, 4, 3);
  o.mask_coding = MaskCoding::kMixing;
  add("masks_mixing",
      "mask mode 2 (two context models mixed per texel): a camera reference in each GOP's "
      "first frame, references two frames back, a short last span and group",
      o, {60, 400});
  o = Base(3, 2, 37, 23, 3, 2);
  o.mask_coding = MaskCoding::kMixing;
  o.predictive = true;
  o.kernel = WaveletKernel::kLeGall53;
  o.bpp = 1.0;
  add("masks_mixing_predictive", "mask mode 2 with the predictive texture (its supports)", o,
      {120});

  // Format version 3: the 9/7's sample precision in 'texr' version 1 (9.1, 9.6).
  o = Base(8, 4, 64, 64, 4, 2);
  o.frac_bits_97 = kFracBits97;
  add("precision_97_f5",
      "9/7 with 5 fractional bits of sample precision (texr version 1), arithmetic SPIHT, "
      "masks; 2x2 GOP grid",
      o, {1, 64, 700});
  o = Base(5, 3, 37, 23, 4, 2);
  o.frac_bits_97 = kMaxFracBits97;
  o.coder = EntropyCoder::kBinary;
  o.chroma = ChromaFormat::k420;
  o.mask_coding = MaskCoding::kMixing;
  add("precision_97_f6_binary_420",
      "9/7 at the largest precision (6 fractional bits), binary SPIHT, 4:2:0 on an odd atlas, "
      "mask mode 2",
      o, {30, 200});

  // The encoder's defaults with `coder`, in 4-frame GOPs on a 2x2 grid: the
  // 9/7 at precision 5, own-band weights, 3 fractional sample bits.
  const auto encoder_defaults = [](EntropyCoder coder) {
    SampleStreamOptions c = Base(8, 4, 64, 64, 4, 2);
    c.frac_bits_97 = kFracBits97;
    c.coder = coder;
    c.weights = BandWeights::kOwnBand;
    c.sample_frac = 3;
    return c;
  };
  // Format versions 4 and 5: SPIHT coders 2 (neighbourhood contexts) and 3
  // (set and sign contexts), 9.5: the 9/7 at precision 5 in 4-frame GOPs, and
  // the 5/3 with 4:2:0 on an odd atlas in multi-camera GOPs.
  const auto coder_cases = [&](EntropyCoder coder, const char* the_97, const char* the_53) {
    const std::string name = std::string("arith") + std::to_string(static_cast<int>(coder));
    SampleStreamOptions c = Base(8, 4, 64, 64, 4, 2);
    c.frac_bits_97 = kFracBits97;
    c.coder = coder;
    add(name + "_97", the_97, c, {1, 64, 700});
    c = Base(6, 3, 37, 23, 6, 3);
    c.kernel = WaveletKernel::kLeGall53;
    c.coder = coder;
    c.chroma = ChromaFormat::k420;
    c.mask_coding = MaskCoding::kMixing;
    add(name + "_53_420_multicamera", the_53, c, {30, 200});
  };
  coder_cases(EntropyCoder::kNeighbourContexts,
              "SPIHT coder 2 (neighbourhood contexts, temporal neighbours in 4-frame GOPs), 9/7 "
              "with 5 fractional bits, masks; 2x2 GOP grid",
              "SPIHT coder 2 with the 5/3 kernel, 4:2:0 on an odd atlas, 6-frame x 3-camera GOPs, "
              "mask mode 2");
  coder_cases(EntropyCoder::kSetSignContexts,
              "SPIHT coder 3 (set and sign contexts, neighbours in time in 4-frame GOPs, "
              "count-adaptive probabilities), 9/7 with 5 fractional bits, masks; 2x2 GOP grid",
              "SPIHT coder 3 with the 5/3 kernel, 4:2:0 on an odd atlas, 6-frame x 3-camera GOPs, "
              "mask mode 2");
  // Format version 8: coder 4 (quadtrees per subband, 9.9), in the same two
  // settings and with the encoder's other defaults (own-band weights, 3
  // fractional sample bits).
  coder_cases(EntropyCoder::kQuadtree,
              "coder 4 (quadtrees per subband, neighbours in time in 4-frame GOPs), 9/7 with 5 "
              "fractional bits, masks; 2x2 GOP grid",
              "coder 4 with the 5/3 kernel, 4:2:0 on an odd atlas (bands whose parents have "
              "fewer tree levels), 6-frame x 3-camera GOPs, mask mode 2");
  add("arith4_sample_precision_97",
      "coder 4 with own-band weights and decoded samples with 3 fractional bits, 9/7 with 5 "
      "fractional bits, masks; 2x2 GOP grid",
      encoder_defaults(EntropyCoder::kQuadtree), {1, 64, 700});

  // Format version 11: the texture in chunks (3.5.1); a budget is a prefix of
  // each fragment, at least the largest head of the stream.
  {
    SampleStreamOptions c = encoder_defaults(EntropyCoder::kQuadtree);
    c.quantise_model = true;
    c.texture_chunks = true;
    add("texture_chunks_97",
        "format version 11: the texture in chunks ('txhd', 'txck'), decoded from prefixes of "
        "each fragment; coder 4 with the encoder's other defaults, masks; 2x2 GOP grid",
        c, {0, 150, 600, 1500}, {"3.5.1", "B.2"})
        ->budgets_past_head = true;
    c = Base(6, 3, 37, 23, 6, 3);
    c.kernel = WaveletKernel::kLeGall53;
    c.coder = EntropyCoder::kQuadtree;
    c.chroma = ChromaFormat::k420;
    c.mask_coding = MaskCoding::kMixing;
    c.vertex_visibility = true;
    c.fast_start = false;
    c.texture_chunks = true;
    add("texture_chunks_53_420_index_end",
        "format version 11: chunks of a 5/3 4:2:0 texture on an odd atlas in 6-frame x "
        "3-camera GOPs with vertex visibility, the index (version 1, with the heads' sizes) at "
        "the end",
        c, {0, 100, 400}, {"3.5.1", "8", "B.2"})
        ->budgets_past_head = true;
  }

  // Format version 12: the surface of every frame (3.5.2), in camera group
  // 0's chunks: whole, or left out by a prefix that ends before it.
  {
    SampleStreamOptions c = encoder_defaults(EntropyCoder::kQuadtree);
    c.quantise_model = true;
    c.texture_chunks = true;
    c.surface = true;
    c.gop_frames = 4;
    add("surface_97",
        "format version 12: the surface of every frame ('sfhd', chunks of channel 3) in 4-frame "
        "GOPs, decoded whole, and left out by prefixes that end before its last chunk (the head "
        "alone, 200 bytes past the largest head: the texture of group 1 only) or taken (600 "
        "and 2500 past it); coder 4, masks",
        c, {0, 200, 600, 2500}, {"3.5.1", "3.5.2", "B.1", "B.2"})
        ->budgets_past_head = true;
  }

  // Format version 6: own-band weights ('texr' version 2, 9.3): the 9/7 with
  // coder 3 as the encoder's defaults have it, the 5/3 (power-of-two weights)
  // with coder 1 in multi-camera GOPs, and the 9/7 at its legacy precision.
  o = Base(8, 4, 64, 64, 4, 2);
  o.frac_bits_97 = kFracBits97;
  o.coder = EntropyCoder::kSetSignContexts;
  o.weights = BandWeights::kOwnBand;
  add("own_band_weights_97",
      "own-band weights (texr version 2), SPIHT coder 3, 9/7 with 5 fractional bits, masks; "
      "2x2 GOP grid",
      o, {1, 64, 700});
  o = Base(6, 3, 37, 23, 6, 3);
  o.kernel = WaveletKernel::kLeGall53;
  o.weights = BandWeights::kOwnBand;
  o.chroma = ChromaFormat::k420;
  add("own_band_weights_53_420_multicamera",
      "own-band weights with the 5/3 kernel (power-of-two weights), SPIHT coder 1, 4:2:0 on an "
      "odd atlas, 6-frame x 3-camera GOPs",
      o, {30, 200});
  o = Base(5, 2, 40, 24, 5, 2);
  o.weights = BandWeights::kOwnBand;
  o.coder = EntropyCoder::kBinary;
  add("own_band_weights_97_f2_binary",
      "own-band weights with the 9/7 at 2 fractional bits (texr version 2 without the "
      "texture-precision tool), binary SPIHT, 5-frame x 2-camera GOPs",
      o, {40, 300});

  // Format version 7: fractional output samples ('texr' version 3, 9.6, 9.7):
  // the encoder's default (3 of the 9/7's 5 fractional bits), the most (4 of
  // 6) with 4:2:0 on an odd atlas, and 1 of 2 with binary SPIHT.
  add("sample_precision_97",
      "decoded samples with 3 fractional bits (texr version 3), own-band weights, SPIHT coder 3, "
      "9/7 with 5 fractional bits, masks; 2x2 GOP grid",
      encoder_defaults(EntropyCoder::kSetSignContexts), {1, 64, 700});
  o = Base(6, 3, 37, 23, 6, 3);
  o.frac_bits_97 = 6;
  o.coder = EntropyCoder::kSetSignContexts;
  o.weights = BandWeights::kOwnBand;
  o.sample_frac = 4;
  o.chroma = ChromaFormat::k420;
  add("sample_precision_97_p4_f6_420",
      "decoded samples with 4 fractional bits from a 9/7 with 6, 4:2:0 on an odd atlas, SPIHT "
      "coder 3, 6-frame x 3-camera GOPs",
      o, {30, 200});
  o = Base(5, 2, 40, 24, 5, 2);
  o.frac_bits_97 = kFracBits97Legacy;
  o.weights = BandWeights::kOwnBand;
  o.coder = EntropyCoder::kBinary;
  o.sample_frac = 1;
  add("sample_precision_97_p1_f2_binary",
      "decoded samples with 1 fractional bit from a 9/7 with 2 (texr version 3 without the "
      "texture-precision tool), binary SPIHT, 5-frame x 2-camera GOPs",
      o, {40, 300});
  return v;
}

// ---- invalid cases ---------------------------------------------------------

// Offset in raw model data (SPEC.md 3.3) of bone `index`'s name field.
size_t SkeletonBoneOffset(const std::vector<uint8_t>& raw, size_t index) {
  size_t at = 2;
  for (size_t b = 0; b < index; ++b) {
    at += 2 + size_t(LoadLe(raw, at, 2));  // name
    at += 2 + 12 + 16 + 1;                 // parent, translation, rotation, order
    const uint8_t dof_mask = raw[at];
    at += 1 + 8 * size_t(__builtin_popcount(dof_mask));  // dof_mask, limits
  }
  return at;
}

// An edit of the body model's raw data (decompressed), stored again
// uncompressed (compression 0) so that the edit is visible in the stream.
std::function<Status(std::vector<EditBox>*)> EditModelData(
    std::function<void(std::vector<uint8_t>*)> edit) {
  return [edit](std::vector<EditBox>* boxes) -> Status {
    std::vector<uint8_t>& m = (*boxes)[size_t(FindBox(*boxes, box::kModel))].payload;
    const size_t raw_size = size_t(LoadLe(m, 1, 4));
    std::vector<uint8_t> raw(raw_size);
    if (m[0] == 1) {
      if (ZSTD_decompress(raw.data(), raw_size, m.data() + 5, m.size() - 5) != raw_size) {
        return Internal("edit: modl does not decompress");
      }
    } else {
      raw.assign(m.begin() + 5, m.end());
    }
    edit(&raw);
    m.assign(1, 0);
    for (int i = 0; i < 4; ++i) m.push_back(uint8_t(raw_size >> (8 * i)));
    m.insert(m.end(), raw.begin(), raw.end());
    return Status::Ok();
  };
}

std::vector<CaseSpec> InvalidCases() {
  std::vector<CaseSpec> v;
  const auto add = [&v](std::string name, std::string description, StatusCode error,
                        std::vector<std::string> sections) {
    CaseSpec s;
    s.name = "invalid/" + name;
    s.description = std::move(description);
    s.options = Tiny();
    s.error = error;
    s.sections = std::move(sections);
    v.push_back(std::move(s));
    return &v.back();
  };
  const auto header = [](std::vector<EditBox>* boxes) -> std::vector<uint8_t>& {
    return (*boxes)[FindBox(*boxes, box::kFileHeader)].payload;
  };
  // Clears, then sets, bits of the header's coding tools.
  const auto set_tools = [header](std::vector<EditBox>* boxes, uint32_t clear, uint32_t set) {
    std::vector<uint8_t>& h = header(boxes);
    const uint32_t tools = h[fvvh::kTools] | h[fvvh::kTools + 1] << 8 | h[fvvh::kTools + 2] << 16 |
                           uint32_t{h[fvvh::kTools + 3]} << 24;
    StoreLe(&h, fvvh::kTools, (tools & ~clear) | set, 4);
  };
  const auto fragment = [](std::vector<EditBox>* boxes, int n) -> EditBox& {
    return (*boxes)[FindBox(*boxes, box::kFragment, n)];
  };
  // An edit of the header: clears, then sets, tool bits, and sets the format
  // version unless `version` is 0.
  const auto retool = [header, set_tools](uint32_t clear, uint32_t set, uint16_t version) {
    return [header, set_tools, clear, set, version](std::vector<EditBox>* boxes) {
      set_tools(boxes, clear, set);
      if (version != 0) StoreLe(&header(boxes), fvvh::kFormatVersion, version, 2);
      return Status::Ok();
    };
  };
  // Sets one byte of a sub-box of the first fragment and recomputes its
  // checksum, so that only the decoding process can object.
  const auto patch_first_fragment = [fragment](FourCC type, size_t offset, uint8_t value) {
    return [fragment, type, offset, value](std::vector<EditBox>* boxes) {
      return EditFragment(&fragment(boxes, 0), [&](std::vector<EditBox>* subs) {
        (*subs)[FindBox(*subs, type)].payload[offset] = value;
      });
    };
  };

  add("truncated_in_fragment", "the stream ends inside the last fragment", StatusCode::kTruncated,
      {"2", "10"})
      ->raw = [](std::vector<EditBox>* boxes, std::vector<uint8_t>* bytes) {
    const int last = FindBox(*boxes, box::kFragment, 1);
    bytes->resize(BoxOffset(*boxes, last) + 40);
  };
  add("truncated_in_model", "the stream ends inside the body model box", StatusCode::kTruncated,
      {"2", "3.3", "10"})
      ->raw = [](std::vector<EditBox>* boxes, std::vector<uint8_t>* bytes) {
    bytes->resize(BoxOffset(*boxes, FindBox(*boxes, box::kModel)) + 100);
  };
  add("truncated_missing_fragment",
      "the last fragment is missing: the stream ends before all fragments its header declares",
      StatusCode::kTruncated, {"3", "3.6", "10"})
      ->raw = [](std::vector<EditBox>* boxes, std::vector<uint8_t>* bytes) {
    bytes->resize(BoxOffset(*boxes, FindBox(*boxes, box::kFragment, 1)));
  };
  auto* end_index = add("truncated_in_end_index", "the stream ends inside its index (at the end)",
                        StatusCode::kTruncated, {"3.6", "10"});
  end_index->options.fast_start = false;
  end_index->raw = [](std::vector<EditBox>*, std::vector<uint8_t>* bytes) {
    bytes->resize(bytes->size() - 10);
  };

  add("box_size_zero", "a top-level box (meta) with size 0", StatusCode::kCorrupt, {"2", "10"})
      ->raw = [](std::vector<EditBox>* boxes, std::vector<uint8_t>* bytes) {
    StoreLe(bytes, BoxOffset(*boxes, FindBox(*boxes, box::kMetadata)), 0, 4);
  };
  add("box_size_below_header", "a top-level box (mtrk) whose size is smaller than its header",
      StatusCode::kCorrupt, {"2", "10"})
      ->raw = [](std::vector<EditBox>* boxes, std::vector<uint8_t>* bytes) {
    StoreLe(bytes, BoxOffset(*boxes, FindBox(*boxes, box::kMotionParams)), 8, 4);
  };
  add("subbox_past_fragment",
      "a fragment's texr sub-box runs past the end of the fragment "
      "(found by the sub-box walk, before the checksum)",
      StatusCode::kCorrupt, {"2", "3.5", "10"})
      ->edit = [](std::vector<EditBox>* boxes) { return DropIndex(boxes); };
  // The texr box's declared size grows past the fcrc that follows it (on the
  // joined bytes: a box of the edit list cannot lie about its size).
  v.back().raw = [](std::vector<EditBox>* boxes, std::vector<uint8_t>* bytes) {
    const int f = FindBox(*boxes, box::kFragment, 0);
    auto subs = SplitBoxes((*boxes)[f].payload);
    if (!subs.ok()) return;
    const int tex = FindBox(*subs, box::kTexture);
    const uint64_t at = BoxOffset(*boxes, f) + kMinBoxHeaderSize + BoxOffset(*subs, tex);
    StoreLe(bytes, at, (*subs)[tex].payload.size() + kMinBoxHeaderSize + 1000, 4);
  };

  add("level_atlas_too_wide", "atlas width 513 in a level-1 stream", StatusCode::kLimitExceeded,
      {"3.1", "5", "10"})
      ->edit = [header](std::vector<EditBox>* boxes) {
    StoreLe(&header(boxes), fvvh::kAtlasWidth, 513, 2);
    return Status::Ok();
  };
  add("level_gop_frames", "9 frames per GOP in a level-1 stream", StatusCode::kLimitExceeded,
      {"3.1", "5", "10"})
      ->edit = [header](std::vector<EditBox>* boxes) {
    StoreLe(&header(boxes), fvvh::kGopFrames, 9, 2);
    return Status::Ok();
  };
  add("level_cameras", "9 cameras in a level-1 stream", StatusCode::kLimitExceeded,
      {"3.1", "5", "10"})
      ->edit = [header](std::vector<EditBox>* boxes) {
    StoreLe(&header(boxes), fvvh::kCameraCount, 9, 2);
    return Status::Ok();
  };
  // Header fields out of range, one case per rule of 3.1, and one with two
  // errors: the first in 3.1's order of checks is the stream's.
  struct Field {
    size_t offset, bytes;
    uint32_t value;
  };
  const auto set_fields = [header](std::vector<Field> fields) {
    return [header, fields](std::vector<EditBox>* boxes) {
      for (const Field& f : fields) StoreLe(&header(boxes), f.offset, f.value, f.bytes);
      return Status::Ok();
    };
  };
  // The GOP grid: an index the header does not point at, and a time span
  // shorter than F_g that is not the last (known frame count, and live).
  {
    SampleStreamOptions end = Tiny();
    end.fast_start = false;
    add("index_while_offset_zero",
        "an 'indx' at the end while the header's index_offset is 0 (it must sit where the "
        "header says)",
        StatusCode::kCorrupt, {"3.1", "3.6", "10"})
        ->options = end;
    v.back().edit = [header](std::vector<EditBox>* boxes) {
      StoreLe(&header(boxes), fvvh::kIndexOffset, 0, 8);
      return Status::Ok();
    };
    const auto shorten_first_span = [fragment](bool live_stream) {
      return [fragment, live_stream](std::vector<EditBox>* boxes) -> Status {
        FVV_RETURN_IF_ERROR(DropIndex(boxes));
        if (live_stream) {
          StoreLe(&(*boxes)[size_t(FindBox(*boxes, box::kFileHeader))].payload, fvvh::kFrameCount,
                  0, 4);
        }
        // fghd: gop_index u32, first_frame u32, frame_count u16.
        return EditFragment(&fragment(boxes, 0), [](std::vector<EditBox>* subs) {
          StoreLe(&(*subs)[size_t(FindBox(*subs, box::kFragmentHeader))].payload, 8, 1, 2);
        });
      };
    };
    add("short_span_not_last",
        "the first fragment covers 1 frame of its 2-frame time span, in a stream of known "
        "frame count",
        StatusCode::kCorrupt, {"3.1", "3.5", "10"})
        ->edit = shorten_first_span(false);
    add("live_short_span_not_last",
        "a live stream (frame count 0) whose first time span has 1 frame of 2 and is followed "
        "by another",
        StatusCode::kCorrupt, {"3.1", "3.5", "10"})
        ->edit = shorten_first_span(true);
  }
  // A live stream's time spans: the fragments of one span agree on its frame
  // count, and the stream ends after a whole span. Two camera groups, 3
  // frames: spans of 2 and 1 frames, fragments 0-3.
  {
    SampleStreamOptions groups = Tiny();
    groups.gop_cameras = 1;
    const auto make_live = [](std::vector<EditBox>* boxes) -> Status {
      FVV_RETURN_IF_ERROR(DropIndex(boxes));
      StoreLe(&(*boxes)[size_t(FindBox(*boxes, box::kFileHeader))].payload, fvvh::kFrameCount, 0,
              4);
      return Status::Ok();
    };
    add("live_span_frame_counts_differ",
        "a live stream of two camera groups whose last time span is 1 frame in the first "
        "group's fragment and 2 in the second's",
        StatusCode::kCorrupt, {"3.1", "3.5", "10"});
    v.back().options = groups;
    v.back().edit = [make_live, fragment](std::vector<EditBox>* boxes) -> Status {
      FVV_RETURN_IF_ERROR(make_live(boxes));
      // fghd: gop_index u32, first_frame u32, frame_count u16.
      return EditFragment(&fragment(boxes, 3), [](std::vector<EditBox>* subs) {
        StoreLe(&(*subs)[size_t(FindBox(*subs, box::kFragmentHeader))].payload, 8, 2, 2);
      });
    };
    add("live_ends_inside_span",
        "a live stream of two camera groups that ends after the first group's fragment of a "
        "time span",
        StatusCode::kTruncated, {"3.1", "3.5", "10"});
    v.back().options = groups;
    v.back().edit = [make_live](std::vector<EditBox>* boxes) -> Status {
      FVV_RETURN_IF_ERROR(make_live(boxes));
      boxes->erase(boxes->begin() + FindBox(*boxes, box::kFragment, 3));
      return Status::Ok();
    };
  }
  add("header_format_version_0", "format_version 0", StatusCode::kUnsupported, {"3.1", "10"})
      ->edit = set_fields({{fvvh::kFormatVersion, 2, 0}});
  add("header_profile_2", "profile 2 (only 1, Main, exists)", StatusCode::kUnsupported,
      {"3.1", "5", "10"})
      ->edit = set_fields({{fvvh::kProfile, 1, 2}});
  add("header_level_0", "level 0", StatusCode::kUnsupported, {"3.1", "5", "10"})->edit =
      set_fields({{fvvh::kLevel, 1, 0}});
  add("header_level_5", "level 5", StatusCode::kUnsupported, {"3.1", "5", "10"})->edit =
      set_fields({{fvvh::kLevel, 1, 5}});
  add("header_frame_rate_num_0", "frame rate 0/1", StatusCode::kCorrupt, {"3.1", "10"})->edit =
      set_fields({{fvvh::kFrameRateNum, 4, 0}, {fvvh::kFrameRateDen, 4, 1}});
  add("header_frame_rate_den_0", "frame rate 25/0", StatusCode::kCorrupt, {"3.1", "10"})->edit =
      set_fields({{fvvh::kFrameRateNum, 4, 25}, {fvvh::kFrameRateDen, 4, 0}});
  add("header_frame_rate_241", "frame rate 241/1 (above 240 fps)", StatusCode::kLimitExceeded,
      {"3.1", "10"})
      ->edit = set_fields({{fvvh::kFrameRateNum, 4, 241}, {fvvh::kFrameRateDen, 4, 1}});
  add("header_camera_count_0", "camera_count 0", StatusCode::kCorrupt, {"3.1", "10"})->edit =
      set_fields({{fvvh::kCameraCount, 2, 0}});
  add("header_atlas_height_0", "atlas_height 0", StatusCode::kCorrupt, {"3.1", "10"})->edit =
      set_fields({{fvvh::kAtlasHeight, 2, 0}});
  add("header_gop_cameras_0", "gop_cameras 0", StatusCode::kCorrupt, {"3.1", "10"})->edit =
      set_fields({{fvvh::kGopCameras, 2, 0}});
  add("header_first_error_wins",
      "profile 2 and camera_count 0: the profile is checked first (3.1's order)",
      StatusCode::kUnsupported, {"3.1", "10"})
      ->edit = set_fields({{fvvh::kProfile, 1, 2}, {fvvh::kCameraCount, 2, 0}});
  add("checksum_mismatch", "one byte of a fragment's texture payload changed",
      StatusCode::kChecksumMismatch, {"3.5", "10"})
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    EditBox& f = fragment(boxes, 1);
    f.payload[f.payload.size() / 2] ^= 0x10;
    return Status::Ok();
  };
  add("unknown_essential_box", "an unknown top-level box marked essential",
      StatusCode::kUnsupported, {"2", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));
    EditBox b;
    b.type = MakeFourCC("zzzz");
    b.flags = kBoxFlagEssential;
    b.payload = {0, 0, 0, 0};
    boxes->insert(boxes->begin() + FindBox(*boxes, box::kFragment), b);
    return Status::Ok();
  };
  add("sub_box_65",
      "a fragment of 65 sub-boxes (unknown non-essential ones added; checksum recomputed)",
      StatusCode::kCorrupt, {"3.5", "10"})
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));
    return EditFragment(&fragment(boxes, 0), [](std::vector<EditBox>* subs) {
      EditBox b;
      b.type = MakeFourCC("zzzz");
      while (subs->size() < 65) subs->insert(subs->begin() + 1, b);
    });
  };
  add("unknown_essential_subbox",
      "an unknown sub-box marked essential inside a fragment "
      "(checksum recomputed)",
      StatusCode::kUnsupported, {"2", "3.5", "10"})
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));
    return EditFragment(&fragment(boxes, 0), [](std::vector<EditBox>* subs) {
      EditBox b;
      b.type = MakeFourCC("zzzz");
      b.flags = kBoxFlagEssential;
      subs->insert(subs->begin() + 1, b);
    });
  };
  add("newer_format_version", "format_version 999", StatusCode::kUnsupported, {"3.1", "4", "10"})
      ->edit = retool(0, 0, 999);
  add("newer_box_version", "the cams box at version 1", StatusCode::kUnsupported, {"2", "4", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    (*boxes)[FindBox(*boxes, box::kCameras)].version = 1;
    return Status::Ok();
  };
  add("unknown_tool_bit", "coding tool bit 20 set", StatusCode::kUnsupported, {"3.1", "10"})->edit =
      retool(0, 1u << 20, 0);
  add("index_entry_mismatch", "an index entry's frame count differs from its fragment's header",
      StatusCode::kCorrupt, {"3.6", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    // entry 1 starts after count (4 bytes) and entry 0 (26); frame_count at +4.
    StoreLe(&(*boxes)[FindBox(*boxes, box::kIndex)].payload, 4 + 26 + 4, 2, 2);
    return Status::Ok();
  };
  add("index_offset_wrong", "the header's index_offset points 4 bytes past the index",
      StatusCode::kCorrupt, {"3.1", "3.6", "10"})
      ->edit = [header](std::vector<EditBox>* boxes) {
    StoreLe(&header(boxes), fvvh::kIndexOffset, BoxOffset(*boxes, FindBox(*boxes, box::kIndex)) + 4,
            8);
    return Status::Ok();
  };
  add("fragments_out_of_order", "the two fragments swapped (no index)", StatusCode::kCorrupt,
      {"3.5", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));
    std::swap((*boxes)[FindBox(*boxes, box::kFragment, 0)],
              (*boxes)[FindBox(*boxes, box::kFragment, 1)]);
    return Status::Ok();
  };
  add("header_box_after_fragment", "the mtrk box after the first fragment (no index)",
      StatusCode::kCorrupt, {"3", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));
    const int m = FindBox(*boxes, box::kMotionParams);
    const EditBox mtrk = (*boxes)[m];
    boxes->erase(boxes->begin() + m);
    boxes->insert(boxes->begin() + FindBox(*boxes, box::kFragment) + 1, mtrk);
    return Status::Ok();
  };
  add("camera_count_mismatch", "cams declares one camera fewer than the header",
      StatusCode::kCorrupt, {"3.2", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    std::vector<uint8_t>& cams = (*boxes)[FindBox(*boxes, box::kCameras)].payload;
    StoreLe(&cams, 0, 1, 2);
    return Status::Ok();
  };
  add("model_checksum_wrong", "the content checksum of the body model's zstd frame changed",
      StatusCode::kCorrupt, {"3.3", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    std::vector<uint8_t>& m = (*boxes)[FindBox(*boxes, box::kModel)].payload;
    m.back() ^= 0x01;
    return Status::Ok();
  };
  add("metadata_bad_utf8", "a metadata value that is not valid UTF-8 (an overlong form)",
      StatusCode::kCorrupt, {"3.7", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    EditBox& meta = (*boxes)[FindBox(*boxes, box::kMetadata)];
    // count 1, key "k", value "\xC0\xAF" (an overlong '/').
    meta.payload = {1, 0, 1, 0, 'k', 2, 0, 0xC0, 0xAF};
    return DropIndex(boxes);
  };
  add("mask_mode_unknown", "mask coding mode 2 (checksum recomputed)", StatusCode::kUnsupported,
      {"7", "10"})
      ->edit = patch_first_fragment(box::kMasks, 0, 2);
  add("texture_too_many_bitplanes",
      "a channel stream declaring 31 bitplanes (checksum "
      "recomputed)",
      StatusCode::kCorrupt, {"9.1", "10"})
      ->edit = patch_first_fragment(box::kTexture, 4, 31);
  add("texture_undeclared_kernel",
      "a texture coded with Haar in a stream declaring 9/7 "
      "(checksum recomputed)",
      StatusCode::kCorrupt, {"3.1", "9.1", "10"})
      ->edit = patch_first_fragment(box::kTexture, 0, 0);
  add("motion_bad_predictor", "motion predictor 2 (checksum recomputed)", StatusCode::kCorrupt,
      {"6.2", "10"})
      ->edit = patch_first_fragment(box::kMotion, 0, 2);

  // Format version 2: the predictive texture.
  const auto predictive = [](CaseSpec* c) {
    c->options.predictive = true;
    c->options.kernel = WaveletKernel::kLeGall53;
    return c;
  };
  predictive(add("predictive_in_version_1",
                 "the predictive-texture tool (bit 11) in a format version 1 header",
                 StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 1);
  predictive(add("ptex_without_tool",
                 "a 'ptex' texture in a stream whose header declares SPIHT instead of bit 11",
                 StatusCode::kCorrupt, {"3.1", "3.5", "9.8", "10"}))
      ->edit = retool(kToolPredictiveTexture, kToolSpihtArith, 1);
  // The first fragment of the tiny stream is 2 frames x 2 cameras: 3 (1 + 2 + 4)
  // = 21 stream sizes after the kernel byte; T00 Y's first byte follows them.
  predictive(add("ptex_sizes_mismatch",
                 "a 'ptex' whose stream sizes add up to more than the bytes that follow "
                 "(checksum recomputed)",
                 StatusCode::kCorrupt, {"9.8", "10"}))
      ->edit = patch_first_fragment(box::kPredictiveTexture, 2, 0x40);
  add("mask_mode_unknown_v2",
      "mask coding mode 3 in a format version 2 stream (checksum "
      "recomputed)",
      StatusCode::kUnsupported, {"7", "10"})
      ->edit = [patch_first_fragment](std::vector<EditBox>* boxes) {
    StoreLe(&(*boxes)[FindBox(*boxes, box::kFileHeader)].payload, fvvh::kFormatVersion, 2, 2);
    return patch_first_fragment(box::kMasks, 0, 3)(boxes);
  };
  predictive(add("ptex_kernel_3", "a 'ptex' naming wavelet kernel 3 (checksum recomputed)",
                 StatusCode::kCorrupt, {"9.8", "10"}))
      ->edit = patch_first_fragment(box::kPredictiveTexture, 0, 3);
  predictive(add("ptex_top_plane",
                 "a 'ptex' stream whose top bitplane byte is 31 (checksum "
                 "recomputed)",
                 StatusCode::kCorrupt, {"9.8", "10"}))
      ->edit = patch_first_fragment(box::kPredictiveTexture, 1 + 4 * 21, 31);

  // Format version 3: texture precision ('texr' version 1: kernel, coder,
  // colour, chroma, frac_bits, then the channel streams).
  const auto precise = [](CaseSpec* c) {
    c->options.frac_bits_97 = kFracBits97;
    return c;
  };
  precise(add("precision_in_version_2",
              "the texture-precision tool (bit 12) in a format version 2 header",
              StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 2);
  precise(add("texr_v1_without_tool",
              "'texr' version 1 in a format version 3 stream whose header does not declare "
              "texture-precision",
              StatusCode::kCorrupt, {"3.1", "9.1", "10"}))
      ->edit = retool(kToolTexturePrecision, 0, 0);
  add("texr_v0_with_tool",
      "'texr' version 0 (no precision field) in a stream that declares texture-precision",
      StatusCode::kCorrupt, {"3.1", "9.1", "10"})
      ->edit = retool(0, kToolTexturePrecision, 3);
  precise(add("precision_out_of_range",
              "a 9/7 texture declaring 7 fractional bits (allowed 2..6; checksum recomputed)",
              StatusCode::kCorrupt, {"9.1", "10"}))
      ->edit = patch_first_fragment(box::kTexture, 4, 7);
  precise(add("precision_without_97",
              "a header declaring texture-precision with the 5/3 kernel instead of the 9/7",
              StatusCode::kCorrupt, {"3.1", "10"}))
      ->edit = retool(kToolCdf97, kToolLeGall53, 0);

  // Format version 4: SPIHT coder 2.
  const auto arith2 = [](CaseSpec* c) {
    c->options.coder = EntropyCoder::kNeighbourContexts;
    return c;
  };
  arith2(add("arith2_in_version_3", "the spiht-arith2 tool (bit 13) in a format version 3 header",
             StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 3);
  add("arith2_without_tool",
      "a 'texr' naming coder 2 in a stream whose header declares spiht-arith, not spiht-arith2 "
      "(checksum recomputed)",
      StatusCode::kCorrupt, {"3.1", "9.1", "10"})
      ->edit = patch_first_fragment(box::kTexture, 1, 2);
  add("coder_unknown", "a 'texr' naming entropy coder 3 (checksum recomputed)",
      StatusCode::kCorrupt, {"9.1", "10"})
      ->edit = patch_first_fragment(box::kTexture, 1, 3);
  // A value its field does not define is Corrupt in 'texr' and 'ptex' alike.
  // Range-coded data that ends before its decisions do, in a whole box.
  const auto halve_first = [fragment](FourCC type) {
    return [fragment, type](std::vector<EditBox>* boxes) -> Status {
      FVV_RETURN_IF_ERROR(DropIndex(boxes));  // the fragment shrinks
      return EditFragment(&fragment(boxes, 0), [type](std::vector<EditBox>* subs) {
        std::vector<uint8_t>& p = (*subs)[size_t(FindBox(*subs, type))].payload;
        p.resize((p.size() + 1) / 2);
      });
    };
  };
  add("motion_data_short",
      "the first fragment's 'motn' cut to half its bytes (box and checksum made whole): its "
      "decisions need bytes beyond the payload",
      StatusCode::kCorrupt, {"6.3", "9.4", "10"})
      ->edit = halve_first(box::kMotion);
  add("mask_data_short",
      "the first fragment's 'mask' cut to half its bytes (box and checksum made whole): its "
      "decisions need bytes beyond the payload",
      StatusCode::kCorrupt, {"7", "9.4", "10"})
      ->edit = halve_first(box::kMasks);
  // The motion track's zstd form: after the key frame's residuals (one LEB128
  // value per DOF), the first decision of frame 1 is a flag, made 2.
  {
    SampleStreamOptions z = Tiny();
    z.motion_coder = MotionCoder::kZstd;
    const size_t dofs = MakeSampleBodyModel().skeleton.Dofs().size();
    add("motion_zstd_flag_2",
        "a flag byte of 2 in the zstd motion form (the first flag of frame 1; recompressed, "
        "checksum recomputed)",
        StatusCode::kCorrupt, {"6.3", "10"})
        ->options = z;
    v.back().edit = [fragment, dofs](std::vector<EditBox>* boxes) -> Status {
      FVV_RETURN_IF_ERROR(DropIndex(boxes));
      Status inner = Status::Ok();
      FVV_RETURN_IF_ERROR(EditFragment(&fragment(boxes, 0), [&](std::vector<EditBox>* subs) {
        std::vector<uint8_t>& p = (*subs)[size_t(FindBox(*subs, box::kMotion))].payload;
        const unsigned long long n = ZSTD_getFrameContentSize(p.data() + 1, p.size() - 1);
        if (n == ZSTD_CONTENTSIZE_ERROR || n == ZSTD_CONTENTSIZE_UNKNOWN || n > (1u << 20)) {
          inner = Internal("edit: motn is not one zstd frame with its size");
          return;
        }
        std::vector<uint8_t> raw(n);
        if (ZSTD_decompress(raw.data(), n, p.data() + 1, p.size() - 1) != n) {
          inner = Internal("edit: motn does not decompress");
          return;
        }
        size_t at = 0;
        for (size_t d = 0; d < dofs && at < raw.size(); ++d) {
          while (at < raw.size() && (raw[at] & 0x80)) ++at;  // LEB128 continuation
          ++at;
        }
        if (at >= raw.size() || raw[at] > 1) {
          inner = Internal("edit: no flag after the key frame");
          return;
        }
        raw[at] = 2;
        std::vector<uint8_t> packed(ZSTD_compressBound(raw.size()));
        const size_t m = ZSTD_compress(packed.data(), packed.size(), raw.data(), raw.size(), 19);
        packed.resize(m);
        p.resize(1);
        p.insert(p.end(), packed.begin(), packed.end());
      }));
      return inner;
    };
  }
  // The body model: bone 1 names itself its parent (not an earlier bone). The
  // model is stored uncompressed (compression 0) so the edit is visible.
  add("model_parent_not_earlier", "bone 1 of the body model is its own parent",
      StatusCode::kCorrupt, {"3.3", "10"})
      ->edit = EditModelData([](std::vector<uint8_t>* raw) {
    const size_t name = SkeletonBoneOffset(*raw, 1);
    StoreLe(raw, name + 2 + size_t(LoadLe(*raw, name, 2)), 1, 2);  // bone 1's parent: itself
  });
  add("camera_focal_nan", "the first camera's fx is NaN", StatusCode::kCorrupt, {"3.2", "10"})
      ->edit = [](std::vector<EditBox>* boxes) {
    // cams: count u16, then the first camera: name (u16 length, bytes),
    // width u32, height u32, fx f64.
    std::vector<uint8_t>& c = (*boxes)[size_t(FindBox(*boxes, box::kCameras))].payload;
    const size_t name = size_t(LoadLe(c, 2, 2)), fx = 2 + 2 + name + 8;
    StoreLe(&c, fx, 0x7FF8000000000000ull, 8);  // a quiet NaN
    return Status::Ok();
  };
  add("texr_kernel_3", "a 'texr' naming wavelet kernel 3 (checksum recomputed)",
      StatusCode::kCorrupt, {"9.1", "10"})
      ->edit = patch_first_fragment(box::kTexture, 0, 3);
  add("texr_colour_2", "a 'texr' naming colour space 2 (checksum recomputed)", StatusCode::kCorrupt,
      {"9.1", "10"})
      ->edit = patch_first_fragment(box::kTexture, 2, 2);
  add("texr_chroma_2", "a 'texr' naming chroma format 2 (checksum recomputed)",
      StatusCode::kCorrupt, {"9.1", "10"})
      ->edit = patch_first_fragment(box::kTexture, 3, 2);

  // A coder's three invalid cases: its tool bit in a header of the format
  // version before its own, a 'texr' naming it in a stream whose header
  // declares the coder before it instead, and a 'texr' naming the number after it.
  const auto coder_invalid_cases = [&](EntropyCoder coder, EntropyCoder before,
                                       const std::string& tool, const std::string& tool_before,
                                       int bit, int version) {
    const auto coded_with = [](EntropyCoder c) {
      return [c](CaseSpec* spec) {
        spec->options.coder = c;
        return spec;
      };
    };
    const int n = static_cast<int>(coder);
    const std::string number = std::to_string(n), older = std::to_string(version - 1);
    coded_with(coder)(add("arith" + number + "_in_version_" + older,
                          "the " + tool + " tool (bit " + std::to_string(bit) +
                              ") in a format version " + older + " header",
                          StatusCode::kCorrupt, {"3.1", "4", "10"}))
        ->edit = retool(0, 0, static_cast<uint16_t>(version - 1));
    coded_with(before)(add("arith" + number + "_without_tool",
                           "a 'texr' naming coder " + number +
                               " in a stream whose header declares " + tool_before + ", not " +
                               tool + " (checksum recomputed)",
                           StatusCode::kCorrupt, {"3.1", "9.1", "10"}))
        ->edit = patch_first_fragment(box::kTexture, 1, static_cast<uint8_t>(n));
    coded_with(coder)(add("coder_unknown_in_version_" + std::to_string(version),
                          "a 'texr' of a format version " + std::to_string(version) +
                              " stream naming entropy coder " + std::to_string(n + 1) +
                              " (checksum recomputed)",
                          StatusCode::kCorrupt, {"9.1", "10"}))
        ->edit = patch_first_fragment(box::kTexture, 1, static_cast<uint8_t>(n + 1));
  };
  // Format version 5: SPIHT coder 3.
  coder_invalid_cases(EntropyCoder::kSetSignContexts, EntropyCoder::kNeighbourContexts,
                      "spiht-arith3", "spiht-arith2", 14, 5);

  // Format version 6: own-band weights ('texr' version 2).
  const auto own_band = [](CaseSpec* c) {
    c->options.frac_bits_97 = kFracBits97;
    c->options.coder = EntropyCoder::kSetSignContexts;
    c->options.weights = BandWeights::kOwnBand;
    return c;
  };
  own_band(add("own_band_weights_in_version_5",
               "the own-band-weights tool (bit 15) in a format version 5 header",
               StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 5);
  own_band(add("texr_v2_without_tool",
               "'texr' version 2 in a stream whose header declares texture-precision but not "
               "own-band-weights",
               StatusCode::kCorrupt, {"3.1", "9.1", "10"}))
      ->edit = retool(kToolOwnBandWeights, 0, 0);
  precise(add("texr_v1_with_own_band_tool",
              "'texr' version 1 (per-axis weights) in a format version 6 stream that declares "
              "own-band-weights",
              StatusCode::kCorrupt, {"3.1", "9.1", "10"}))
      ->edit = retool(0, kToolOwnBandWeights, 6);
  own_band(add("texr_version_3", "a 'texr' of box version 3 (checksum recomputed)",
               StatusCode::kUnsupported, {"9.1", "10"}))
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    return EditFragment(&fragment(boxes, 0), [&](std::vector<EditBox>* subs) {
      (*subs)[FindBox(*subs, box::kTexture)].version = 3;
    });
  };

  // Format version 7: fractional samples ('texr' version 3).
  const auto sample_precision = [own_band](CaseSpec* c) {
    own_band(c)->options.sample_frac = 3;
    return c;
  };
  sample_precision(add("sample_precision_in_version_6",
                       "the sample-precision tool (bit 16) in a format version 6 header",
                       StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 6);
  sample_precision(add("sample_precision_without_own_band",
                       "a header declaring sample-precision but not own-band-weights",
                       StatusCode::kCorrupt, {"3.1", "10"}))
      ->edit = retool(kToolOwnBandWeights, 0, 0);
  sample_precision(add("texr_v3_without_tool",
                       "'texr' version 3 in a format version 7 stream whose header declares "
                       "own-band-weights but not sample-precision",
                       StatusCode::kCorrupt, {"3.1", "9.1", "10"}))
      ->edit = retool(kToolSamplePrecision, 0, 0);
  own_band(add("texr_v2_with_sample_tool",
               "'texr' version 2 in a format version 7 stream that declares sample-precision",
               StatusCode::kCorrupt, {"3.1", "9.1", "10"}))
      ->edit = retool(0, kToolSamplePrecision, 7);
  sample_precision(add("sample_frac_above_frac_bits",
                       "a 9/7 texture with 5 fractional bits declaring decoded samples with 6 "
                       "(allowed 0..min(4, 5); checksum recomputed)",
                       StatusCode::kCorrupt, {"9.1", "10"}))
      ->edit = patch_first_fragment(box::kTexture, 5, 6);
  sample_precision(add("texr_version_4",
                       "a 'texr' of box version 4 in a format version 7 stream (checksum "
                       "recomputed)",
                       StatusCode::kUnsupported, {"9.1", "10"}))
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    return EditFragment(&fragment(boxes, 0), [&](std::vector<EditBox>* subs) {
      (*subs)[FindBox(*subs, box::kTexture)].version = 4;
    });
  };

  // Format version 8: coder 4.
  coder_invalid_cases(EntropyCoder::kQuadtree, EntropyCoder::kSetSignContexts, "quadtree-arith4",
                      "spiht-arith3", 17, 8);

  // Format version 9: 4:2:0 chroma upsampled bilinearly.
  const auto bilinear = [](CaseSpec* c) {
    c->options.chroma = ChromaFormat::k420;
    c->options.upsampling = ChromaUpsampling::kBilinear;
    return c;
  };
  bilinear(add("chroma_bilinear_in_version_8",
               "the chroma-bilinear tool (bit 18) in a format version 8 header",
               StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 8);
  add("chroma_bilinear_without_420",
      "a format version 9 header declaring chroma-bilinear without chroma-420",
      StatusCode::kCorrupt, {"3.1", "10"})
      ->edit = retool(0, kToolChromaBilinear, 9);

  // Format version 10: the body model on a grid ('modl' version 1).
  const auto quantised = [](CaseSpec* c) {
    c->options.quantise_model = true;
    return c;
  };
  quantised(add("quantised_model_in_version_9",
                "the quantised-model tool (bit 19) in a format version 9 header",
                StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 9);
  quantised(add("model_v1_without_tool",
                "a 'modl' version 1 in a format version 10 stream that does not declare "
                "quantised-model",
                StatusCode::kCorrupt, {"3.1", "3.3", "10"}))
      ->edit = retool(kToolQuantisedModel, 0, 10);
  add("model_v0_with_tool", "a 'modl' version 0 (floats) in a stream that declares quantised-model",
      StatusCode::kCorrupt, {"3.1", "3.3", "10"})
      ->edit = retool(0, kToolQuantisedModel, 10);
  // The grid after the skeleton and the two counts: position exponent,
  // uv exponent, normal bits, weight bits.
  quantised(add("model_normal_bits_17", "a 'modl' version 1 with 17-bit normal codes",
                StatusCode::kCorrupt, {"3.3", "10"}))
      ->edit = EditModelData([](std::vector<uint8_t>* raw) {
    const size_t bones = size_t(LoadLe(*raw, 0, 2));
    (*raw)[SkeletonBoneOffset(*raw, bones) + 8 + 2] = 17;
  });
  quantised(add("model_weights_not_255",
                "a 'modl' version 1 whose first vertex's 8-bit skin weights sum to 254 or 256",
                StatusCode::kCorrupt, {"3.3", "10"}))
      ->edit = EditModelData([](std::vector<uint8_t>* raw) {
    const size_t bones = size_t(LoadLe(*raw, 0, 2));
    const size_t counts = SkeletonBoneOffset(*raw, bones);
    const size_t n = size_t(LoadLe(*raw, counts, 4));
    // Positions (3 x 4 byte planes), normals (2 x 2), uvs (2 x 4), joints
    // (4 x 2), then weights: the first weight's low byte plane.
    const size_t weights = counts + 8 + 4 + n * (12 + 4 + 8 + 8);
    (*raw)[weights] ^= 1;
  });

  // Format version 11: the texture in chunks (3.5.1).
  const auto chunked = [](CaseSpec* c) {
    c->options.texture_chunks = true;
    return c;
  };
  chunked(add("texture_chunks_in_version_10",
              "the texture-chunks tool (bit 21) in a format version 10 header",
              StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 10);
  predictive(add("texture_chunks_with_predictive",
                 "a format version 11 header declaring texture-chunks with predictive-texture",
                 StatusCode::kCorrupt, {"3.1", "10"}))
      ->edit = retool(0, kToolTextureChunks, 11);
  chunked(add("chunks_prefix_inside_head",
              "a valid chunked stream decoded at a budget of 40 bytes per fragment: every "
              "prefix ends inside its fragment's head",
              StatusCode::kTruncated, {"3.5.1", "10", "B.2"}))
      ->error_budget = 40;
  chunked(add("chunk_checksum_mismatch",
              "one byte of the first fragment's last chunk changed (the chunk's CRC-32C no longer "
              "matches; the head's does)",
              StatusCode::kChecksumMismatch, {"3.5.1", "10"}))
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    return EditChunkedFragment(&fragment(boxes, 0), nullptr,
                               [](std::vector<uint8_t>* chunks) { chunks->back() ^= 0x10; });
  };
  chunked(add("chunk_channel_3",
              "the first fragment's first chunk names channel 3 (its CRC-32C recomputed)",
              StatusCode::kCorrupt, {"3.5.1", "10"}))
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    return EditChunkedFragment(&fragment(boxes, 0), nullptr, [](std::vector<uint8_t>* chunks) {
      (*chunks)[0] = 3;
      RechecksumChunk(chunks, 0);
    });
  };
  chunked(add("chunks_short_of_head",
              "the first fragment's 'txhd' declares one byte more of channel Y than its chunks "
              "hold (head checksum recomputed)",
              StatusCode::kCorrupt, {"3.5.1", "10"}))
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    return EditChunkedFragment(
        &fragment(boxes, 0),
        [](std::vector<EditBox>* subs) {
          // After kernel, coder, colour, chroma and the precisions its
          // version has (9.1): Y's bitplanes, then its size.
          EditBox& head = (*subs)[FindBox(*subs, box::kTextureHead)];
          const size_t y_size = 4 + (head.version >= 1) + (head.version >= 3) + 1;
          StoreLe(&head.payload, y_size, LoadLe(head.payload, y_size, 4) + 1, 4);
        },
        nullptr);
  };
  // Format version 12: the surface of every frame (3.5.2).
  const auto surfaced = [](CaseSpec* c) {
    c->options.texture_chunks = true;
    c->options.surface = true;
    c->options.gop_frames = 4;
    c->options.gop_cameras = 1;  // two camera groups, one with the surface
    return c;
  };
  surfaced(add("surface_in_version_11", "the surface tool (bit 22) in a format version 11 header",
               StatusCode::kCorrupt, {"3.1", "4", "10"}))
      ->edit = retool(0, 0, 11);
  surfaced(add("surface_without_chunks",
               "a format version 12 header declaring the surface without texture-chunks",
               StatusCode::kCorrupt, {"3.1", "10"}))
      ->edit = retool(kToolTextureChunks, 0, 12);
  // 'sfhd': step exponent u8, vertex count u32, data size u32.
  const auto edit_surface_head = [fragment](std::function<void(std::vector<uint8_t>*)> edit) {
    return [fragment, edit](std::vector<EditBox>* boxes) {
      return EditChunkedFragment(
          &fragment(boxes, 0),
          [edit](std::vector<EditBox>* subs) {
            edit(&(*subs)[FindBox(*subs, box::kSurfaceHead)].payload);
          },
          nullptr);
    };
  };
  surfaced(add("surface_vertex_count",
               "the first fragment's 'sfhd' declares one vertex more than the model has (head "
               "checksum recomputed)",
               StatusCode::kCorrupt, {"3.5.2", "10"}))
      ->edit =
      edit_surface_head([](std::vector<uint8_t>* p) { StoreLe(p, 1, LoadLe(*p, 1, 4) + 1, 4); });
  surfaced(add("surface_step_exponent_17", "the first fragment's 'sfhd' declares steps of 2^-17 m",
               StatusCode::kCorrupt, {"3.5.2", "10"}))
      ->edit = edit_surface_head([](std::vector<uint8_t>* p) { (*p)[0] = 17; });
  surfaced(add("surface_short_of_head",
               "the first fragment's 'sfhd' declares one byte more than its channel 3 chunks hold",
               StatusCode::kCorrupt, {"3.5.2", "10"}))
      ->edit =
      edit_surface_head([](std::vector<uint8_t>* p) { StoreLe(p, 5, LoadLe(*p, 5, 4) + 1, 4); });
  surfaced(add("surface_value_too_large",
               "a surface whose large swings reach 2^20 steps (one beyond the limit)",
               StatusCode::kCorrupt, {"3.5.2", "10"}))
      ->options.surface_amplitude = 1 << 20;
  surfaced(add("surface_outside_group_0",
               "the second fragment (camera group 1) carries the first fragment's 'sfhd' (head "
               "checksum recomputed; its chunks hold no channel 3; no index)",
               StatusCode::kCorrupt, {"3.5", "3.5.2", "10"}))
      ->edit = [fragment](std::vector<EditBox>* boxes) {
    FVV_RETURN_IF_ERROR(DropIndex(boxes));  // the second fragment grows
    FVV_ASSIGN_OR_RETURN(std::vector<EditBox> first, SplitBoxes(fragment(boxes, 0).payload));
    const EditBox head = first[FindBox(first, box::kSurfaceHead)];
    return EditChunkedFragment(
        &fragment(boxes, 1),
        [head](std::vector<EditBox>* subs) { subs->insert(subs->begin() + 1, head); }, nullptr);
  };
  chunked(add("index_head_size_wrong",
              "the index's first entry gives its fragment's head one byte more than it has",
              StatusCode::kCorrupt, {"3.5.1", "3.6", "10"}))
      ->edit = [](std::vector<EditBox>* boxes) {
    std::vector<uint8_t>& index = (*boxes)[FindBox(*boxes, box::kIndex)].payload;
    StoreLe(&index, 4 + 26, LoadLe(index, 4 + 26, 4) + 1, 4);
    return Status::Ok();
  };
  return v;
}

int Main(int argc, char** argv) {
  CLI::App app{"Makes the fvv conformance suite's cases (streams and test.json)."};
  std::string out, only;
  bool force = false;
  app.add_option("out", out, "conformance case directory (conformance/cases/)")->required();
  app.add_option("--only", only, "make only the case of this name (e.g. invalid/box_size_zero)");
  app.add_flag("--force", force, "remake cases that exist (released cases never change!)");
  CLI11_PARSE(app, argc, argv);
  mkdir((out + "/invalid").c_str(), 0755);
  std::vector<CaseSpec> all = ValidCases();
  for (CaseSpec& s : InvalidCases()) all.push_back(std::move(s));
  int made = 0;
  for (const CaseSpec& spec : all) {
    if (!only.empty() && spec.name != only) continue;
    const Status s = MakeCase(spec, out + "/" + spec.name, force);
    if (!s.ok()) {
      std::fprintf(stderr, "fvv_make_conformance: %s: %s\n", spec.name.c_str(),
                   s.ToString().c_str());
      return 1;
    }
    ++made;
  }
  if (made == 0) {
    std::fprintf(stderr, "fvv_make_conformance: no case named %s\n", only.c_str());
    return 1;
  }
  return 0;
}

}  // namespace
}  // namespace fvv

int main(int argc, char** argv) { return fvv::Main(argc, argv); }
