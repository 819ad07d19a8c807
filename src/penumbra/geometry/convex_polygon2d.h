#pragma once
/// Convex polygons in the plane: clipping by a half-plane, convexity and overlap tests, and the
/// ray's first boundary hit. Used by the 2D laboratory for cells and for the objects of the object
/// BSP variant.
#include <span>
#include <vector>

#include "penumbra/geometry/segment2d.h"

namespace penumbra {

/// Twice the signed area (positive when counter-clockwise).
double signed_area2(std::span<const Vec2d> poly);

/// True when poly (at least three vertices) turns the same way at every vertex, up to eps (a
/// distance); collinear vertices are allowed.
bool is_convex(std::span<const Vec2d> poly, double eps);

/// The part of the convex polygon poly on the `positive` side of line (ℓ⁺ when positive, else ℓ⁻;
/// points on the line kept), by Sutherland–Hodgman clipping (Sutherland and Hodgman 1974,
/// "Reentrant polygon clipping"); empty when nothing lies more than eps on that side.
std::vector<Vec2d> clip_convex(std::span<const Vec2d> poly, const Line2& line, bool positive,
                               double eps);

/// True when the interiors of two convex polygons (or segments, given as two vertices) overlap by
/// more than eps along every separating-axis candidate (the separating axis theorem: disjoint
/// convex sets have a separating line parallel to an edge of one of them); touching is no overlap.
bool convex_overlap(std::span<const Vec2d> p, std::span<const Vec2d> q, double eps);

/// The first parameter where the ray meets the boundary of the closed polygon (or segment, given
/// as two vertices) on [tmin, tmax]; +inf when it misses. The minimum of `intersect` over edges.
double intersect_polygon(const Ray2& ray, std::span<const Vec2d> poly);

/// The part of line inside the convex polygon poly (a chord), or false when the line misses it.
bool clip_line(std::span<const Vec2d> poly, const Line2& line, Segment2& chord);

}  // namespace penumbra
