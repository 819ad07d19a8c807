#include "penumbra/accel/collision/swept_tests.h"

#include <algorithm>
#include <cmath>

#include "penumbra/accel/collision/exact_predicates.h"
#include "penumbra/accel/collision/triangle_triangle.h"

namespace penumbra::collision {

namespace {

double clamp01(double x) {
  return std::clamp(x, 0.0, 1.0);
}

/// orient2d of points projected by dropping `axis`.
int orient_projected(const DVec3& a, const DVec3& b, const DVec3& c, int axis) {
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  return orient2d(a[i], a[j], b[i], b[j], c[i], c[j]);
}

/// Segment pq in the plane of the triangle: the separating-axis test in that plane, with the
/// triangle's edge lines and the segment's line as candidate separators.
bool coplanar_segment_intersects(const DVec3& p, const DVec3& q, const DTriangle& t) {
  const int axis = projection_axis(t);
  const int s = orient_projected(t[0], t[1], t[2], axis);
  for (int i = 0; i < 3; ++i) {
    const DVec3 &e0 = t[i], &e1 = t[(i + 1) % 3];
    if (orient_projected(e0, e1, p, axis) * s < 0 && orient_projected(e0, e1, q, axis) * s < 0)
      return false;
  }
  const int o0 = orient_projected(p, q, t[0], axis), o1 = orient_projected(p, q, t[1], axis),
            o2 = orient_projected(p, q, t[2], axis);
  return !((o0 > 0 && o1 > 0 && o2 > 0) || (o0 < 0 && o1 < 0 && o2 < 0));
}

/// Projection interval of the swept box {x + s d : x in box, s in [0, 1]} on `axis`.
void swept_box_interval(const DBox& box, const DVec3& d, const DVec3& axis, double& lo,
                        double& hi) {
  lo = hi = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double a = box.lo[k] * axis[k], b = box.hi[k] * axis[k];
    lo += std::min(a, b), hi += std::max(a, b);
  }
  const double m = dot(d, axis);
  lo += std::min(m, 0.0), hi += std::max(m, 0.0);
}

/// True when `axis` separates the swept box from the triangle (strictly; a zero axis never does).
bool separates(const DVec3& axis, const DTriangle& t, const DBox& box, const DVec3& d) {
  const double p0 = dot(t[0], axis), p1 = dot(t[1], axis), p2 = dot(t[2], axis);
  const double tlo = std::min(p0, std::min(p1, p2)), thi = std::max(p0, std::max(p1, p2));
  double blo, bhi;
  swept_box_interval(box, d, axis, blo, bhi);
  return thi < blo || tlo > bhi;
}

}  // namespace

bool segment_intersects_triangle(const DVec3& p, const DVec3& q, const DTriangle& t) {
  const int sp = orient3d(t[0], t[1], t[2], p), sq = orient3d(t[0], t[1], t[2], q);
  if (sp * sq > 0) return false;  // both strictly on one side
  if (sp == 0 && sq == 0) return coplanar_segment_intersects(p, q, t);
  // The segment meets the plane in one point; it is in the triangle when the line pq passes on
  // the same side of the three edges (signed volumes of one sign, zeros on the boundary).
  const int s0 = orient3d(p, q, t[0], t[1]), s1 = orient3d(p, q, t[1], t[2]),
            s2 = orient3d(p, q, t[2], t[0]);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

double point_triangle_distance_sq(const DVec3& p, const DTriangle& t) {
  const DVec3 &a = t[0], &b = t[1], &c = t[2];
  const DVec3 ab = b - a, ac = c - a, ap = p - a;
  // Vertex regions and edge regions in turn (Ericson, ClosestPtPointTriangle).
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return length_sq(ap);
  const DVec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return length_sq(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return length_sq(ap - ab * (d1 / (d1 - d3)));
  const DVec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return length_sq(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return length_sq(ap - ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return length_sq(bp - (c - b) * w);
  }
  // Face region: the distance to the plane.
  const DVec3 n = cross(ab, ac);
  const double h = dot(ap, n);
  return h * h / length_sq(n);
}

double segment_segment_distance_sq(const DVec3& p0, const DVec3& p1, const DVec3& q0,
                                   const DVec3& q1) {
  // Ericson, ClosestPtSegmentSegment: p0 + s d1 and q0 + t d2 with s, t clamped to [0, 1].
  const DVec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = length_sq(d1), e = length_sq(d2), f = dot(d2, r);
  double s = 0, t = 0;
  if (a == 0 && e == 0) return length_sq(r);
  if (a == 0) {
    t = clamp01(f / e);
  } else {
    const double c = dot(d1, r);
    if (e == 0) {
      s = clamp01(-c / a);
    } else {
      const double b = dot(d1, d2), denom = a * e - b * b;
      // Parallel segments (denom 0): any s, then t and s clamped in turn.
      s = denom != 0 ? clamp01((b * f - c * e) / denom) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0, s = clamp01(-c / a);
      } else if (t > 1) {
        t = 1, s = clamp01((b - c) / a);
      }
    }
  }
  return length_sq((p0 + d1 * s) - (q0 + d2 * t));
}

double segment_triangle_distance_sq(const DVec3& p, const DVec3& q, const DTriangle& t) {
  if (segment_intersects_triangle(p, q, t)) return 0.0;
  double d = std::min(point_triangle_distance_sq(p, t), point_triangle_distance_sq(q, t));
  if (p == q) return d;
  for (int i = 0; i < 3; ++i)
    d = std::min(d, segment_segment_distance_sq(p, q, t[i], t[(i + 1) % 3]));
  return d;
}

bool moving_sphere_touches(const DTriangle& t, const DVec3& c0, const DVec3& c1, double r) {
  return segment_triangle_distance_sq(c0, c1, t) <= r * r;
}

bool moving_box_touches(const DTriangle& t, const DBox& box, const DVec3& d) {
  const DVec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const DVec3 edges[3] = {t[1] - t[0], t[2] - t[1], t[0] - t[2]};
  // Face normals of the swept box: the box axes first (the cheapest and most often decisive).
  for (const DVec3& a : axes)
    if (separates(a, t, box, d)) return false;
  if (separates(cross(edges[0], edges[1]), t, box, d)) return false;
  for (const DVec3& a : axes)
    if (separates(cross(d, a), t, box, d)) return false;
  // Edge-edge axes: box axes x triangle edges, and the sweep direction x triangle edges.
  for (const DVec3& e : edges) {
    for (const DVec3& a : axes)
      if (separates(cross(a, e), t, box, d)) return false;
    if (separates(cross(d, e), t, box, d)) return false;
  }
  return true;
}

}  // namespace penumbra::collision
