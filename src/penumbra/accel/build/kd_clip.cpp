#include "penumbra/accel/build/kd_clip.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "penumbra/core/dvec3.h"

namespace penumbra {

namespace {

/// A convex polygon in double precision. Clipping by a half-space adds at most one vertex, so a
/// parallelogram clipped by a box and one more plane has at most 4 + 7 vertices.
struct Polygon {
  static constexpr int kMax = 16;
  double v[kMax][3];
  int n = 0;

  void push(const double* p) {
    v[n][0] = p[0], v[n][1] = p[1], v[n][2] = p[2];
    ++n;
  }
};

/// The part of `in` on one side of plane x[axis] = c: x[axis] <= c when `keep_below`, >= c
/// otherwise (Sutherland and Hodgman's one-plane step). Points on the plane are kept; a crossing
/// edge contributes its intersection, with the axis coordinate set to c exactly.
void clip_plane(const Polygon& in, Polygon& out, int axis, double c, bool keep_below) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const double* p = in.v[i];
    const double* q = in.v[i + 1 == in.n ? 0 : i + 1];
    const bool p_in = keep_below ? p[axis] <= c : p[axis] >= c;
    const bool q_in = keep_below ? q[axis] <= c : q[axis] >= c;
    if (p_in) out.push(p);
    if (p_in != q_in) {  // p[axis] != q[axis] here, one being on each side of c
      const double t = (c - p[axis]) / (q[axis] - p[axis]);
      double r[3];
      for (int a = 0; a < 3; ++a) r[a] = p[a] + t * (q[a] - p[a]);
      r[axis] = c;
      out.push(r);
    }
  }
}

/// Clips `poly` to `box` in place (six planes).
void clip_to_box(Polygon& poly, const Bounds3& box) {
  Polygon tmp;
  for (int axis = 0; axis < 3 && poly.n > 0; ++axis) {
    clip_plane(poly, tmp, axis, box.lo[axis], false);
    clip_plane(tmp, poly, axis, box.hi[axis], true);
  }
}

/// Bounds of `poly` rounded outward, intersected with `box`.
Bounds3 polygon_bounds(const Polygon& poly, const Bounds3& box) {
  if (poly.n == 0) return {};
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = poly.v[0][a];
  for (int i = 1; i < poly.n; ++i)
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], poly.v[i][a]), hi[a] = std::max(hi[a], poly.v[i][a]);
  Bounds3 b;
  b.lo = {round_down(lo[0]), round_down(lo[1]), round_down(lo[2])};
  b.hi = {round_up(hi[0]), round_up(hi[1]), round_up(hi[2])};
  return intersect_boxes(b, box);
}

Polygon make_polygon(std::span<const Vec3> pts) {
  Polygon poly;
  for (const Vec3& p : pts) {
    const double d[3] = {p.x, p.y, p.z};
    poly.push(d);
  }
  return poly;
}

/// The primitive as a polygon (triangles and parallelograms); false for spheres and moving
/// primitives, which have no fixed polygon: they are bounded by their (swept) boxes instead.
bool prim_polygon(const PrimitiveSet& prims, uint32_t id, Polygon& poly) {
  if (prims.moving(id)) return false;
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      const Vec3* v = prims.triangle(id);
      poly = make_polygon({v, 3});
      return true;
    }
    case PrimKind::kQuad: {
      // Corners in double: float sums round them, inward as often as not, and a quad far from
      // the origin (where an ulp is larger than it is) would lose its edges.
      const QuadData& q = prims.quad(id);
      const DVec3 p(q.p), e1(q.e1), e2(q.e2);
      poly = Polygon{};
      for (const DVec3& c : {p, p + e1, p + e1 + e2, p + e2}) {
        const double d[3] = {c.x, c.y, c.z};
        poly.push(d);
      }
      return true;
    }
    default:
      return false;
  }
}

}  // namespace

Bounds3 clip_polygon_bounds(std::span<const Vec3> poly, const Bounds3& box) {
  if (poly.empty() || poly.size() > 8 || box.empty()) return {};
  Polygon p = make_polygon(poly);
  clip_to_box(p, box);
  return polygon_bounds(p, box);
}

Bounds3 clip_prim_bounds(const PrimitiveSet& prims, uint32_t id, const Bounds3& box) {
  Polygon poly;
  if (!prim_polygon(prims, id, poly)) return intersect_boxes(prims.prim_bounds(id), box);
  clip_to_box(poly, box);
  return polygon_bounds(poly, box);
}

double clip_prim_area(const PrimitiveSet& prims, uint32_t id, const Bounds3& box) {
  Polygon poly;
  if (!prim_polygon(prims, id, poly)) return 0.0;
  // A polygon inside the box is its own clip (every vertex kept, no edge crossing a plane).
  const Bounds3 b = prims.prim_bounds(id);
  if (!(b.lo.x >= box.lo.x && b.lo.y >= box.lo.y && b.lo.z >= box.lo.z && b.hi.x <= box.hi.x &&
        b.hi.y <= box.hi.y && b.hi.z <= box.hi.z))
    clip_to_box(poly, box);
  // Newell's sum: twice the area vector of a planar polygon is the sum of its edges' cross
  // products taken from any point (its first vertex here).
  double n[3] = {0.0, 0.0, 0.0};
  for (int i = 1; i + 1 < poly.n; ++i) {
    double e1[3], e2[3];
    for (int a = 0; a < 3; ++a)
      e1[a] = poly.v[i][a] - poly.v[0][a], e2[a] = poly.v[i + 1][a] - poly.v[0][a];
    n[0] += e1[1] * e2[2] - e1[2] * e2[1];
    n[1] += e1[2] * e2[0] - e1[0] * e2[2];
    n[2] += e1[0] * e2[1] - e1[1] * e2[0];
  }
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

void split_prim_bounds(const PrimitiveSet& prims, uint32_t id, const Bounds3& box, int axis,
                       float pos, bool clip, Bounds3& below, Bounds3& above) {
  Bounds3 below_box = box, above_box = box;
  below_box.hi[axis] = pos;
  above_box.lo[axis] = pos;
  Polygon poly;
  if (!clip || !prim_polygon(prims, id, poly)) {
    below = below_box, above = above_box;
    return;
  }
  // The part inside the current box, then each side of the plane.
  clip_to_box(poly, box);
  Polygon side;
  clip_plane(poly, side, axis, pos, true);
  below = polygon_bounds(side, below_box);
  clip_plane(poly, side, axis, pos, false);
  above = polygon_bounds(side, above_box);
}

}  // namespace penumbra
