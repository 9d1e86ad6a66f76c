// A fuzz target's scratch directory and file writes, for parsers that read
// files rather than bytes.
#ifndef FVV_FUZZ_TEMP_FILE_H_
#define FVV_FUZZ_TEMP_FILE_H_

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace fvv {

// A directory of this process's own under /tmp, made on the first call and
// removed with everything in it when the process exits.
inline const std::string& FuzzTempDir() {
  // Never destroyed: the exit handler that removes the directory reads it
  // after static objects are gone.
  static const std::string* dir = [] {
    char tmpl[] = "/tmp/fvv_fuzz_XXXXXX";
    const char* made = mkdtemp(tmpl);
    if (!made) return new std::string("/tmp");
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(FuzzTempDir(), ec);
    });
    return new std::string(made);
  }();
  return *dir;
}

inline bool WriteFuzzFile(const std::string& path, const void* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  std::fwrite(data, 1, size, f);
  return std::fclose(f) == 0;
}

}  // namespace fvv

#endif  // FVV_FUZZ_TEMP_FILE_H_
