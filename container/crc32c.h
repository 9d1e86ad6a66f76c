// CRC-32C (Castagnoli): the fragment checksum of the fvv format (SPEC.md, "fcrc").
#ifndef FVV_CONTAINER_CRC32C_H_
#define FVV_CONTAINER_CRC32C_H_

#include <cstddef>
#include <cstdint>

namespace fvv {

// Reflected polynomial 0x82F63B78, initial value and final xor 0xFFFFFFFF.
// Pass the previous result as `crc` to continue over a further range.
uint32_t Crc32c(const uint8_t* data, size_t size, uint32_t crc = 0);

}  // namespace fvv

#endif  // FVV_CONTAINER_CRC32C_H_
