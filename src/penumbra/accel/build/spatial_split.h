#pragma once
/// Spatial splits of BVH nodes (Stich, Friedrich & Dietrich 2009, "Spatial Splits in Bounding
/// Volume Hierarchies", HPG): besides partitioning its references (an object split), a node may
/// cut space at a plane, references that straddle it going to both children, each with the box
/// of its part on that side (exactly clipped, rounded outward: kd_clip.h). Where long or large
/// triangles make the object split's children overlap, this lowers the SAH cost at the price of
/// duplicated references.
///
/// Ours, as in the paper: the candidate planes are the `bins - 1` inner boundaries of equal-width
/// bins over the node's box; every reference is chopped into the bins it spans (its part in each,
/// clipped), entering at its first bin and leaving at its last; the SAH is swept over the
/// boundaries; and when the split is made, a straddling reference whose whole box costs less on
/// one side than two parts ("reference unsplitting", section 3.2 of the paper) goes whole to that
/// side.
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// The best spatial split found by chopped binning; `axis` is -1 when none was found.
struct SpatialSplit {
  int axis = -1;        ///< split axis, or -1
  float pos = 0.0f;     ///< the plane: parts below go left, above go right
  float cost = 0.0f;    ///< area(left) T(left) + area(right) T(right), not normalised
  Bounds3 left, right;  ///< boxes of the two sides (from the bins)
  /// References entering on the left and leaving on the right (before unsplitting; estimated
  /// from the sample when the search had one).
  uint32_t left_count = 0, right_count = 0;
  /// References on both sides (straddling the plane; estimated as the counts), 0 when the split
  /// duplicates none of the sample: then it is an object split.
  float straddlers = 0.0f;
};

/// Finds the spatial split of `refs` (inside `box`) over `bins` equal bins per axis (2..64)
/// minimising the SAH's area-weighted test counts (sah_tests with `block_shift`), with each
/// reference's part in a bin estimated by its box cut to the bin (spatial_split.cpp). With
/// `max_samples` (0: all), larger sets are estimated from every k-th reference, k the smallest
/// stride that keeps to the limit, counts scaled up: the same sample at every thread count.
SpatialSplit find_spatial_split(std::span<const PrimRef> refs, const Bounds3& box, int bins,
                                size_t max_samples, int block_shift = 0);

/// The SAH cost (as SpatialSplit::cost) of `split`'s plane over all of `refs`, each straddling
/// reference in both sides with its box cut at the plane: exact counts, and boxes that bound
/// those apply_spatial_split would make before unsplitting. O(n), no clipping: the check that a
/// split found from a sample pays before it is made.
float spatial_split_cost(std::span<const PrimRef> refs, const SpatialSplit& split,
                         int block_shift = 0);

/// The two sides of a spatial split, made: the references on each side, their boxes and the
/// bounds of their centroids (as lo + hi).
struct SpatialSides {
  std::vector<PrimRef> left, right;
  Bounds3 left_box, right_box;
  Bounds3 left_centroids, right_centroids;
};

/// Divides `refs` at `split`'s plane: references below it go left, above it right, and each
/// straddling one is unsplit (whole to one side, when the SAH of the bins prefers that) or split
/// into its clipped parts on both sides (a part found empty drops out). The order of `refs` is
/// kept on each side.
void apply_spatial_split(const PrimitiveSet& prims, std::span<const PrimRef> refs,
                         const SpatialSplit& split, SpatialSides& out);

}  // namespace penumbra
