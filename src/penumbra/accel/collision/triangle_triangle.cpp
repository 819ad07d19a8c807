#include "penumbra/accel/collision/triangle_triangle.h"

#include <cmath>
#include <utility>

#include "penumbra/accel/collision/exact_predicates.h"

namespace penumbra::collision {

namespace {

/// A point of the projection plane.
struct P2 {
  double x, y;
};

P2 project(const DVec3& p, int drop) {
  return {p[(drop + 1) % 3], p[(drop + 2) % 3]};
}

int orient(const P2& a, const P2& b, const P2& c) {
  return orient2d(a.x, a.y, b.x, b.y, c.x, c.y);
}

/// True when every vertex of `t` lies strictly outside the line of edge (p, q) of a triangle of
/// orientation `sign` (the triangle's interior is where orient(p, q, x) has that sign).
bool edge_separates(const P2& p, const P2& q, int sign, const P2 t[3]) {
  for (int i = 0; i < 3; ++i)
    if (orient(p, q, t[i]) * sign >= 0) return false;
  return true;
}

/// Final test of Guigue and Devillers for triangles in canonical form: p1 alone on its side of
/// the plane of T2 and p2 alone on its side of the plane of T1, both seen so that the overlap of
/// the two intervals on the planes' common line reduces to two orientation tests.
bool check_min_max(const DVec3& p1, const DVec3& q1, const DVec3& r1, const DVec3& p2,
                   const DVec3& q2, const DVec3& r2) {
  if (orient3d(q1, p2, p1, q2) > 0) return false;
  if (orient3d(p1, p2, r1, r2) > 0) return false;
  return true;
}

/// Permutes T2 into canonical form (p2 alone on its side of the plane of T1), given the sides
/// dp2, dq2, dr2 of its vertices, T1 already canonical.
bool tri_tri_3d(const DVec3& p1, const DVec3& q1, const DVec3& r1, const DVec3& p2, const DVec3& q2,
                const DVec3& r2, int dp2, int dq2, int dr2) {
  if (dp2 > 0) {
    if (dq2 > 0) return check_min_max(p1, r1, q1, r2, p2, q2);
    if (dr2 > 0) return check_min_max(p1, r1, q1, q2, r2, p2);
    return check_min_max(p1, q1, r1, p2, q2, r2);
  }
  if (dp2 < 0) {
    if (dq2 < 0) return check_min_max(p1, q1, r1, r2, p2, q2);
    if (dr2 < 0) return check_min_max(p1, q1, r1, q2, r2, p2);
    return check_min_max(p1, r1, q1, p2, q2, r2);
  }
  if (dq2 < 0) {
    if (dr2 >= 0) return check_min_max(p1, r1, q1, q2, r2, p2);
    return check_min_max(p1, q1, r1, p2, q2, r2);
  }
  if (dq2 > 0) {
    if (dr2 > 0) return check_min_max(p1, r1, q1, p2, q2, r2);
    return check_min_max(p1, q1, r1, q2, r2, p2);
  }
  if (dr2 > 0) return check_min_max(p1, q1, r1, r2, p2, q2);
  return check_min_max(p1, r1, q1, r2, p2, q2);  // dr2 < 0: all zero would mean coplanar
}

}  // namespace

int projection_axis(const DTriangle& t) {
  const DVec3 n = cross(t[1] - t[0], t[2] - t[0]);
  // Axes by decreasing |n| (rounded); the first whose exact component is nonzero wins.
  int order[3] = {0, 1, 2};
  const double m[3] = {std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)};
  if (m[order[1]] > m[order[0]]) std::swap(order[0], order[1]);
  if (m[order[2]] > m[order[1]]) std::swap(order[1], order[2]);
  if (m[order[1]] > m[order[0]]) std::swap(order[0], order[1]);
  for (int k : order) {
    const P2 a = project(t[0], k), b = project(t[1], k), c = project(t[2], k);
    if (orient(a, b, c) != 0) return k;
  }
  return -1;
}

bool is_valid_triangle(const DTriangle& t) {
  return is_finite(t[0]) && is_finite(t[1]) && is_finite(t[2]) && projection_axis(t) >= 0;
}

bool triangles_intersect(const DTriangle& a, const DTriangle& b) {
  return is_valid_triangle(a) && is_valid_triangle(b) && valid_triangles_intersect(a, b);
}

bool coplanar_triangles_intersect(const DTriangle& a, const DTriangle& b) {
  const int axis = projection_axis(a);
  const P2 ta[3] = {project(a[0], axis), project(a[1], axis), project(a[2], axis)};
  const P2 tb[3] = {project(b[0], axis), project(b[1], axis), project(b[2], axis)};
  const int sa = orient(ta[0], ta[1], ta[2]), sb = orient(tb[0], tb[1], tb[2]);
  if (sb == 0) return false;  // b not valid in this plane (cannot happen for valid coplanar b)
  // Two disjoint convex polygons are strictly separated by the line of one of their edges.
  for (int i = 0; i < 3; ++i) {
    if (edge_separates(ta[i], ta[(i + 1) % 3], sa, tb)) return false;
    if (edge_separates(tb[i], tb[(i + 1) % 3], sb, ta)) return false;
  }
  return true;
}

bool valid_triangles_intersect(const DTriangle& a, const DTriangle& b) {
  const DVec3 &p1 = a[0], &q1 = a[1], &r1 = a[2];
  const DVec3 &p2 = b[0], &q2 = b[1], &r2 = b[2];
  // Sides of T1's vertices relative to the plane of T2: all strictly on one side, no overlap.
  const PlaneOrientation plane2(p2, q2, r2);
  const int dp1 = plane2(p1), dq1 = plane2(q1), dr1 = plane2(r1);
  if (dp1 * dq1 > 0 && dp1 * dr1 > 0) return false;
  // And of T2's vertices relative to the plane of T1.
  const PlaneOrientation plane1(p1, q1, r1);
  const int dp2 = plane1(p2), dq2 = plane1(q2), dr2 = plane1(r2);
  if (dp2 * dq2 > 0 && dp2 * dr2 > 0) return false;

  // Permute T1 so that p1 is alone on its side of T2's plane (swapping T2's orientation when T1
  // is seen from the other side), then finish with two orientation tests.
  if (dp1 > 0) {
    if (dq1 > 0) return tri_tri_3d(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2);
    if (dr1 > 0) return tri_tri_3d(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2);
    return tri_tri_3d(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dp1 < 0) {
    if (dq1 < 0) return tri_tri_3d(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2);
    if (dr1 < 0) return tri_tri_3d(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2);
    return tri_tri_3d(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2);
  }
  if (dq1 < 0) {
    if (dr1 >= 0) return tri_tri_3d(q1, r1, p1, p2, r2, q2, dp2, dr2, dq2);
    return tri_tri_3d(p1, q1, r1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dq1 > 0) {
    if (dr1 > 0) return tri_tri_3d(p1, q1, r1, p2, r2, q2, dp2, dr2, dq2);
    return tri_tri_3d(q1, r1, p1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dr1 > 0) return tri_tri_3d(r1, p1, q1, p2, q2, r2, dp2, dq2, dr2);
  if (dr1 < 0) return tri_tri_3d(r1, p1, q1, p2, r2, q2, dp2, dr2, dq2);
  return coplanar_triangles_intersect(a, b);
}

}  // namespace penumbra::collision
