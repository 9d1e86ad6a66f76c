// Box-level editing of whole streams, for making the conformance suite's edge
// cases and invalid streams from valid ones: split a stream into its boxes,
// change them, join them again (fragment checksums recomputed on request).
#ifndef FVV_CONFORMANCE_GENERATOR_STREAM_EDIT_H_
#define FVV_CONFORMANCE_GENERATOR_STREAM_EDIT_H_

#include <cstdint>
#include <functional>
#include <vector>

#include "codec/base/status.h"
#include "container/box.h"

namespace fvv {

struct EditBox {
  FourCC type = 0;
  uint8_t version = 0;
  uint32_t flags = 0;
  std::vector<uint8_t> payload;
  bool large = false;  // write the 64-bit size form even when 32 bits would do
};

StatusOr<std::vector<EditBox>> SplitBoxes(const std::vector<uint8_t>& bytes);
std::vector<uint8_t> JoinBoxes(const std::vector<EditBox>& boxes);

// Offset of box i in JoinBoxes(boxes).
uint64_t BoxOffset(const std::vector<EditBox>& boxes, size_t i);
// Index of the n-th (0-based) box of `type`, or -1.
int FindBox(const std::vector<EditBox>& boxes, FourCC type, int n = 0);

// A fragment's sub-boxes, edited by `edit`, joined again with a fresh fcrc.
Status EditFragment(EditBox* fragment, const std::function<void(std::vector<EditBox>*)>& edit);

// Removes the index box and clears the header's index_offset (readers then
// rebuild the index by scanning), so that boxes can move.
Status DropIndex(std::vector<EditBox>* boxes);
// Edits a chunked fragment (texture-chunks, SPEC.md 3.5.1): `head` gets its
// sub-boxes before 'fcrc', `chunks` the payload of 'txck'; the head's checksum
// is recomputed (the chunks' own are the edit's business: RechecksumChunk).
Status EditChunkedFragment(EditBox* fragment,
                           const std::function<void(std::vector<EditBox>*)>& head,
                           const std::function<void(std::vector<uint8_t>*)>& chunks);
// Recomputes the CRC-32C of the chunk that starts at `at` in a 'txck' payload.
void RechecksumChunk(std::vector<uint8_t>* chunks, size_t at);

// Little-endian stores into a payload.
void StoreLe(std::vector<uint8_t>* payload, size_t offset, uint64_t value, int bytes);
// The little-endian value of `bytes` bytes at `offset` (0 past the end).
uint64_t LoadLe(const std::vector<uint8_t>& payload, size_t offset, int bytes);

// Field offsets in the fvvh payload (SPEC.md 3.1).
namespace fvvh {
constexpr size_t kFormatVersion = 0, kProfile = 2, kLevel = 3, kTools = 4, kFrameRateNum = 8,
                 kFrameRateDen = 12, kFrameCount = 16, kCameraCount = 20, kAtlasWidth = 22,
                 kAtlasHeight = 24, kGopFrames = 26, kGopCameras = 28, kIndexOffset = 30;
}  // namespace fvvh

}  // namespace fvv

#endif  // FVV_CONFORMANCE_GENERATOR_STREAM_EDIT_H_
