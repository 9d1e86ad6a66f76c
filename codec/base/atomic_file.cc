#include "codec/base/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace fvv {

std::string TempNameFor(const std::string& path) {
  return path + ".tmp" + std::to_string(::getpid());
}

Status CommitTempFile(const std::string& tmp, const std::string& path) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    return IoError("cannot rename " + tmp + " to " + path + ": " + why);
  }
  return Status::Ok();
}

Status WriteFileAtomic(const std::string& path, const uint8_t* data, size_t size) {
  const std::string tmp = TempNameFor(path);
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return IoError(path + ": cannot create (" + std::strerror(errno) + ")");
  const bool written = (size == 0 || std::fwrite(data, 1, size, f) == size) && std::fflush(f) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    std::remove(tmp.c_str());
    return IoError(path + ": write failed");
  }
  return CommitTempFile(tmp, path);
}

}  // namespace fvv
