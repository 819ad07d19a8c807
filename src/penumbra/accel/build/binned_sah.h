#pragma once
/// Binned surface-area-heuristic splits over primitive references (Wald 2007, "On fast
/// Construction of SAH-based Bounding Volume Hierarchies", IEEE Symposium on Interactive Ray
/// Tracing): centroids are counted into equal-width bins along each axis and the SAH is evaluated
/// only at the bin boundaries, in O(N + bins) per node.
#include <cstdint>
#include <span>

#include "penumbra/accel/build/prim_ref.h"

namespace penumbra {

/// Most bins per axis.
inline constexpr int kMaxBins = 64;

/// Maps centroids (as lo + hi) to bins of equal width along each axis of the centroid bounds.
struct BinMapping {
  Vec3 origin;    ///< low corner of the centroid bounds
  Vec3 scale;     ///< bins per unit length (0 on an axis without extent)
  int bins = 16;  ///< bins per axis

  /// Mapping of `bins` bins over `centroid_bounds` (bounds of lo + hi).
  BinMapping(const Bounds3& centroid_bounds, int bins);
  /// Bin of centroid coordinate `c` on `axis`, clamped to [0, bins); NaN and overflow map to an
  /// end bin, so every reference lands in exactly one bin.
  int bin(float c, int axis) const {
    const float f = (c - origin[axis]) * scale[axis];
    return f >= 0.0f ? (f < float(bins - 1) ? int(f) : bins - 1) : 0;
  }
};

/// The best split found by binning; `axis` is -1 when no split separates the references.
struct SahSplit {
  int axis = -1;             ///< split axis, or -1
  int pos = 0;               ///< bins [0, pos) go left, [pos, bins) right
  float cost = 0.0f;         ///< sum over the two sides of area(box) * count (not normalised)
  Bounds3 left, right;       ///< boxes of the two sides
  uint32_t left_count = 0;   ///< references on the left
  uint32_t right_count = 0;  ///< references on the right
};

/// Finds the binned split of `refs` minimising area(left) T(left) + area(right) T(right), T the
/// SAH's test count of a side (sah_tests with `block_shift`: N itself by default).
/// Bins large sets in parallel chunks of fixed size when `parallel` is set; bin boxes and counts
/// combine exactly (min, max, integer sums), so the result is the same for every thread count.
SahSplit find_binned_split(std::span<const PrimRef> refs, const BinMapping& map, bool parallel,
                           int block_shift = 0);

/// Moves the references of bins [0, split.pos) on split.axis to the front and returns how many
/// there are; also returns the centroid bounds (of lo + hi) of the two sides. Deterministic.
size_t partition_refs(std::span<PrimRef> refs, const BinMapping& map, const SahSplit& split,
                      Bounds3& left_centroids, Bounds3& right_centroids);

}  // namespace penumbra
