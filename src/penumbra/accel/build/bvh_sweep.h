#pragma once
/// Full-sweep SAH splits of BVH nodes: the surface area heuristic evaluated exactly at every one
/// of the N - 1 object partitions along each axis, in centroid order (MacDonald & Booth 1990,
/// "Heuristics for Ray Tracing Using Space Subdivision"; Wald 2007, "On fast Construction of
/// SAH-based Bounding Volume Hierarchies", compares it with the binned approximation).
///
/// The references are sorted by centroid once per axis, into three arrays (the builder's own
/// and two copies) in which every node's references occupy the same range [b, e). A node sweeps
/// each array from the right (areas of the suffixes) and from the left (the cost of each
/// partition), O(n) per axis; the chosen partition is a prefix of one array, and the two other
/// arrays are partitioned stably by it, so each stays sorted. O(N) per tree level, O(N log N) in
/// all after the O(N log N) sorts.
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/bvh_split.h"
#include "penumbra/accel/build/prim_ref.h"

namespace penumbra {

/// The most references find_exact_split() takes.
inline constexpr uint32_t kMaxExactSplit = 256;

/// The exact SAH split of a small node (at most kMaxExactSplit references, at least 2): every
/// partition of `refs` in centroid order along each axis (centroid, then id: a total order), as
/// the sweep below evaluates them, but sorted for this node alone. The binned build takes it for
/// its small nodes (`exact=N`): bins cannot put a boundary at an exact count, and the SAH of
/// blocks (`block_shift`) prefers children whose counts fill their blocks. Leaves `refs` in the
/// order of the chosen axis, its first `left_count` references forming the left side; `pos`
/// is left_count too. Ties keep the lower axis and the fewer references on the left.
SahSplit find_exact_split(std::span<PrimRef> refs, int block_shift);

/// The split strategy of `bvh:sweep`, called by the top-down builder once per node.
class SweepSahSplitter {
 public:
  /// Sorts `refs` (the builder's array, which is therefore in leaf order after the build) and two
  /// copies by centroid along x, y and z, ties by id: a total order, so the result does not depend
  /// on the thread count. `refs` and `params` must outlive the splitter.
  SweepSahSplitter(std::span<PrimRef> refs, const BvhBuildParams& params);

  /// The split of the node over [b, e) (at least 2 references) with box `box` and centroid
  /// bounds `centroids` at `depth`: the cheapest partition by SAH, a leaf when the SAH prefers it
  /// and it is small enough, the object median below kMaxSahDepth. Reorders [b, e) of the three
  /// arrays; calls on disjoint ranges may run concurrently.
  NodeSplit operator()(uint32_t b, uint32_t e, uint32_t cap, const Bounds3& box,
                       const Bounds3& centroids, int depth);

 private:
  /// The cheapest partition along one axis: `count` references go left.
  struct AxisBest {
    float cost = 0.0f;   ///< area(L) N(L) + area(R) N(R)
    uint32_t count = 0;  ///< 0 while none was evaluated
  };

  /// The cheapest partition of [b, e) in the order of `axis`.
  AxisBest sweep(int axis, uint32_t b, uint32_t e);
  /// Splits [b, e) before position `mid` of the `axis` array: the children's boxes, and the
  /// other two arrays partitioned stably to match.
  NodeSplit divide(int axis, uint32_t b, uint32_t e, uint32_t mid, bool parallel);

  const BvhBuildParams& params_;
  size_t n_ = 0;
  PrimRef* sorted_[3] = {};        ///< by centroid on x, y, z
  PrimRefArray copies_[2];         ///< the y and z arrays
  PrimRefArray temp_[2];           ///< partition scratch per other axis
  std::vector<float> right_area_;  ///< 3 n suffix areas, per axis
};

}  // namespace penumbra
