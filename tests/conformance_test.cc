// The conformance suite's machinery: hashing, the reference output, the runner
// in process and with external decoders (its failure modes), blessing, and the
// suite's coverage of versions, tools, levels and error codes.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <string>

#include "conformance/lib/conformance_case.h"
#include "conformance/lib/runner.h"
#include "conformance/lib/sha256.h"
#include "conformance/sample/sample_stream.h"
#include "container/file_header.h"
#include "fvv/fvv_types.h"
#include "gtest/gtest.h"

namespace fvv {
namespace {

const std::string kSuite = FVV_CONFORMANCE_DIR;

std::string TempDir(const std::string& name) {
  const std::string dir =
      ::testing::TempDir() + "/fvv_conformance_" + std::to_string(getpid()) + "_" + name;
  std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
  return dir;
}

// A copy of a suite case in a fresh directory, so a test may damage it.
std::string CopyCase(const std::string& name, const std::string& tag) {
  const std::string dir = TempDir(tag);
  EXPECT_EQ(std::system(("cp '" + kSuite + "/" + name + "'/* '" + dir + "'/").c_str()), 0);
  return dir;
}

ConformanceCase Load(const std::string& dir) {
  auto c = LoadCase(dir);
  EXPECT_TRUE(c.ok()) << c.status().ToString();
  return c.ok() ? std::move(c).value() : ConformanceCase{};
}

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(Sha256Hex(nullptr, 0),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  const std::string abc = "abc";
  EXPECT_EQ(Sha256Hex(reinterpret_cast<const uint8_t*>(abc.data()), abc.size()),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

// An independent check of the recorded hashes: the lossless case's whole-stream
// output, turned back into RGB by the spec's RCT (9.7), is the sample source.
TEST(ReferenceOutput, LosslessCaseReproducesTheSourceExactly) {
  const ConformanceCase c = Load(kSuite + "/lossless_53_rct");
  std::ifstream in(c.stream_path(), std::ios::binary);
  const std::vector<uint8_t> stream(std::istreambuf_iterator<char>(in), {});
  SampleStreamOptions o;
  o.frames = 4;
  o.cameras = 2;
  o.atlas_width = 24;
  o.atlas_height = 20;
  auto source = MakeSampleStream(o);
  ASSERT_TRUE(source.ok());
  const size_t texels = 24 * 20;
  size_t planes = 0, checked = 0;
  const Status s = ReferenceDecode(
      stream.data(), stream.size(), {},
      [&](const std::string& name, const std::vector<uint8_t>& bytes) {
        unsigned f, cam;
        if (std::sscanf(name.c_str(), "yuv_%u_%u.bin", &f, &cam) != 2) return Status::Ok();
        EXPECT_EQ(bytes.size(), texels * 3 * 2);
        const auto sample = [&](int channel, size_t i) {
          const size_t k = 2 * (channel * texels + i);
          return static_cast<int>(static_cast<int16_t>(bytes[k] | bytes[k + 1] << 8));
        };
        const uint8_t* used = &source->masks[(size_t{f} * 2 + cam) * texels];
        for (size_t i = 0; i < texels; ++i) {
          if (!used[i]) continue;  // unused texels carry no information (SPEC.md 7)
          ++checked;
          const int y = sample(0, i), u = sample(1, i), v = sample(2, i);
          const int g = y - ((u + v) >> 2);
          const uint8_t* rgb = &source->rgb[((size_t{f} * 2 + cam) * texels + i) * 3];
          if (v + g != rgb[0] || g != rgb[1] || u + g != rgb[2]) {
            ADD_FAILURE() << name << " texel " << i << " differs from the source";
            return Status::Ok();
          }
        }
        ++planes;
        return Status::Ok();
      });
  ASSERT_TRUE(s.ok()) << s.ToString();
  EXPECT_EQ(planes, 8u);
  EXPECT_GT(checked, texels * 8 / 4);  // a real share of the 8 views' texels
}

TEST(Runner, EveryCaseOfTheSuiteLoadsAndBudgetsChangeTheOutput) {
  auto dirs = FindCaseDirs(kSuite);
  ASSERT_TRUE(dirs.ok());
  ASSERT_GE(dirs->size(), 40u);
  for (const std::string& dir : *dirs) {
    const ConformanceCase c = Load(dir);
    ASSERT_TRUE(c.blessed()) << dir;
    if (c.expect_error) continue;
    ASSERT_EQ(c.budgets[0].bytes_per_fragment, 0u) << dir;
    // A truncation point that decodes like the whole stream checks nothing.
    for (size_t b = 1; b < c.budgets.size(); ++b) {
      EXPECT_NE(c.budgets[b].yuv, c.budgets[0].yuv)
          << dir << ": budget " << c.budgets[b].bytes_per_fragment << " decodes everything";
    }
  }
}

TEST(Runner, ReferenceDecoderPassesACaseAndFailsAChangedExpectation) {
  const std::string dir = CopyCase("basic_97_arith", "changed_hash");
  ConformanceCase c = Load(dir);
  EXPECT_TRUE(RunCase(c, {}).passed);
  // One sample file's expected hash at one budget changed.
  std::string& h = c.budgets[1].yuv.begin()->second;
  h[0] = h[0] == '0' ? '1' : '0';
  const CaseResult r = RunCase(c, {});
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("differs"), std::string::npos) << r.detail;
}

TEST(Runner, AChangedReleasedStreamFails) {
  const std::string dir = CopyCase("gop_1x1", "changed_stream");
  const ConformanceCase c = Load(dir);
  std::fstream f(c.stream_path(), std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(-1, std::ios::end);
  f.put('\x7f');
  f.close();
  const CaseResult r = RunCase(c, {});
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("not the released stream"), std::string::npos) << r.detail;
}

TEST(Runner, AnInvalidStreamMustGiveItsOwnCode) {
  ConformanceCase c = Load(kSuite + "/invalid/checksum_mismatch");
  EXPECT_TRUE(RunCase(c, {}).passed);
  c.error = StatusCode::kCorrupt;
  const CaseResult r = RunCase(c, {});
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("expected corrupt"), std::string::npos) << r.detail;
}

// SPEC.md 5.1: a case above the decoder's claimed level is reported as
// beyond it, not run, neither passed nor failed; a case within it runs.
TEST(Runner, CasesBeyondTheDecodersClaimAreReportedAsSuch) {
  const ConformanceCase high = Load(kSuite + "/level3_limits");
  ASSERT_EQ(high.level, 3);
  RunOptions o;
  o.max_level = 2;
  const CaseResult r = RunCase(high, o);
  EXPECT_FALSE(r.passed);
  EXPECT_TRUE(r.beyond_claim);
  EXPECT_NE(r.detail.find("beyond the decoder's claim"), std::string::npos) << r.detail;
  o.max_level = 3;
  EXPECT_TRUE(RunCase(high, o).passed);
  const CaseResult low = RunCase(Load(kSuite + "/gop_1x1"), o);
  EXPECT_TRUE(low.passed);
  EXPECT_FALSE(low.beyond_claim);
}

RunOptions External(const std::string& command) {
  RunOptions o;
  o.decoder = command;
  o.timeout_seconds = 2;
  o.work_dir = ::testing::TempDir();
  return o;
}

// The runner's verdict on external decoders that misbehave in each way.
TEST(Runner, ExternalDecoderFailureModes) {
  const ConformanceCase valid = Load(kSuite + "/gop_one_frame");
  const ConformanceCase invalid = Load(kSuite + "/invalid/box_size_zero");
  struct Expectation {
    const char* command;
    const ConformanceCase* c;
    const char* detail;  // nullptr: passes
    bool any_error = false;
  };
  const Expectation cases[] = {
      {"true {stream} {out}", &valid, "missing"},
      {"kill -SEGV $$ # {stream} {out}", &valid, "crashed"},
      {"sleep 30 # {stream} {out}", &valid, "ran past"},
      {"exit 3 # {stream} {out}", &valid, "exited 3"},
      {"echo x > {out}/extra.bin # {stream}", &valid, "extra.bin not expected"},
      {"true {stream} {out}", &invalid, "accepted"},
      {"exit 5 # {stream} {out}", &invalid, "expected 3"},
      {"exit 3 # {stream} {out}", &invalid, nullptr},
      {"exit 1 # {stream} {out}", &invalid, nullptr, true},
      {"kill -SEGV $$ # {stream} {out}", &invalid, "crashed", true},
  };
  for (const Expectation& e : cases) {
    RunOptions o = External(e.command);
    o.any_error = e.any_error;
    const CaseResult r = RunCase(*e.c, o);
    if (e.detail == nullptr) {
      EXPECT_TRUE(r.passed) << e.command << ": " << r.detail;
    } else {
      EXPECT_FALSE(r.passed) << e.command;
      EXPECT_NE(r.detail.find(e.detail), std::string::npos) << e.command << ": " << r.detail;
    }
  }
}

TEST(Runner, DecoderTemplateNeedsItsPlaceholders) {
  EXPECT_FALSE(CheckDecoderTemplate("mydec {stream}").ok());
  EXPECT_FALSE(CheckDecoderTemplate("mydec -o {out}").ok());
  EXPECT_TRUE(CheckDecoderTemplate("mydec {stream} -o {out} --bytes {bytes}").ok());
}

TEST(Cases, BadTestJsonIsRefusedWithTheField) {
  const std::string dir = TempDir("bad_json");
  const auto load_with = [&](const std::string& text) {
    std::ofstream(dir + "/test.json") << text;
    return LoadCase(dir);
  };
  EXPECT_EQ(load_with("{").status().code(), StatusCode::kCorrupt);
  auto r = load_with(R"({"format_version": 1, "expect": "maybe"})");
  EXPECT_NE(r.status().message().find("expect"), std::string::npos) << r.status().ToString();
  r = load_with(R"({"format_version": 1, "expect": "error", "error": {"code": 9, "name": "x"}})");
  EXPECT_NE(r.status().message().find("error.code"), std::string::npos);
  r = load_with(R"({"format_version": 1, "expect": "error", "error": {"code": 3, "name": "x"}})");
  EXPECT_NE(r.status().message().find("error.name"), std::string::npos);
  r = load_with(R"({"format_version": 1, "expect": "decode",
                    "budgets": [{"bytes_per_fragment": 0, "yuv": {"a.bin": "12"}}]})");
  EXPECT_NE(r.status().message().find("SHA-256"), std::string::npos);
  r = load_with(R"({"format_version": 1, "expect": "decode", "stream": "../x.fvv"})");
  EXPECT_NE(r.status().message().find("stream"), std::string::npos);
  EXPECT_EQ(LoadCase(dir + "/absent").status().code(), StatusCode::kIoError);
}

TEST(Cases, BlessFillsANewCaseAndRefusesAReleasedOne) {
  const std::string dir = CopyCase("motion_zstd", "bless");
  ConformanceCase c = Load(dir);
  const ConformanceCase released = c;
  EXPECT_EQ(BlessCase(&c, {}, false).code(), StatusCode::kInvalidArgument);
  c.budgets.clear();
  c.fixed.clear();
  c.stream_sha256.clear();
  ASSERT_TRUE(BlessCase(&c, {500}, false).ok());
  const ConformanceCase again = Load(dir);
  EXPECT_EQ(again.fixed, released.fixed);
  EXPECT_EQ(again.budgets[0].yuv, released.budgets[0].yuv);
  EXPECT_EQ(again.budgets[1].bytes_per_fragment, 500u);
  EXPECT_TRUE(RunCase(again, {}).passed);
}

// The suite covers every format version, coding tool, level and stream error.
TEST(Coverage, EveryVersionToolLevelAndErrorHasACase) {
  auto dirs = FindCaseDirs(kSuite);
  ASSERT_TRUE(dirs.ok());
  std::set<int> versions, levels, errors;
  std::set<std::string> tools;
  for (const std::string& dir : *dirs) {
    const ConformanceCase c = Load(dir);
    if (c.expect_error) {
      errors.insert(static_cast<int>(c.error));
      continue;
    }
    versions.insert(c.format_version);
    levels.insert(c.level);
    tools.insert(c.tools.begin(), c.tools.end());
  }
  for (int v = 1; v <= FVV_FORMAT_VERSION; ++v) EXPECT_TRUE(versions.count(v)) << "version " << v;
  for (int l = 1; l <= 4; ++l) EXPECT_TRUE(levels.count(l)) << "level " << l;
  for (int e = 2; e <= 6; ++e) EXPECT_TRUE(errors.count(e)) << "error code " << e;
  for (uint32_t bit = 1; bit != 0; bit <<= 1) {
    if (!(bit & kAllKnownTools)) continue;
    EXPECT_TRUE(tools.count(CodingToolName(bit))) << "tool " << CodingToolName(bit);
  }
}

// Annex B grows by new files only: a released case gains their hashes (the
// RGB of 9.7, the model, the cameras) while every hash it had still matches,
// and a case whose recorded hash no longer matches is refused.
TEST(Cases, NewOutputFilesAreAddedBesideTheReleasedOnes) {
  const std::string dir = CopyCase("chroma_420_odd", "add_outputs");
  ConformanceCase c = Load(dir);
  StatusOr<size_t> none = AddNewOutputs(&c);
  ASSERT_TRUE(none.ok()) << none.status().ToString();
  EXPECT_EQ(*none, 0u);
  ASSERT_TRUE(c.fixed.count("model.bin") && c.fixed.count("cameras.bin"));
  const OutputHashes rgb = c.budgets[0].rgb;
  ASSERT_EQ(rgb.size(), c.budgets[0].yuv.size());
  // As the case was before RGB, model and cameras were outputs.
  ConformanceCase older = c;
  older.fixed.erase("model.bin");
  older.fixed.erase("cameras.bin");
  for (BudgetExpectation& b : older.budgets) b.rgb.clear();
  StatusOr<size_t> added = AddNewOutputs(&older);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  EXPECT_EQ(*added, 2 + rgb.size() * c.budgets.size());
  EXPECT_EQ(older.budgets[0].rgb, rgb);
  EXPECT_EQ(Load(dir).fixed, c.fixed);  // saved
  ConformanceCase changed = c;
  changed.fixed["motion.bin"] = std::string(64, '0');
  changed.fixed.erase("model.bin");
  StatusOr<size_t> refused = AddNewOutputs(&changed);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("motion.bin no longer matches"), std::string::npos)
      << refused.status().message();
}

