#include "codec/base/large_buffer.h"
#include "codec/bitplane_dec.h"
#include "codec/quadtree4d.h"
#include "codec/quadtree4d_common.h"

namespace fvv {

SpihtDecodeResult QuadtreeDecode(const SpihtTree& tree, const SubbandQuantisers& quantisers,
                                 const uint8_t* data, size_t size, int planes,
                                 const SpihtDecodeLimits& limits,
                                 std::vector<int32_t>* coefficients) {
  AssignLarge(coefficients, tree.size());
  const size_t budget = size < limits.max_bytes ? size : static_cast<size_t>(limits.max_bytes);
  BitplaneDecoder side(tree, data, budget, EntropyCoder::kQuadtree, limits, coefficients);
  const QuadtreeLayout layout(tree.geometry());
  QuadtreeTraversal<BitplaneDecoder>(layout, &side).Run(planes);
  side.Reconstruct(tree, quantisers);
  return side.Result();
}

}  // namespace fvv
