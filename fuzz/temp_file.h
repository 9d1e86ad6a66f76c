// A fuzz target's scratch directory and file writes, for parsers that read
// files rather than bytes.
#ifndef FVV_FUZZ_TEMP_FILE_H_
#define FVV_FUZZ_TEMP_FILE_H_

#include <unistd.h>

#include <cstdio>
#include <string>

namespace fvv {

// A directory of this process's own under /tmp, made on the first call.
inline const std::string& FuzzTempDir() {
  static const std::string dir = [] {
    char tmpl[] = "/tmp/fvv_fuzz_XXXXXX";
    const char* made = mkdtemp(tmpl);
    return std::string(made ? made : "/tmp");
  }();
  return dir;
}

inline bool WriteFuzzFile(const std::string& path, const void* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  std::fwrite(data, 1, size, f);
  return std::fclose(f) == 0;
}

}  // namespace fvv

#endif  // FVV_FUZZ_TEMP_FILE_H_
