#pragma once
/// Top-down construction of a binary BVH over primitive references with binned SAH splits
/// (Wald 2007, "On fast Construction of SAH-based Bounding Volume Hierarchies"), full-sweep SAH
/// splits (bvh_sweep.h) or object-median splits (bvh_median.h). Shared by every structure that
/// starts from a binary BVH.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/accel/build/binned_sah.h"
#include "penumbra/accel/build/bvh_node.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/core/params.h"

namespace penumbra {

/// How the build chooses the split of a node.
enum class BvhSplitMethod {
  kBinned,  ///< binned SAH: `bins` candidate planes per axis (the default)
  kMedian,  ///< object median along the widest centroid axis, no SAH
  kSweep,   ///< exact SAH over every object partition in centroid order
};

/// Settings of the binary BVH build.
struct BvhBuildParams {
  BvhSplitMethod method = BvhSplitMethod::kBinned;  ///< split strategy
  int bins = 16;                                    ///< SAH bins per axis, in [2, kMaxBins]
  /// With few_bins > 0, nodes of fewer than 256 references are binned with at most that many
  /// (the many small nodes of a large set are most of its binning time).
  int few_bins = 0;
  int max_leaf = 8;                                 ///< most references in one leaf
  /// Binned builds split nodes of at most this many references (at most kMaxExactSplit) by the
  /// exact SAH over every partition in centroid order (find_exact_split); 0: every node binned.
  int exact_below = 0;
  float traversal_cost = 2.0f;  ///< cost of an inner node relative to one primitive test
  /// Leaves are tested 2^block_shift primitives at a time (SIMD blocks); the SAH counts blocks.
  int block_shift = 0;
  size_t parallel_min = 4096;  ///< nodes with more references build their children as tasks
  /// Spatial splits (spatial_split.h; Stich, Friedrich & Dietrich 2009), binned builds only:
  /// the build may add up to this many references per input reference (in [0, 4]; 0: none).
  /// They need the primitive set, given to build_binary_bvh.
  float spatial_budget = 0.0f;
  /// A spatial split is tried only where the best object split's two boxes overlap by more
  /// than this fraction of the root's surface area (the paper's alpha, which it sets to 1e-5;
  /// 0 tries every node).
  float spatial_alpha = 1e-3f;
};

/// Reads build=binned|median|sweep (or the bare word), leaf=N (1..64), bins=N (2..kMaxBins, binned
/// only), exact=N|auto (0..kMaxExactSplit, binned only; auto keeps the default) and trav=X (0..100,
/// not for median) from `params`, the defaults being those of BvhBuildParams but for leaf's,
/// `default_leaf`; throws Error on bad values. Unused keys are left for the caller.
BvhBuildParams read_bvh_build_params(const ParamList& params, int default_leaf = 8);

/// A built binary BVH. nodes[0] is the root and nodes[1] is padding, so that every pair of
/// children starts at an even index (one cache line); children always follow their parent;
/// `refs` are in leaf order.
struct BinaryBvh {
  BvhNodeArray nodes;    ///< root, padding, then child pairs (depth first when compacted)
  PrimRefArray refs;     ///< leaf order; leaves index into it
  size_t leaves = 0;     ///< number of leaves
  size_t max_depth = 0;  ///< depth of the deepest leaf (root at 0)

  /// Number of nodes reachable from the root (inner and leaf).
  size_t node_count() const { return leaves ? 2 * leaves - 1 : 0; }
};

/// Deepest level at which SAH splits are used; below it nodes are split at the object median,
/// which bounds the depth (and the traversal stack) by this plus log2 of the primitive count.
inline constexpr int kMaxSahDepth = 48;
/// Traversal stack size that covers every tree this builder makes.
inline constexpr int kBvhStackSize = kMaxSahDepth + 40;

/// Builds a binary BVH over `refs` (consumed). Leaves hold at most `max_leaf` references and are
/// made where the SAH says a leaf is cheaper than any split (median: as soon as they fit).
/// Subtrees build in parallel; the
/// result is identical for every thread count. An empty input gives an empty tree.
/// With `compact` the nodes are dense, in depth-first order; without, they stay in the build's
/// scratch array (2 slots per reference, the unused ones unwritten, the order of the pairs
/// depending on the order in which parallel tasks ran), which suits a caller that only walks the
/// tree from the root (e.g. to collapse it into a wide BVH): the tree it finds is the same.
/// With `prims` (the set of static triangles the references point into) and a spatial budget,
/// binned builds also
/// try spatial splits: references then repeat (parts of one primitive in different subtrees), and
/// `refs` has unused slots between the leaves' ranges (only those ranges are meaningful).
BinaryBvh build_binary_bvh(PrimRefs refs, const BvhBuildParams& params, bool compact = true,
                           const PrimitiveSet* prims = nullptr);

}  // namespace penumbra
