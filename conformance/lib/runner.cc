#include "conformance/lib/runner.h"

#include <ftw.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "conformance/lib/sha256.h"
#include "encoder/io/image_io.h"
#include "fvv/fvv_types.h"

namespace fvv {
namespace {

bool StartsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// "" when `actual` holds exactly the expected files with the expected hashes.
// A decoder that writes no vertex visibility at all is allowed (the box is not
// essential, SPEC.md 8), and so is one that writes no surface (Annex B.1);
// one that writes some must write them right.
std::string Compare(const OutputHashes& expected, const OutputHashes& actual, std::string* note) {
  static const char* const kOptional[2] = {"vvis_", "surface_"};
  static const char* const kWhat[2] = {"vertex visibility", "surface"};
  bool any[2] = {false, false};
  for (const auto& a : actual) {
    for (int k = 0; k < 2; ++k) any[k] = any[k] || StartsWith(a.first, kOptional[k]);
  }
  std::vector<std::string> problems;
  for (const auto& a : actual) {
    if (!expected.count(a.first)) problems.push_back(a.first + " not expected");
  }
  size_t skipped[2] = {0, 0};
  for (const auto& e : expected) {
    const auto it = actual.find(e.first);
    if (it == actual.end()) {
      bool optional = false;
      for (int k = 0; k < 2; ++k) {
        if (StartsWith(e.first, kOptional[k]) && !any[k]) optional = true, ++skipped[k];
      }
      if (!optional) problems.push_back(e.first + " missing");
    } else if (it->second != e.second) {
      problems.push_back(e.first + " differs");
    }
  }
  std::string skipped_note;
  for (int k = 0; k < 2; ++k) {
    if (!skipped[k]) continue;
    skipped_note += std::string(skipped_note.empty() ? "" : "; ") + kWhat[k] +
                    " not output (optional), not checked";
  }
  if (note && !skipped_note.empty()) *note = skipped_note;
  if (problems.empty()) return {};
  std::string out = std::to_string(problems.size()) + " output file(s) wrong: ";
  for (size_t i = 0; i < problems.size() && i < 3; ++i) out += (i ? ", " : "") + problems[i];
  if (problems.size() > 3) out += ", ...";
  return out;
}

OutputHashes Expected(const ConformanceCase& c, const BudgetExpectation& b) {
  OutputHashes all = c.fixed;
  all.insert(b.yuv.begin(), b.yuv.end());
  all.insert(b.rgb.begin(), b.rgb.end());
  all.insert(b.surface.begin(), b.surface.end());
  return all;
}

std::string BudgetName(uint64_t bytes) {
  return bytes == 0 ? "whole streams" : std::to_string(bytes) + " bytes per fragment";
}

const char* PathName(ReadPath p) {
  return p == ReadPath::kStreaming ? "streaming reader" : "random-access reader";
}

std::string RunReference(const ConformanceCase& c, const std::vector<uint8_t>& stream,
                         const RunOptions& options, std::string* note) {
  for (const ReadPath path : {ReadPath::kRandomAccess, ReadPath::kStreaming}) {
    ReferenceDecodeOptions o;
    o.path = path;
    o.threads = options.threads;
    if (c.expect_error) {
      o.bytes_per_fragment = c.error_bytes_per_fragment;
      const auto got = ReferenceDecodeHashes(stream, o);
      if (got.ok()) return std::string(PathName(path)) + ": decoded a stream it must reject";
      if (got.status().code() != c.error) {
        return std::string(PathName(path)) + ": expected " + StatusCodeName(c.error) + ", got " +
               got.status().ToString();
      }
      continue;
    }
    for (const BudgetExpectation& b : c.budgets) {
      o.bytes_per_fragment = b.bytes_per_fragment;
      const auto got = ReferenceDecodeHashes(stream, o);
      if (!got.ok()) return std::string(PathName(path)) + ": " + got.status().ToString();
      const std::string diff = Compare(Expected(c, b), *got, note);
      if (!diff.empty()) {
        return std::string(PathName(path)) + ", " + BudgetName(b.bytes_per_fragment) + ": " + diff;
      }
    }
  }
  return {};
}

std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

std::string Substitute(const std::string& tmpl, const std::string& stream, const std::string& out,
                       uint64_t bytes) {
  std::string cmd;
  for (size_t i = 0; i < tmpl.size();) {
    if (tmpl.compare(i, 8, "{stream}") == 0) {
      cmd += ShellQuote(stream);
      i += 8;
    } else if (tmpl.compare(i, 5, "{out}") == 0) {
      cmd += ShellQuote(out);
      i += 5;
    } else if (tmpl.compare(i, 7, "{bytes}") == 0) {
      cmd += std::to_string(bytes);
      i += 7;
    } else {
      cmd += tmpl[i++];
    }
  }
  return cmd;
}

int RemoveEntry(const char* path, const struct stat*, int, struct FTW*) {
  return std::remove(path);
}
void RemoveTree(const std::string& dir) {
  nftw(dir.c_str(), RemoveEntry, 16, FTW_DEPTH | FTW_PHYS);
}

std::string Tail(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last.empty() ? "" : " (decoder said: " + last + ")";
}

struct ExternalRun {
  int exit_code = -1;  // -1: did not start or died by a signal
  bool timed_out = false;
  std::string log_tail;
  OutputHashes outputs;
  std::string error;  // the runner's own problem
};

ExternalRun RunExternal(const RunOptions& options, const std::string& stream, uint64_t bytes) {
  ExternalRun r;
  std::string work = options.work_dir + "/fvv-conform-XXXXXX";
  if (!mkdtemp(work.data())) {
    r.error = "cannot create a work directory in " + options.work_dir;
    return r;
  }
  const std::string out = work + "/out", log = work + "/decoder.log";
  if (mkdir(out.c_str(), 0755) != 0) {
    r.error = "cannot create " + out;
    RemoveTree(work);
    return r;
  }
  const std::string cmd = "timeout -k 5 " + std::to_string(options.timeout_seconds) + " sh -c " +
                          ShellQuote(Substitute(options.decoder, stream, out, bytes)) + " >" +
                          ShellQuote(log) + " 2>&1";
  const int status = std::system(cmd.c_str());
  if (status != -1 && WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == 124) {
      r.timed_out = true;
    } else if (code < 126) {  // 126/127: not runnable; >= 128: killed by a signal
      r.exit_code = code;
    } else {
      r.exit_code = -1;
      r.error = code == 126 || code == 127
                    ? "decoder command could not run (exit " + std::to_string(code) + ")"
                    : "decoder crashed (exit " + std::to_string(code) + ")";
    }
  } else {
    r.error = "decoder crashed or could not start";
  }
  r.log_tail = Tail(log);
  if (r.exit_code == 0) {
    auto hashes = HashDirectory(out);
    if (hashes.ok()) {
      r.outputs = std::move(hashes).value();
    } else {
      r.error = hashes.status().ToString();
    }
  }
  RemoveTree(work);
  return r;
}

std::string RunWithExternal(const ConformanceCase& c, const RunOptions& options,
                            std::string* note) {
  const std::string stream = c.stream_path();
  if (c.expect_error) {
    if (c.error_bytes_per_fragment != 0 && options.decoder.find("{bytes}") == std::string::npos) {
      return "the case decodes at a budget of " + std::to_string(c.error_bytes_per_fragment) +
             " bytes per fragment, and the decoder command has no {bytes}";
    }
    const ExternalRun r = RunExternal(options, stream, c.error_bytes_per_fragment);
    if (!r.error.empty()) return r.error + r.log_tail;
    if (r.timed_out) return "decoder ran past " + std::to_string(options.timeout_seconds) + " s";
    if (r.exit_code == 0) return "decoder accepted a stream it must reject";
    if (!options.any_error && r.exit_code != static_cast<int>(c.error)) {
      return "decoder exited " + std::to_string(r.exit_code) + ", expected " +
             std::to_string(static_cast<int>(c.error)) + " (" + StatusCodeName(c.error) + ")" +
             r.log_tail;
    }
    return {};
  }
  for (const BudgetExpectation& b : c.budgets) {
    const ExternalRun r = RunExternal(options, stream, b.bytes_per_fragment);
    const std::string where = BudgetName(b.bytes_per_fragment) + ": ";
    if (!r.error.empty()) return where + r.error + r.log_tail;
    if (r.timed_out) {
      return where + "decoder ran past " + std::to_string(options.timeout_seconds) + " s";
    }
    if (r.exit_code != 0) {
      return where + "decoder exited " + std::to_string(r.exit_code) + r.log_tail;
    }
    const std::string diff = Compare(Expected(c, b), r.outputs, note);
    if (!diff.empty()) return where + diff;
  }
  return {};
}

}  // namespace

