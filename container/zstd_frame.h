// The zstd frames of the format (the model data of SPEC.md 3.3, the motion's
// byte form of 6.3): the size a frame declares, and its decompression,
// checked. Backed by libzstd (zstd_frame.cc), or in the WebAssembly build by
// the page's zstd decompressor with the content checksum checked here
// (zstd_frame_web.cc).
#ifndef FVV_CONTAINER_ZSTD_FRAME_H_
#define FVV_CONTAINER_ZSTD_FRAME_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

// The content size the frame at `data` declares; Corrupt when it is not a
// zstd frame or declares none.
StatusOr<uint64_t> ZstdContentSize(const uint8_t* data, size_t size);

// Decompresses the frame into exactly out->size() bytes (its declared content
// size), checking its content checksum where it has one; Corrupt otherwise.
Status ZstdDecompress(const uint8_t* data, size_t size, std::vector<uint8_t>* out);

// The frame's zstd compression at `level`, with its content checksum (the
// writer's side: encoder builds only).
std::vector<uint8_t> ZstdCompress(const uint8_t* data, size_t size, int level);

// XXH64 of `data` with seed 0, whose low 32 bits are a zstd frame's content
// checksum (RFC 8878, 3.1.1).
uint64_t Xxh64(const uint8_t* data, size_t size);

}  // namespace fvv

#endif  // FVV_CONTAINER_ZSTD_FRAME_H_