// A harness picks cases by test.json's format version, profile, level and
// tools: they are what the stream's own header says, also where the header
// is what makes the case invalid.
TEST(Cases, TestJsonStatesTheStreamsOwnHeader) {
  auto dirs = FindCaseDirs(kSuite);
  ASSERT_TRUE(dirs.ok());
  for (const std::string& dir : *dirs) {
    const ConformanceCase c = Load(dir);
    std::ifstream in(dir + "/" + c.stream, std::ios::binary);
    const std::vector<uint8_t> b(std::istreambuf_iterator<char>(in), {});
    ASSERT_GE(b.size(), 20u) << c.name;
    ASSERT_EQ(std::string(b.begin() + 4, b.begin() + 8), "fvvh") << c.name;
    const auto le = [&](size_t at, int bytes) {
      uint64_t v = 0;
      for (int i = bytes - 1; i >= 0; --i) v = v << 8 | b[12 + at + size_t(i)];
      return v;
    };
    std::vector<std::string> tools;
    for (int n = 0; n < 32; ++n) {
      if (!(le(4, 4) >> n & 1)) continue;
      const std::string name = CodingToolName(1u << n);
      tools.push_back(name == "unknown" ? "bit" + std::to_string(n) : name);
    }
    EXPECT_EQ(c.format_version, int(le(0, 2))) << c.name;
    EXPECT_EQ(c.profile, int(le(2, 1))) << c.name;
    EXPECT_EQ(c.level, int(le(3, 1))) << c.name;
    EXPECT_EQ(c.tools, tools) << c.name;
  }
}