Status CheckDecoderTemplate(const std::string& decoder) {
  if (decoder.find("{stream}") == std::string::npos || decoder.find("{out}") == std::string::npos) {
    return InvalidArgument(
        "the decoder command needs {stream} and {out} placeholders (and "
        "{bytes} for truncation budgets): \"" +
        decoder + "\"");
  }
  return Status::Ok();
}

CaseResult RunCase(const ConformanceCase& c, const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CaseResult result;
  result.name = c.name;
  const auto finish = [&](std::string problem) {
    result.passed = problem.empty();
    if (!problem.empty()) result.detail = std::move(problem);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  };
  if (c.decoder_version < 1 || c.decoder_version > FVV_FORMAT_VERSION) {
    return finish("format version " + std::to_string(c.decoder_version) +
                  " is not one this build knows (1.." + std::to_string(FVV_FORMAT_VERSION) + ")");
  }
  if (!c.blessed()) return finish("test.json has no expectations (run fvv conform --bless)");
  if (options.max_level != 0 && c.level > options.max_level) {
    result.beyond_claim = true;
    return finish("level " + std::to_string(c.level) + ", beyond the decoder's claim (level " +
                  std::to_string(options.max_level) + ")");
  }
  auto stream = ReadFileBytes(c.stream_path(), kMaxConformanceFileBytes);
  if (!stream.ok()) return finish(stream.status().ToString());
  if (c.stream_sha256.empty() || Sha256Hex(*stream) != c.stream_sha256) {
    return finish(c.stream + " is not the released stream (its SHA-256 differs from test.json)");
  }
  if (!c.expect_error && (c.budgets.empty() || c.budgets[0].bytes_per_fragment != 0)) {
    return finish("test.json must list the whole-stream budget (0) first");
  }
  std::string note;
  std::string problem = options.decoder.empty() ? RunReference(c, *stream, options, &note)
                                                : RunWithExternal(c, options, &note);
  if (problem.empty()) result.detail = note;
  return finish(std::move(problem));
}

