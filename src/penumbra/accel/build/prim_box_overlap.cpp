#include "penumbra/accel/build/prim_box_overlap.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

/// A point or vector in double precision.
struct D3 {
  double v[3];
  double operator[](int i) const { return v[i]; }
};

D3 to_d3(Vec3 p) {
  return {{p.x, p.y, p.z}};
}
D3 sub(const D3& a, const D3& b) {
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}
D3 add(const D3& a, const D3& b) {
  return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}};
}
D3 cross(const D3& a, const D3& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
double dot(const D3& a, const D3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// The padded box as centre and half extents, in double.
struct PaddedBox {
  D3 lo, hi, center, half;

  explicit PaddedBox(const Bounds3& b) {
    for (int i = 0; i < 3; ++i) {
      const double l = b.lo[i], h = b.hi[i];
      const double pad = kOverlapPad * (std::fabs(l) + std::fabs(h));
      lo.v[i] = l - pad;
      hi.v[i] = h + pad;
      center.v[i] = 0.5 * (lo.v[i] + hi.v[i]);
      half.v[i] = 0.5 * (hi.v[i] - lo.v[i]);
    }
  }
};

/// True when the projections of the triangle (p0, p1, p2) and of the box (radius r around 0)
/// on one axis are disjoint.
bool separated(double p0, double p1, double p2, double r) {
  return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

/// The separating axis test on a triangle given in double (Akenine-Möller 2001).
bool triangle_overlap(const D3& a, const D3& b, const D3& c, const PaddedBox& box) {
  // 1. The three box normals: the triangle's bounding box against the box.
  for (int i = 0; i < 3; ++i)
    if (std::min({a[i], b[i], c[i]}) > box.hi[i] || std::max({a[i], b[i], c[i]}) < box.lo[i])
      return false;
  // Vertices relative to the box centre.
  const D3 v0 = sub(a, box.center), v1 = sub(b, box.center), v2 = sub(c, box.center);
  const D3 e[3] = {sub(v1, v0), sub(v2, v1), sub(v0, v2)};
  const D3& h = box.half;
  // 2. The nine cross products of a box axis with a triangle edge. Axis x * e = (0, -e.z, e.y),
  // and likewise for y and z; the box's projected radius is sum(h_i |axis_i|).
  for (const D3& ej : e) {
    {  // x * e
      const double ay = -ej[2], az = ej[1];
      const double r = h[1] * std::fabs(ay) + h[2] * std::fabs(az);
      if (separated(ay * v0[1] + az * v0[2], ay * v1[1] + az * v1[2], ay * v2[1] + az * v2[2], r))
        return false;
    }
    {  // y * e
      const double ax = ej[2], az = -ej[0];
      const double r = h[0] * std::fabs(ax) + h[2] * std::fabs(az);
      if (separated(ax * v0[0] + az * v0[2], ax * v1[0] + az * v1[2], ax * v2[0] + az * v2[2], r))
        return false;
    }
    {  // z * e
      const double ax = -ej[1], ay = ej[0];
      const double r = h[0] * std::fabs(ax) + h[1] * std::fabs(ay);
      if (separated(ax * v0[0] + ay * v0[1], ax * v1[0] + ay * v1[1], ax * v2[0] + ay * v2[1], r))
        return false;
    }
  }
  // 3. The triangle's plane against the box (zero normal for a degenerate triangle: never
  // separating, the edge axes above decide).
  const D3 n = cross(e[0], e[1]);
  const double r = h[0] * std::fabs(n[0]) + h[1] * std::fabs(n[1]) + h[2] * std::fabs(n[2]);
  return std::fabs(dot(n, v0)) <= r;
}

bool sphere_overlap(Vec3 center, float radius, const PaddedBox& pb) {
  double near2 = 0, far2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double c = center[i];
    const double dlo = c - pb.lo[i], dhi = c - pb.hi[i];
    // Nearest point: the centre clamped to the box; farthest: the farther face.
    if (dlo < 0)
      near2 += dlo * dlo;
    else if (dhi > 0)
      near2 += dhi * dhi;
    far2 += std::max(dlo * dlo, dhi * dhi);
  }
  const double r2 = double(radius) * radius;
  return near2 <= r2 && r2 <= far2;
}

bool quad_overlap(Vec3 p, Vec3 e1, Vec3 e2, const PaddedBox& pb) {
  const D3 a = to_d3(p), b = add(a, to_d3(e1)), d = add(a, to_d3(e2)), c = add(b, to_d3(e2));
  return triangle_overlap(a, b, c, pb) || triangle_overlap(a, c, d, pb);
}

/// The box `b` against the padded box.
bool box_overlap(const Bounds3& b, const PaddedBox& pb) {
  for (int i = 0; i < 3; ++i)
    if (b.lo[i] > pb.hi[i] || b.hi[i] < pb.lo[i]) return false;
  return true;
}

bool prim_overlap(const PrimitiveSet& prims, uint32_t id, const PaddedBox& pb) {
  // A moving primitive: its box over the whole time interval (conservative; the exact swept
  // volume of a moving triangle is not convex in general and is not worth its cost here).
  if (prims.moving(id)) return box_overlap(prims.prim_bounds(id), pb);
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      const Vec3* v = prims.triangle(id);
      return triangle_overlap(to_d3(v[0]), to_d3(v[1]), to_d3(v[2]), pb);
    }
    case PrimKind::kSphere: {
      const SphereData& s = prims.sphere(id);
      return sphere_overlap(s.center, s.radius, pb);
    }
    case PrimKind::kQuad: {
      const QuadData& q = prims.quad(id);
      return quad_overlap(q.p, q.e1, q.e2, pb);
    }
  }
  return true;
}

}  // namespace

bool triangle_box_overlap(Vec3 a, Vec3 b, Vec3 c, const Bounds3& box) {
  return triangle_overlap(to_d3(a), to_d3(b), to_d3(c), PaddedBox(box));
}

bool sphere_box_overlap(Vec3 center, float radius, const Bounds3& box) {
  return sphere_overlap(center, radius, PaddedBox(box));
}

bool quad_box_overlap(Vec3 p, Vec3 e1, Vec3 e2, const Bounds3& box) {
  return quad_overlap(p, e1, e2, PaddedBox(box));
}

bool prim_box_overlap(const PrimitiveSet& prims, uint32_t id, const Bounds3& box) {
  return prim_overlap(prims, id, PaddedBox(box));
}

bool prim_box_overlap(const PrimitiveSet& prims, uint32_t id, const Bounds3& prim_box,
                      const Bounds3& box) {
  const PaddedBox pb(box);
  int inside = 0;
  for (int i = 0; i < 3; ++i) {
    const double lo = prim_box.lo[i], hi = prim_box.hi[i];
    if (lo > pb.hi[i] || hi < pb.lo[i]) return false;
    inside += lo >= pb.lo[i] && hi <= pb.hi[i];
  }
  return inside >= 2 || prim_overlap(prims, id, pb);
}

}  // namespace penumbra
