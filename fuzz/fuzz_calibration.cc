// Fuzz target: the studio calibration importers of `fvv capture import-calib`.
// Byte 0 picks the format by file name: OpenCV FileStorage YAML, EasyMocap
// (intri.yml and extri.yml, split at the first line "==="), TOML, Qualisys
// .qca.txt. The rest is the file(s), written to a temporary directory because
// the importers read files.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "encoder/capture/calibration_import.h"
#include "fuzz/temp_file.h"

namespace {

bool Write(const std::string& path, const std::string& bytes) {
  return fvv::WriteFuzzFile(path, bytes.data(), bytes.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string& dir = fvv::FuzzTempDir();
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::vector<std::string> paths;
  switch (data[0] % 4) {
    case 0:
      paths = {dir + "/cam.yml"};
      if (!Write(paths[0], text)) return 0;
      break;
    case 1: {
      const size_t split = text.find("\n===\n");
      paths = {dir + "/intri.yml", dir + "/extri.yml"};
      if (!Write(paths[0], text.substr(0, split)) ||
          !Write(paths[1], split == std::string::npos ? "" : text.substr(split + 5))) {
        return 0;
      }
      break;
    }
    case 2:
      paths = {dir + "/rig.toml"};
      if (!Write(paths[0], text)) return 0;
      break;
    default:
      paths = {dir + "/Calib.qca.txt"};
      if (!Write(paths[0], text)) return 0;
      break;
  }
  (void)fvv::ImportCalibrationFiles(paths, 1.0);
  for (const std::string& p : paths) std::remove(p.c_str());
  return 0;
}
