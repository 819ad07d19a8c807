#pragma once
/// Clipping of primitives to kd-tree cells: the bounds of the part of a triangle or
/// parallelogram inside a box, found by clipping the polygon to the box's six planes
/// (Sutherland, Hodgman 1974, "Reentrant Polygon Clipping"), as the "perfect splits" of
/// Havran 2000 ("Heuristic Ray Shooting Algorithms", PhD thesis) and of Wald,
/// Havran 2006 ("On building fast kd-Trees for Ray Tracing, and on doing that in O(N log N)").
/// Spheres are bounded by their box intersected with the cell.
#include <cstdint>
#include <span>

#include "penumbra/accel/build/kd_node.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Side of a split plane a primitive's box lies on.
enum class KdSide : uint8_t { kBelow, kAbove, kBoth };

/// Which side of plane (axis, pos) box `b` is on: below when b.hi <= pos, above when b.lo >= pos,
/// both when it straddles. A box flat in `axis` lying in the plane goes below when
/// `planar_below`, above otherwise (Wald and Havran's p_side).
inline KdSide classify_box(const Bounds3& b, int axis, float pos, bool planar_below) {
  const float lo = b.lo[axis], hi = b.hi[axis];
  if (lo == hi && lo == pos) return planar_below ? KdSide::kBelow : KdSide::kAbove;
  if (hi <= pos) return KdSide::kBelow;
  if (lo >= pos) return KdSide::kAbove;
  return KdSide::kBoth;
}

/// Bounds of the part of convex polygon `poly` (at most 8 vertices) inside `box`, rounded outward
/// to float (so never smaller than the exact part) and within `box`; empty when they do not meet.
/// Clipping runs in double precision.
Bounds3 clip_polygon_bounds(std::span<const Vec3> poly, const Bounds3& box);

/// Bounds of the part of primitive `id` inside `box`: the clipped polygon of a triangle or
/// parallelogram, the box of a sphere or of a moving primitive (over its whole time interval)
/// intersected with `box`. Empty when they do not meet.
Bounds3 clip_prim_bounds(const PrimitiveSet& prims, uint32_t id, const Bounds3& box);

/// Area of the part of primitive `id` inside `box` (the clipped polygon of a triangle or
/// parallelogram); 0 for spheres and moving primitives, which have no fixed polygon.
double clip_prim_area(const PrimitiveSet& prims, uint32_t id, const Bounds3& box);

/// Splits a primitive whose current bounds `box` straddle plane (axis, pos): the bounds of its
/// parts below and above the plane (either may be empty). With `clip` false (or for spheres and
/// moving primitives), `box` is just cut at the plane.
void split_prim_bounds(const PrimitiveSet& prims, uint32_t id, const Bounds3& box, int axis,
                       float pos, bool clip, Bounds3& below, Bounds3& above);

/// The intersection of two boxes (empty when they do not meet).
inline Bounds3 intersect_boxes(const Bounds3& a, const Bounds3& b) {
  Bounds3 r;
  r.lo = max(a.lo, b.lo);
  r.hi = min(a.hi, b.hi);
  return r.empty() ? Bounds3{} : r;
}

}  // namespace penumbra
