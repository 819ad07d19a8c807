#pragma once
/// Exact and distance-based tests of one triangle against a moving sphere or a moving box, and
/// the distance kernels they rest on (Ericson 2005, "Real-Time Collision Detection", 5.1.5 and
/// 5.1.9). Triangles must be valid (is_valid_triangle); all tests treat shapes as closed, so
/// touching counts.
#include "penumbra/accel/collision/dvec3.h"

namespace penumbra::collision {

/// True when the closed segment pq (possibly a single point) and the triangle share a point;
/// exact (orientation predicates only).
bool segment_intersects_triangle(const DVec3& p, const DVec3& q, const DTriangle& t);

/// Squared distance from p to the triangle: the closest point by Voronoi regions, and within the
/// face the distance to the plane (more accurate there than the barycentric point).
double point_triangle_distance_sq(const DVec3& p, const DTriangle& t);

/// Squared distance between the segments p0p1 and q0q1 (either may be a single point).
double segment_segment_distance_sq(const DVec3& p0, const DVec3& p1, const DVec3& q0,
                                   const DVec3& q1);

/// Squared distance between the segment pq and the triangle: 0 when they intersect (exactly),
/// else the least of the endpoints' distances to the triangle and the segment's distances to
/// the three edges (one of the closest points of two disjoint convex sets lies on a boundary).
double segment_triangle_distance_sq(const DVec3& p, const DVec3& q, const DTriangle& t);

/// True when a sphere of radius r whose centre moves along c0 -> c1 touches the triangle: the
/// distance between the centre's segment and the triangle is at most r.
bool moving_sphere_touches(const DTriangle& t, const DVec3& c0, const DVec3& c1, double r);

/// True when the box [lo, hi] swept along the displacement d touches the triangle. The swept
/// box is a convex polytope; separating-axis test (Gottschalk, Lin and Manocha 1996, "OBBTree")
/// on its face normals (3 box axes, d x the 3 box axes), the triangle's normal, and the cross
/// products of the edge directions (box axes and d) with the 3 triangle edges: 19 axes.
bool moving_box_touches(const DTriangle& t, const DBox& box, const DVec3& d);

}  // namespace penumbra::collision
