#include "codec/base/large_buffer.h"
#include "codec/bitplane_dec.h"
#include "codec/quadtree4d.h"
#include "codec/spiht4d.h"

namespace fvv {

SpihtDecodeResult SpihtDecode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                              const uint8_t* data, size_t size, int planes, EntropyCoder coder,
                              const SpihtDecodeLimits& limits, std::vector<int32_t>* coefficients) {
  if (coder == EntropyCoder::kQuadtree) {
    return QuadtreeDecode(tree, quantisers, data, size, planes, limits, coefficients);
  }
  AssignLarge(coefficients, tree.size());
  const size_t budget = size < limits.max_bytes ? size : static_cast<size_t>(limits.max_bytes);
  BitplaneDecoder side(tree, data, budget, coder, limits, coefficients);
  SpihtTraverse(coder, tree, planes, &side);
  side.Reconstruct(tree, quantisers);
  return side.Result();
}

}  // namespace fvv
