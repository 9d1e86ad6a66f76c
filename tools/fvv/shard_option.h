// The --shard K/N option of the commands that work on one shard of a take.
#ifndef FVV_TOOLS_FVV_SHARD_OPTION_H_
#define FVV_TOOLS_FVV_SHARD_OPTION_H_

#include <cstdint>
#include <stdexcept>
#include <string>

#include "codec/base/status.h"

namespace fvv {

// "K/N", K from 0.
inline Status ParseShard(const std::string& text, uint32_t* k, uint32_t* n) {
  const size_t slash = text.find('/');
  try {
    size_t used_k = 0, used_n = 0;
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    const unsigned long kk = std::stoul(text.substr(0, slash), &used_k);
    const unsigned long nn = std::stoul(text.substr(slash + 1), &used_n);
    if (used_k != slash || used_n != text.size() - slash - 1 || nn == 0 || nn > 100000 ||
        kk >= nn) {
      throw std::invalid_argument("range");
    }
    *k = uint32_t(kk);
    *n = uint32_t(nn);
  } catch (const std::exception&) {
    return InvalidArgument("--shard " + text + " is not K/N with 0 <= K < N (e.g. 0/4)");
  }
  return Status::Ok();
}

}  // namespace fvv

#endif  // FVV_TOOLS_FVV_SHARD_OPTION_H_
