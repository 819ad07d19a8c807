#pragma once
/// The kd-tree builds that need no cost model: the spatial median (Kaplan 1985, "Space-Tracing: A
/// Constant Time Ray-Tracer"; the plane through the middle of the cell's longest axis) and the
/// largest gap near the median (an empty slab between primitives, which cuts off empty space the
/// way the SAH's empty-space bonus rewards; Havran 2000, "Heuristic Ray Shooting Algorithms",
/// surveys such rules).
///
/// Gap criterion, exactly: for each axis on which the cell has extent w > 0, the window is the
/// middle half of the cell, [lo + w/4, hi - w/4]. Along the axis, the primitives' boxes (clipped
/// to the cell) cover a union of closed intervals; its complement in the cell consists of open
/// gaps. Each gap is cut to the window; the longest cut gap over all three axes wins (the lower
/// axis, then the lower position on ties) and the plane goes through its middle, so that no
/// primitive straddles it. When no gap reaches into any window, the spatial median is used.
#include <vector>

#include "penumbra/accel/build/kd_node.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Builds a kd-tree over `refs` inside `bounds` with params.criterion kMedian or kGap. A node
/// becomes a leaf at params.max_leaf references or fewer, at the depth limit, or when the plane
/// leaves every reference on both sides.
KdSubtree build_kd_simple(const PrimitiveSet& prims, std::vector<KdPrim> refs,
                          const Bounds3& bounds, const KdBuildParams& params);

/// The gap plane of the references `prims` in `voxel` (see the file comment); axis < 0 when no
/// gap reaches into a window. Exposed for tests.
KdPlane kd_gap_plane(const std::vector<KdPrim>& prims, const Bounds3& voxel);

}  // namespace penumbra
