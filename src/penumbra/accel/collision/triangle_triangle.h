#pragma once
/// Exact triangle-triangle overlap (Guigue and Devillers 2003, "Fast and Robust Triangle-Triangle
/// Overlap Test Using Orientation Predicates", Journal of Graphics Tools 8(1)) on the exact
/// predicates of exact_predicates.h. Triangles are closed: touching at a vertex or along an
/// edge counts as intersecting. Degenerate triangles (non-finite or collinear vertices) never
/// intersect anything.
#include "penumbra/accel/collision/dvec3.h"

namespace penumbra::collision {

/// The axis (0, 1, 2) to drop when projecting the triangle to 2D: one along which its normal's
/// component is exactly nonzero (the largest one, as far as rounding can tell); -1 when the
/// vertices are collinear. Needs finite vertices.
int projection_axis(const DTriangle& t);

/// True when the vertices are finite and not collinear (exactly).
bool is_valid_triangle(const DTriangle& t);

/// True when the closed triangles share at least one point; false when either is degenerate.
bool triangles_intersect(const DTriangle& a, const DTriangle& b);

/// triangles_intersect for two triangles known to be valid (skips the checks; the hot path of
/// the mesh queries, whose meshes classify their triangles once).
bool valid_triangles_intersect(const DTriangle& a, const DTriangle& b);

/// True when two valid triangles in one plane (exactly) overlap: the separating-axis test in the
/// plane, with the six edge lines as candidate separators.
bool coplanar_triangles_intersect(const DTriangle& a, const DTriangle& b);

}  // namespace penumbra::collision
