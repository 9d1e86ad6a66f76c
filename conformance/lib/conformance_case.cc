#include "conformance/lib/conformance_case.h"

#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "encoder/io/image_io.h"

namespace fvv {
namespace {

using nlohmann::json;

bool IsDirectory(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}
bool IsFile(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool IsHash(const std::string& s) {
  return s.size() == 64 && std::all_of(s.begin(), s.end(), [](char ch) {
           return (ch >= '0' && ch <= '9') || (ch >= 'a' && ch <= 'f');
         });
}

Status ReadHashes(const json& j, const std::string& where, OutputHashes* out) {
  if (!j.is_object()) return Corrupt(where + " is not an object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!it.value().is_string() || !IsHash(it.value().get<std::string>())) {
      return Corrupt(where + "[\"" + it.key() + "\"] is not a SHA-256 hex string");
    }
    if (it.key().empty() || it.key().find('/') != std::string::npos) {
      return Corrupt(where + ": bad output file name \"" + it.key() + "\"");
    }
    (*out)[it.key()] = it.value().get<std::string>();
  }
  return Status::Ok();
}

std::vector<std::string> Strings(const json& j) {
  std::vector<std::string> out;
  if (j.is_array()) {
    for (const json& s : j) {
      if (s.is_string()) out.push_back(s.get<std::string>());
    }
  }
  return out;
}

Status FindIn(const std::string& dir, std::vector<std::string>* out) {
  if (IsFile(dir + "/test.json")) {
    out->push_back(dir);
    return Status::Ok();
  }
  std::unique_ptr<DIR, int (*)(DIR*)> d(opendir(dir.c_str()), &closedir);
  if (!d) return IoError("cannot read directory " + dir);
  std::vector<std::string> children;
  while (const dirent* e = readdir(d.get())) {
    const std::string name = e->d_name;
    if (name == "." || name == ".." || !IsDirectory(dir + "/" + name)) continue;
    children.push_back(dir + "/" + name);
  }
  for (const std::string& child : children) FVV_RETURN_IF_ERROR(FindIn(child, out));
  return Status::Ok();
}

}  // namespace

StatusOr<ConformanceCase> LoadCase(const std::string& dir) {
  const std::string path = dir + "/test.json";
  std::ifstream in(path);
  if (!in) return IoError("cannot read " + path);
  json j;
  try {
    in >> j;
  } catch (const json::exception& e) {
    return Corrupt(path + ": not JSON (" + e.what() + ")");
  }
  const auto fail = [&path](const std::string& what) { return Corrupt(path + ": " + what); };
  if (!j.is_object()) return fail("not a JSON object");
  ConformanceCase c;
  c.dir = dir;
  try {
    c.name = j.value("name", dir.substr(dir.find_last_of('/') + 1));
    c.description = j.value("description", "");
    c.format_version = j.at("format_version").get<int>();
    c.decoder_version = j.value("decoder_version", c.format_version);
    c.profile = j.value("profile", 1);
    c.level = j.value("level", 1);
    c.tools = Strings(j.value("tools", json::array()));
    c.spec_sections = Strings(j.value("spec_sections", json::array()));
    c.stream = j.value("stream", "stream.fvv");
    c.stream_sha256 = j.value("stream_sha256", "");
    const std::string expect = j.at("expect").get<std::string>();
    if (expect == "error") {
      c.expect_error = true;
      const json& e = j.at("error");
      const int code = e.at("code").get<int>();
      if (code < static_cast<int>(StatusCode::kTruncated) ||
          code > static_cast<int>(StatusCode::kChecksumMismatch)) {
        return fail("error.code " + std::to_string(code) + " is not a stream error (2..6)");
      }
      c.error = static_cast<StatusCode>(code);
      if (e.value("name", "") != StatusCodeName(c.error)) {
        return fail("error.name does not match code " + std::to_string(code) + " (\"" +
                    StatusCodeName(c.error) + "\")");
      }
      c.error_bytes_per_fragment = j.value("bytes_per_fragment", uint64_t{0});
    } else if (expect == "decode") {
      if (j.contains("outputs")) FVV_RETURN_IF_ERROR(ReadHashes(j["outputs"], "outputs", &c.fixed));
      for (const json& b : j.value("budgets", json::array())) {
        BudgetExpectation e;
        e.bytes_per_fragment = b.at("bytes_per_fragment").get<uint64_t>();
        FVV_RETURN_IF_ERROR(ReadHashes(b.at("yuv"), "budgets[].yuv", &e.yuv));
        if (b.contains("rgb")) FVV_RETURN_IF_ERROR(ReadHashes(b["rgb"], "budgets[].rgb", &e.rgb));
        if (b.contains("surface")) {
          FVV_RETURN_IF_ERROR(ReadHashes(b["surface"], "budgets[].surface", &e.surface));
        }
        c.budgets.push_back(std::move(e));
      }
    } else {
      return fail("expect must be \"decode\" or \"error\"");
    }
  } catch (const json::exception& e) {
    return fail(std::string("bad field: ") + e.what());
  }
  if (c.stream.empty() || c.stream.find('/') != std::string::npos) {
    return fail("stream must be a file name in the case directory");
  }
  if (!c.stream_sha256.empty() && !IsHash(c.stream_sha256)) {
    return fail("stream_sha256 is not a SHA-256 hex string");
  }
  return c;
}

Status SaveCase(const ConformanceCase& c) {
  nlohmann::ordered_json j;  // fields in the order a reader wants them
  j["name"] = c.name;
  j["description"] = c.description;
  j["format_version"] = c.format_version;
  j["profile"] = c.profile;
  j["level"] = c.level;
  j["tools"] = c.tools;
  if (c.decoder_version != c.format_version) j["decoder_version"] = c.decoder_version;
  j["spec_sections"] = c.spec_sections;
  j["stream"] = c.stream;
  if (!c.stream_sha256.empty()) j["stream_sha256"] = c.stream_sha256;
  if (c.expect_error) {
    j["expect"] = "error";
    j["error"] = {{"code", static_cast<int>(c.error)}, {"name", StatusCodeName(c.error)}};
    if (c.error_bytes_per_fragment != 0) j["bytes_per_fragment"] = c.error_bytes_per_fragment;
  } else {
    j["expect"] = "decode";
    if (!c.fixed.empty()) j["outputs"] = c.fixed;
    nlohmann::ordered_json budgets = nlohmann::ordered_json::array();
    for (const BudgetExpectation& b : c.budgets) {
      nlohmann::ordered_json e = {
          {"bytes_per_fragment", b.bytes_per_fragment}, {"yuv", b.yuv}, {"rgb", b.rgb}};
      if (!b.surface.empty()) e["surface"] = b.surface;
      budgets.push_back(std::move(e));
    }
    j["budgets"] = budgets;
  }
  const std::string text = j.dump(1) + "\n";
  return WriteFileAtomic(c.dir + "/test.json", reinterpret_cast<const uint8_t*>(text.data()),
                         text.size());
}

StatusOr<std::vector<std::string>> FindCaseDirs(const std::string& root) {
  if (!IsDirectory(root)) return IoError(root + " is not a directory");
  std::vector<std::string> dirs;
  FVV_RETURN_IF_ERROR(FindIn(root, &dirs));
  std::sort(dirs.begin(), dirs.end());
  return dirs;
}

}  // namespace fvv