StatusOr<size_t> AddNewOutputs(ConformanceCase* c) {
  if (c->expect_error || !c->blessed()) return size_t{0};
  FVV_ASSIGN_OR_RETURN(const std::vector<uint8_t> stream,
                       ReadFileBytes(c->stream_path(), kMaxConformanceFileBytes));
  if (Sha256Hex(stream) != c->stream_sha256) {
    return Corrupt(c->name + ": the stream differs from the released one");
  }
  size_t added = 0;
  for (BudgetExpectation& b : c->budgets) {
    ReferenceDecodeOptions o;
    o.bytes_per_fragment = b.bytes_per_fragment;
    FVV_ASSIGN_OR_RETURN(const OutputHashes got, ReferenceDecodeHashes(stream, o));
    const OutputHashes expected = Expected(*c, b);
    for (const auto& [name, hash] : expected) {
      const auto it = got.find(name);
      if (it == got.end() || it->second != hash) {
        return Corrupt(c->name + ", " + BudgetName(b.bytes_per_fragment) + ": " + name +
                       " no longer matches its released hash");
      }
    }
    for (const auto& h : got) {
      if (expected.count(h.first)) continue;
      if (StartsWith(h.first, "yuv_")) {
        return Corrupt(c->name + ": " + h.first + " appeared (the frames are released)");
      }
      if (StartsWith(h.first, "rgb_")) {
        b.rgb.insert(h);
      } else if (b.bytes_per_fragment == 0) {
        c->fixed.insert(h);
      } else {
        continue;
      }
      ++added;
    }
  }
  if (added) FVV_RETURN_IF_ERROR(SaveCase(*c));
  return added;
}

Status BlessCase(ConformanceCase* c, const std::vector<uint64_t>& budgets, bool force) {
  if (c->blessed() && !c->stream_sha256.empty() && !force) {
    return InvalidArgument(c->dir +
                           " already has expectations; released cases never change "
                           "(a format change adds cases)");
  }
  FVV_ASSIGN_OR_RETURN(const std::vector<uint8_t> stream,
                       ReadFileBytes(c->stream_path(), kMaxConformanceFileBytes));
  c->stream_sha256 = Sha256Hex(stream);
  ReferenceDecodeOptions o;
  if (c->expect_error) {
    o.bytes_per_fragment = c->error_bytes_per_fragment;
    for (const ReadPath path : {ReadPath::kRandomAccess, ReadPath::kStreaming}) {
      o.path = path;
      const auto got = ReferenceDecodeHashes(stream, o);
      if (got.ok() || got.status().code() != c->error) {
        return InvalidArgument(c->name + ": the " + PathName(path) + " gives " +
                               (got.ok() ? std::string("no error") : got.status().ToString()) +
                               ", the case expects " + StatusCodeName(c->error));
      }
    }
    return SaveCase(*c);
  }
  c->fixed.clear();
  c->budgets.clear();
  std::vector<uint64_t> all{0};
  for (uint64_t b : budgets) {
    if (b != 0 && std::find(all.begin(), all.end(), b) == all.end()) all.push_back(b);
  }
  for (uint64_t b : all) {
    o.bytes_per_fragment = b;
    FVV_ASSIGN_OR_RETURN(const OutputHashes hashes, ReferenceDecodeHashes(stream, o));
    BudgetExpectation e;
    e.bytes_per_fragment = b;
    for (const auto& h : hashes) {
      if (StartsWith(h.first, "yuv_")) {
        e.yuv.insert(h);
      } else if (StartsWith(h.first, "rgb_")) {
        e.rgb.insert(h);
      } else if (StartsWith(h.first, "surface_")) {
        e.surface.insert(h);
      } else if (b == 0) {
        c->fixed.insert(h);
      }
    }
    c->budgets.push_back(std::move(e));
  }
  return SaveCase(*c);
}

}  // namespace fvv
