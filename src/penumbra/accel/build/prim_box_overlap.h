#pragma once
/// Exact (conservative by a tiny documented margin) overlap tests between a primitive and an
/// axis-aligned box, for the spatial-subdivision builders (uniform grid, octree, kd-tree split
/// clipping): a primitive is stored in every cell it really touches, not every cell its
/// bounding box touches.
///
/// Robustness. Each test works in double precision on the closed box enlarged per axis by
/// kOverlapPad * (|lo| + |hi|) on both sides (about 16 float ulps of the box's coordinates;
/// the term covers the box's extent too, since hi - lo <= |lo| + |hi|). So a primitive lying in a
/// face plane of the box, or touching it along an edge or at a point, always counts as
/// overlapping, and so does one that misses the box by less than the pad (a harmless extra
/// reference). The pad also absorbs the rounding of the traversal's float cell crossings: a
/// primitive whose hit lies on a cell boundary is stored on both sides of it.
#include <cstdint>

#include "penumbra/core/bounds.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

/// Relative enlargement of the box in every overlap test (2^-20, about 16 float ulps).
inline constexpr double kOverlapPad = 0x1p-20;

/// Triangle (a, b, c) against `box` by the separating axis theorem (Akenine-Möller 2001, "Fast
/// 3D Triangle-Box Overlap Testing", JGT 6(1)): box normals, triangle normal, nine edge cross
/// products. Degenerate triangles (segments, points) are handled exactly by the same axes.
bool triangle_box_overlap(Vec3 a, Vec3 b, Vec3 c, const Bounds3& box);

/// Sphere surface (center, radius) against `box`: the squared distances from the centre to the
/// nearest and to the farthest point of the box must bracket the squared radius (Arvo 1990, "A
/// Simple Method for Box-Sphere Intersection Testing", Graphics Gems; the far bound excludes
/// boxes wholly inside the sphere, which no ray can hit the surface in).
bool sphere_box_overlap(Vec3 center, float radius, const Bounds3& box);

/// Parallelogram p + u e1 + v e2 (u, v in [0, 1]) against `box`, as its two triangles (corners
/// formed in double, so the diagonal is shared exactly).
bool quad_box_overlap(Vec3 p, Vec3 e1, Vec3 e2, const Bounds3& box);

/// Primitive `id` of `prims` (any kind) against `box`; the primitive must have finite bounds. A
/// moving primitive is tested by its bounds over the whole time interval (prim_bounds), so it is
/// stored in every cell that its swept box reaches.
bool prim_box_overlap(const PrimitiveSet& prims, uint32_t id, const Bounds3& box);

/// As above, with the primitive's bounds `prim_box` at hand: answered from the boxes alone when
/// they are disjoint, or when `prim_box` lies within `box` on two axes (every primitive kind is
/// connected with its box's interval as projection on the third axis, so it must then cross
/// `box`); otherwise by the exact test. Same result as the exact test up to the pad.
bool prim_box_overlap(const PrimitiveSet& prims, uint32_t id, const Bounds3& prim_box,
                      const Bounds3& box);

}  // namespace penumbra