// The README's table is how implementers find a case for a tool: it must name
// every case of the suite.
TEST(Coverage, ReadmeNamesEveryCase) {
  std::ifstream in(kSuite + "/../README.md");
  const std::string readme(std::istreambuf_iterator<char>(in), {});
  ASSERT_FALSE(readme.empty());
  auto dirs = FindCaseDirs(kSuite);
  ASSERT_TRUE(dirs.ok());
  for (const std::string& dir : *dirs) {
    const ConformanceCase c = Load(dir);
    EXPECT_NE(readme.find("| `" + c.name + "` |"), std::string::npos)
        << c.name << " is missing from conformance/README.md (fvv conform --list)";
  }
}

// The spec is the format's reference for implementers: its title and its
// versioning section must name the version the reader is.
TEST(Coverage, SpecNamesTheReadersFormatVersion) {
  std::ifstream in(kSuite + "/../../container/SPEC.md");
  const std::string spec(std::istreambuf_iterator<char>(in), {});
  ASSERT_FALSE(spec.empty());
  const std::string v = std::to_string(kFormatVersion);
  EXPECT_EQ(spec.rfind("# The fvv bitstream, format version " + v + " (normative)\n", 0), 0u)
      << "SPEC.md's title does not name format version " << v;
  EXPECT_NE(spec.find("\n- Version " + v + " ("), std::string::npos)
      << "SPEC.md section 4 has no entry for format version " << v;
  EXPECT_EQ(spec.find("\n- Version " + std::to_string(kFormatVersion + 1) + " ("),
            std::string::npos)
      << "SPEC.md section 4 describes a version the reader does not know";
}

}  // namespace
}  // namespace fvv
