// Coder 4: the quadtree significance coder (format version 8, SPEC.md 9.9).
// Same streams, truncation points and budgets as SPIHT's (spiht4d.h); the
// layout and the traversal are in quadtree4d_common.h.
#ifndef FVV_CODEC_QUADTREE4D_H_
#define FVV_CODEC_QUADTREE4D_H_

#include <cstdint>
#include <vector>

#include "codec/spiht4d.h"

namespace fvv {

SpihtEncoded QuadtreeEncode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                            const std::vector<int32_t>& coefficients, uint64_t max_bytes);

SpihtDecodeResult QuadtreeDecode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                                 const uint8_t* data, size_t size, int planes,
                                 const SpihtDecodeLimits& limits,
                                 std::vector<int32_t>* coefficients);

}  // namespace fvv

#endif  // FVV_CODEC_QUADTREE4D_H_
