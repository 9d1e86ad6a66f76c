#include "container/vertex_visibility.h"

#include "codec/range_coder.h"

namespace fvv {
namespace {

// Shared coding order: `code(bit, prob)` encodes or decodes one decision.
template <class Code>
void Traverse(uint32_t frames, uint32_t cameras, uint32_t vertices, std::vector<uint8_t>* bits,
              Code code) {
  uint16_t ctx[2][2] = {{kProbInit, kProbInit}, {kProbInit, kProbInit}};
  const size_t plane = size_t{cameras} * vertices;
  for (uint32_t t = 0; t < frames; ++t) {
    for (uint32_t c = 0; c < cameras; ++c) {
      uint8_t* row = bits->data() + t * plane + size_t{c} * vertices;
      const uint8_t* prev = t > 0 ? row - plane : nullptr;
      uint32_t left = 0;
      for (uint32_t v = 0; v < vertices; ++v) {
        left = row[v] = static_cast<uint8_t>(code(row[v], &ctx[prev ? prev[v] : 0][left]));
      }
    }
  }
}

}  // namespace

std::vector<uint8_t> EncodeVertexVisibility(const std::vector<uint8_t>& bits, uint32_t frames,
                                            uint32_t cameras, uint32_t vertices) {
  std::vector<uint8_t> copy(bits.size());
  for (size_t i = 0; i < bits.size(); ++i) copy[i] = bits[i] != 0;
  RangeEncoder rc;
  Traverse(frames, cameras, vertices, &copy, [&](uint32_t bit, uint16_t* p) {
    rc.Encode(bit, p);
    return bit;
  });
  return rc.Finish();
}

Status DecodeVertexVisibility(const uint8_t* data, size_t size, uint32_t frames, uint32_t cameras,
                              uint32_t vertices, std::vector<uint8_t>* bits) {
  bits->assign(size_t{frames} * cameras * vertices, 0);
  RangeDecoder rc(data, size);
  Traverse(frames, cameras, vertices, bits, [&](uint32_t, uint16_t* p) { return rc.Decode(p); });
  if (!rc.ok()) return Corrupt("vertex visibility data ends early");
  return Status::Ok();
}

}  // namespace fvv
