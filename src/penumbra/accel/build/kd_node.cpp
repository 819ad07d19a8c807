#include "penumbra/accel/build/kd_node.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "penumbra/core/error.h"

namespace penumbra {

int kd_depth_limit(const KdBuildParams& params, size_t n) {
  if (params.max_depth > 0) return std::min(params.max_depth, kKdMaxDepth);
  // pbrt-v3 (section 4.4.2): 8 + 1.3 log2 N, with the integer logarithm.
  const int log2n = n > 1 ? int(std::bit_width(n)) - 1 : 0;
  return std::min(int(std::lround(8.0 + 1.3 * log2n)), kKdMaxDepth);
}

void KdSubtree::add_leaf(const std::vector<KdPrim>& prims, int depth) {
  if (refs.size() + prims.size() > kKdMaxIndex || nodes.size() >= kKdMaxIndex)
    throw Error("kdtree: more than 2^30 nodes or primitive references");
  nodes.push_back(KdNode::leaf(uint32_t(refs.size()), uint32_t(prims.size())));
  for (const KdPrim& p : prims) refs.push_back(p.id);
  ++leaves;
  empty_leaves += prims.empty();
  max_depth = std::max(max_depth, size_t(depth));
}

void KdSubtree::append(const KdSubtree& other) {
  if (nodes.size() + other.nodes.size() > kKdMaxIndex ||
      refs.size() + other.refs.size() > kKdMaxIndex)
    throw Error("kdtree: more than 2^30 nodes or primitive references");
  const auto node_base = uint32_t(nodes.size()), ref_base = uint32_t(refs.size());
  nodes.reserve(nodes.size() + other.nodes.size());
  for (const KdNode& n : other.nodes) nodes.push_back(n.shifted(node_base, ref_base));
  refs.insert(refs.end(), other.refs.begin(), other.refs.end());
  leaves += other.leaves;
  empty_leaves += other.empty_leaves;
  max_depth = std::max(max_depth, other.max_depth);
}

}  // namespace penumbra
