// Files written whole or not at all: the bytes go to a temporary name beside
// the target, which is renamed over it only once everything is written, so
// that an error or a kill never leaves a half-written file or loses the old one.
#ifndef FVV_CODEC_BASE_ATOMIC_FILE_H_
#define FVV_CODEC_BASE_ATOMIC_FILE_H_

#include <cstddef>
#include <cstdint>
#include <string>

#include "codec/base/status.h"

namespace fvv {

// The temporary name for `path` (same directory, so the rename is atomic).
std::string TempNameFor(const std::string& path);
// Renames tmp over path (removing tmp when that fails).
Status CommitTempFile(const std::string& tmp, const std::string& path);
Status WriteFileAtomic(const std::string& path, const uint8_t* data, size_t size);

}  // namespace fvv

#endif  // FVV_CODEC_BASE_ATOMIC_FILE_H_
