// SHA-256 of byte strings, as lowercase hex: the hash the conformance suite
// records for every decoded output file (so `sha256sum` checks them too).
#ifndef FVV_CONFORMANCE_LIB_SHA256_H_
#define FVV_CONFORMANCE_LIB_SHA256_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fvv {

// Empty only if OpenSSL cannot allocate.
std::string Sha256Hex(const uint8_t* data, size_t size);
inline std::string Sha256Hex(const std::vector<uint8_t>& bytes) {
  return Sha256Hex(bytes.data(), bytes.size());
}

}  // namespace fvv

#endif  // FVV_CONFORMANCE_LIB_SHA256_H_
