/// Tests of the collision queries: exact predicates against integer arithmetic, the exact
/// triangle tests against independent references (separating axes and linear programming in
/// integers, a convex minimisation for distances), analytic cases, and the hierarchy queries
/// against brute force on random meshes, poses and motions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "penumbra/accel/collision/collision.h"
#include "penumbra/accel/collision/collision_brute.h"
#include "penumbra/accel/collision/exact_predicates.h"
#include "penumbra/accel/collision/swept_tests.h"
#include "penumbra/accel/collision/triangle_triangle.h"
#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"

namespace penumbra::collision {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

DTriangle tri(DVec3 a, DVec3 b, DVec3 c) {
  return DTriangle{{a, b, c}};
}

// ---------------------------------------------------------------------------------------------
// Integer references.

using I3 = std::array<int64_t, 3>;
__extension__ typedef __int128 I128;  // exact orientation of 21-bit coordinates
I3 isub(const I3& a, const I3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
I3 icross(const I3& a, const I3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
int64_t idot(const I3& a, const I3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
bool izero(const I3& a) {
  return a[0] == 0 && a[1] == 0 && a[2] == 0;
}
DVec3 to_d(const I3& a) {
  return {double(a[0]), double(a[1]), double(a[2])};
}
using ITri = std::array<I3, 3>;
DTriangle to_d(const ITri& t) {
  return tri(to_d(t[0]), to_d(t[1]), to_d(t[2]));
}

/// Separating-axis reference for two closed triangles with integer vertices: face normals, edge
/// cross products, and the in-plane edge normals (which decide coplanar pairs). Exact.
bool reference_triangles_intersect(const ITri& a, const ITri& b) {
  const I3 ea[3] = {isub(a[1], a[0]), isub(a[2], a[1]), isub(a[0], a[2])};
  const I3 eb[3] = {isub(b[1], b[0]), isub(b[2], b[1]), isub(b[0], b[2])};
  const I3 na = icross(ea[0], ea[1]), nb = icross(eb[0], eb[1]);
  if (izero(na) || izero(nb)) return false;  // degenerate triangles never collide
  std::vector<I3> axes{na, nb};
  for (const I3& x : ea)
    for (const I3& y : eb) axes.push_back(icross(x, y));
  for (int i = 0; i < 3; ++i) axes.push_back(icross(na, ea[i])), axes.push_back(icross(nb, eb[i]));
  for (const I3& axis : axes) {
    int64_t alo = INT64_MAX, ahi = INT64_MIN, blo = INT64_MAX, bhi = INT64_MIN;
    for (int i = 0; i < 3; ++i) {
      alo = std::min(alo, idot(a[i], axis)), ahi = std::max(ahi, idot(a[i], axis));
      blo = std::min(blo, idot(b[i], axis)), bhi = std::max(bhi, idot(b[i], axis));
    }
    if (ahi < blo || bhi < alo) return false;
  }
  return true;
}

/// Reference for the moving box: is there (u, v, t) with u, v >= 0, u + v <= 1, t in [0, 1] and
/// lo + t d <= a + u e1 + v e2 <= hi + t d? A bounded polytope in 3 variables is non-empty iff
/// one of its vertices is feasible: every triple of constraints is solved by Cramer's rule and
/// checked in integers.
bool reference_moving_box(const ITri& t, const I3& lo, const I3& hi, const I3& d) {
  const I3 e1 = isub(t[1], t[0]), e2 = isub(t[2], t[0]);
  std::vector<std::array<int64_t, 4>> rows{
      {-1, 0, 0, 0}, {0, -1, 0, 0}, {1, 1, 0, 1}, {0, 0, -1, 0}, {0, 0, 1, 1}};
  for (int k = 0; k < 3; ++k) {
    rows.push_back({-e1[k], -e2[k], d[k], t[0][k] - lo[k]});
    rows.push_back({e1[k], e2[k], -d[k], hi[k] - t[0][k]});
  }
  const auto det3 = [](const I3& r0, const I3& r1, const I3& r2) {
    return idot(r0, icross(r1, r2));
  };
  const size_t n = rows.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      for (size_t k = j + 1; k < n; ++k) {
        const auto &p = rows[i], &q = rows[j], &r = rows[k];
        const int64_t den = det3({p[0], p[1], p[2]}, {q[0], q[1], q[2]}, {r[0], r[1], r[2]});
        if (den == 0) continue;
        I3 num;
        for (int m = 0; m < 3; ++m) {
          I3 rp{p[0], p[1], p[2]}, rq{q[0], q[1], q[2]}, rr{r[0], r[1], r[2]};
          rp[m] = p[3], rq[m] = q[3], rr[m] = r[3];
          num[m] = det3(rp, rq, rr);
        }
        bool feasible = true;
        for (const auto& c : rows) {
          const int64_t lhs = c[0] * num[0] + c[1] * num[1] + c[2] * num[2], rhs = c[3] * den;
          if (den > 0 ? lhs > rhs : lhs < rhs) feasible = false;
        }
        if (feasible) return true;
      }
  return false;
}

I3 random_i3(Pcg32& rng, int range) {
  return {int64_t(rng.next_bounded(2 * range + 1)) - range,
          int64_t(rng.next_bounded(2 * range + 1)) - range,
          int64_t(rng.next_bounded(2 * range + 1)) - range};
}

/// Random integer triangles with many degenerate, touching and coplanar configurations: small
/// coordinates, and half the time both triangles on one lattice plane.
std::pair<ITri, ITri> random_integer_pair(Pcg32& rng) {
  ITri a, b;
  if (rng.next_bounded(2) == 0) {
    for (auto& p : a) p = random_i3(rng, 3);
    for (auto& p : b) p = random_i3(rng, 3);
    return {a, b};
  }
  const I3 o = random_i3(rng, 2), u = random_i3(rng, 1), v = random_i3(rng, 1);
  const auto on_plane = [&] {
    const int64_t i = int64_t(rng.next_bounded(7)) - 3, j = int64_t(rng.next_bounded(7)) - 3;
    return I3{o[0] + i * u[0] + j * v[0], o[1] + i * u[1] + j * v[1], o[2] + i * u[2] + j * v[2]};
  };
  for (auto& p : a) p = on_plane();
  for (auto& p : b) p = on_plane();
  return {a, b};
}

// ---------------------------------------------------------------------------------------------
// Predicates.

TEST(ExactPredicates, SignsMatchInt128OnNearlyCoplanarPoints) {
  Pcg32 rng(7);
  const auto big = [&] { return int64_t(rng.next_bounded(1u << 21)) - (1 << 20); };
  const unsigned long long before = exact_predicate_fallbacks();
  for (int it = 0; it < 20000; ++it) {
    I3 a{big(), big(), big()}, b{big(), big(), big()}, c{big(), big(), big()};
    // d near the plane abc: an affine combination rounded to integers, plus a tiny offset.
    const double u = rng.next_double(), v = rng.next_double();
    I3 d;
    for (int k = 0; k < 3; ++k)
      d[k] = int64_t(std::llround(a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]))) +
             int64_t(rng.next_bounded(3)) - 1;
    const I3 e1 = isub(b, a), e2 = isub(c, a), e3 = isub(d, a);
    const I128 det = I128(e1[0]) * (I128(e2[1]) * e3[2] - I128(e2[2]) * e3[1]) +
                     I128(e1[1]) * (I128(e2[2]) * e3[0] - I128(e2[0]) * e3[2]) +
                     I128(e1[2]) * (I128(e2[0]) * e3[1] - I128(e2[1]) * e3[0]);
    const int expect = det > 0 ? 1 : (det < 0 ? -1 : 0);
    ASSERT_EQ(orient3d(to_d(a), to_d(b), to_d(c), to_d(d)), expect) << it;
    ASSERT_EQ(PlaneOrientation(to_d(a), to_d(b), to_d(c))(to_d(d)), expect) << it;
    // 2D: the xy projections, with c moved onto the line ab up to rounding.
    const int64_t cx = int64_t(std::llround(a[0] + u * (b[0] - a[0]))),
                  cy = int64_t(std::llround(a[1] + u * (b[1] - a[1])));
    const I128 det2 = I128(b[0] - a[0]) * (cy - a[1]) - I128(b[1] - a[1]) * (cx - a[0]);
    ASSERT_EQ(orient2d(a[0], a[1], b[0], b[1], cx, cy), det2 > 0 ? 1 : (det2 < 0 ? -1 : 0));
  }
  EXPECT_GT(exact_predicate_fallbacks(), before) << "the exact stage was exercised";
}

TEST(ExactPredicates, TinyPerturbationsOfACollinearTripleAreClassifiedConsistently) {
  // Shewchuk's example: points near the line y = x, offsets of one unit in the last place.
  const double base = 0.5;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const double px = base + i * 0x1p-53, py = base + j * 0x1p-53;
      const int s = orient2d(px, py, 12.0, 12.0, 24.0, 24.0);
      EXPECT_EQ(s, i == j ? 0 : (i > j ? -1 : 1)) << i << " " << j;
      EXPECT_EQ(orient2d(12.0, 12.0, px, py, 24.0, 24.0), -s);
      EXPECT_EQ(orient2d(12.0, 12.0, 24.0, 24.0, px, py), s);
    }
}

// ---------------------------------------------------------------------------------------------
// Triangle-triangle.

TEST(TriangleTriangle, AnalyticCases) {
  const DTriangle base = tri({0, 0, 0}, {4, 0, 0}, {0, 4, 0});
  // Crossing: a vertical triangle piercing the interior.
  EXPECT_TRUE(triangles_intersect(base, tri({1, 1, -1}, {1, 1, 1}, {2, 0.5, 1})));
  // Disjoint: above, parallel.
  EXPECT_FALSE(triangles_intersect(base, tri({0, 0, 1}, {4, 0, 1}, {0, 4, 1})));
  // Disjoint: the plane crosses the other triangle outside it.
  EXPECT_FALSE(triangles_intersect(base, tri({5, 5, -1}, {5, 5, 1}, {6, 5, 0})));
  // Sharing an edge (a hinge) and sharing only a vertex.
  EXPECT_TRUE(triangles_intersect(base, tri({0, 0, 0}, {4, 0, 0}, {2, -1, 3})));
  EXPECT_TRUE(triangles_intersect(base, tri({4, 0, 0}, {6, 1, 1}, {6, -1, 2})));
  // Touching: a vertex on the other's interior; an edge crossing the other's edge.
  EXPECT_TRUE(triangles_intersect(base, tri({1, 1, 0}, {1, 1, 2}, {2, 2, 2})));
  EXPECT_TRUE(triangles_intersect(base, tri({2, 2, -1}, {2, 2, 1}, {5, 5, 0})));
  // Coplanar: overlapping, contained, touching at a vertex, along an edge, disjoint.
  EXPECT_TRUE(triangles_intersect(base, tri({1, 1, 0}, {5, 1, 0}, {1, 5, 0})));
  EXPECT_TRUE(triangles_intersect(base, tri({0.5, 0.5, 0}, {1, 0.5, 0}, {0.5, 1, 0})));
  EXPECT_TRUE(triangles_intersect(base, tri({4, 0, 0}, {5, 0, 0}, {5, 1, 0})));
  EXPECT_TRUE(triangles_intersect(base, tri({0, 0, 0}, {4, 0, 0}, {2, -3, 0})));
  EXPECT_FALSE(triangles_intersect(base, tri({3, 3, 0}, {5, 3, 0}, {3, 5, 0})));
  EXPECT_FALSE(triangles_intersect(base, tri({2.01, 2.01, 0}, {5, 2, 0}, {2, 5, 0})));
  EXPECT_TRUE(triangles_intersect(base, tri({2, 2, 0}, {5, 2, 0}, {2, 5, 0})));
}

TEST(TriangleTriangle, DegenerateTrianglesNeverCollide) {
  const DTriangle base = tri({0, 0, 0}, {4, 0, 0}, {0, 4, 0});
  const DTriangle degenerate[] = {
      tri({1, 1, -1}, {1, 1, 1}, {1, 1, 3}),         // collinear, through the interior
      tri({1, 1, 0}, {1, 1, 0}, {1, 1, 0}),          // a point on the triangle
      tri({1, 1, 0}, {2, 1, 0}, {1, 1, 0}),          // repeated vertex, segment on the face
      tri({1, 1, kNaN}, {1, 1, 1}, {2, 0.5, 1}),     // NaN
      tri({1, 1, -1}, {1, 1, INFINITY}, {2, 0, 1}),  // infinity
  };
  for (const DTriangle& d : degenerate) {
    EXPECT_FALSE(is_valid_triangle(d));
    EXPECT_FALSE(triangles_intersect(base, d));
    EXPECT_FALSE(triangles_intersect(d, base));
    EXPECT_FALSE(triangles_intersect(d, d));
  }
  EXPECT_TRUE(is_valid_triangle(base));
  EXPECT_TRUE(triangles_intersect(base, base));
}

TEST(TriangleTriangle, MatchesSeparatingAxisReferenceOnIntegerTriangles) {
  Pcg32 rng(11);
  int hits = 0, coplanar = 0;
  for (int it = 0; it < 60000; ++it) {
    const auto [a, b] = random_integer_pair(rng);
    const bool expect = reference_triangles_intersect(a, b);
    const DTriangle da = to_d(a), db = to_d(b);
    ASSERT_EQ(triangles_intersect(da, db), expect) << "case " << it;
    // Symmetric, and independent of the vertex order of either triangle.
    ASSERT_EQ(triangles_intersect(db, da), expect) << "case " << it;
    ASSERT_EQ(triangles_intersect(tri(da[1], da[2], da[0]), tri(db[0], db[2], db[1])), expect)
        << "case " << it;
    hits += expect;
    if (is_valid_triangle(da) && is_valid_triangle(db) &&
        orient3d(da[0], da[1], da[2], db[0]) == 0 && orient3d(da[0], da[1], da[2], db[1]) == 0 &&
        orient3d(da[0], da[1], da[2], db[2]) == 0)
      ++coplanar;
  }
  EXPECT_GT(hits, 5000);
  EXPECT_GT(coplanar, 5000);
}

TEST(TriangleTriangle, AgreesWithItselfUnderExactTranslation) {
  // Translating both triangles by a power-of-two-aligned offset is exact in double, so the answer
  // must not change; small random float triangles exercise the floating-point filter.
  Pcg32 rng(5);
  for (int it = 0; it < 20000; ++it) {
    DTriangle a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = {double(rng.next_float()), double(rng.next_float()), double(rng.next_float())};
      b[k] = {double(rng.next_float()), double(rng.next_float()), double(rng.next_float())};
    }
    const DVec3 shift{64.0, -128.0, 32.0};
    DTriangle as = a, bs = b;
    for (int k = 0; k < 3; ++k) as[k] = a[k] + shift, bs[k] = b[k] + shift;
    ASSERT_EQ(triangles_intersect(a, b), triangles_intersect(as, bs)) << it;
  }
}

// ---------------------------------------------------------------------------------------------
// Moving sphere and moving box against one triangle.

/// Independent point-triangle distance: projection to the plane when inside, else the nearest
/// edge (clamped projection on each).
double reference_point_distance(const DVec3& p, const DTriangle& t) {
  const DVec3 n = cross(t[1] - t[0], t[2] - t[0]);
  const double nn = length_sq(n);
  const DVec3 q = p - n * (dot(p - t[0], n) / nn);
  bool inside = true;
  for (int i = 0; i < 3; ++i)
    if (dot(cross(t[(i + 1) % 3] - t[i], q - t[i]), n) < 0) inside = false;
  if (inside) return std::fabs(dot(p - t[0], n)) / std::sqrt(nn);
  double best = INFINITY;
  for (int i = 0; i < 3; ++i) {
    const DVec3 a = t[i], e = t[(i + 1) % 3] - a;
    const double s = std::clamp(dot(p - a, e) / length_sq(e), 0.0, 1.0);
    best = std::min(best, std::sqrt(length_sq(p - (a + e * s))));
  }
  return best;
}

/// Independent segment-triangle distance: the distance from a point moving along the segment to
/// the (convex) triangle is convex in the parameter; ternary search finds its minimum.
double reference_segment_distance(const DVec3& p, const DVec3& q, const DTriangle& t) {
  double lo = 0, hi = 1;
  const auto f = [&](double s) { return reference_point_distance(p + (q - p) * s, t); };
  for (int i = 0; i < 200; ++i) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (f(m1) <= f(m2))
      hi = m2;
    else
      lo = m1;
  }
  return std::min({f(lo), f(0.0), f(1.0)});
}

TEST(SweptTests, SegmentTriangleDistanceMatchesConvexMinimisation) {
  Pcg32 rng(3);
  const auto rnd = [&] {
    return DVec3(rng.next_double() * 4 - 2, rng.next_double() * 4 - 2, rng.next_double() * 4 - 2);
  };
  for (int it = 0; it < 5000; ++it) {
    const DTriangle t = tri(rnd(), rnd(), rnd());
    DVec3 p = rnd(), q = rnd();
    if (it % 5 == 0) q = p;  // zero motion
    if (it % 7 == 0) {       // motion parallel to the face, at some height
      const DVec3 n = cross(t[1] - t[0], t[2] - t[0]);
      q = p + cross(n, rnd());
    }
    const double expect = reference_segment_distance(p, q, t);
    const double got = std::sqrt(segment_triangle_distance_sq(p, q, t));
    ASSERT_NEAR(got, expect, 1e-7) << it;
  }
}

TEST(SweptTests, MovingSphereAtDistanceExactlyRadiusTouches) {
  const DTriangle t = tri({0, 0, 0}, {4, 0, 0}, {0, 4, 0});
  const double r = 0.5, eps = 1e-9;
  // Sliding parallel to the face at height r, over the interior.
  EXPECT_TRUE(moving_sphere_touches(t, {-2, 1, r}, {6, 1, r}, r));
  EXPECT_FALSE(moving_sphere_touches(t, {-2, 1, r}, {6, 1, r}, r * (1 - eps)));
  EXPECT_FALSE(moving_sphere_touches(t, {-2, 1, r * (1 + eps)}, {6, 1, r * (1 + eps)}, r));
  EXPECT_TRUE(
      moving_sphere_touches(t, {-2, 1, r * (1 + eps)}, {6, 1, r * (1 + eps)}, r * (1 + 2 * eps)));
  // Passing a vertex in the plane at distance 1.
  EXPECT_TRUE(moving_sphere_touches(t, {5, -3, 0}, {5, 3, 0}, 1.0));
  EXPECT_FALSE(moving_sphere_touches(t, {5, -3, 0}, {5, 3, 0}, 1.0 - eps));
  // Passing the hypotenuse x + y = 4 at distance sqrt(2), approaching from the side.
  EXPECT_TRUE(moving_sphere_touches(t, {3, 3, 0}, {3, 3, 0}, std::sqrt(2.0)));
  EXPECT_FALSE(moving_sphere_touches(t, {3, 3, 0}, {4, 4, 0}, std::sqrt(2.0) * (1 - eps)));
  // Crossing the face with radius 0, and stopping just short of it.
  EXPECT_TRUE(moving_sphere_touches(t, {1, 1, -5}, {1, 1, 5}, 0.0));
  EXPECT_TRUE(moving_sphere_touches(t, {1, 1, 5}, {1, 1, 0.25}, 0.25));
  EXPECT_FALSE(moving_sphere_touches(t, {1, 1, 5}, {1, 1, 0.25 + eps}, 0.25));
  // Zero motion.
  EXPECT_TRUE(moving_sphere_touches(t, {1, 1, 0.5}, {1, 1, 0.5}, 0.5));
  EXPECT_FALSE(moving_sphere_touches(t, {1, 1, 0.5}, {1, 1, 0.5}, 0.49));
}

TEST(SweptTests, MovingBoxAnalyticCases) {
  const DTriangle t = tri({0, 0, 0}, {4, 0, 0}, {0, 4, 0});
  const DBox above{{0, 0, 1}, {1, 1, 2}};
  EXPECT_TRUE(moving_box_touches(t, above, {0, 0, -1}));  // reaches the face at the end
  EXPECT_FALSE(moving_box_touches(t, above, {0, 0, -0.999}));
  EXPECT_FALSE(moving_box_touches(t, above, {0, 0, 0}));
  // Sliding parallel to the face: resting on it, and a hair above.
  EXPECT_TRUE(moving_box_touches(t, {{-3, 1, 0}, {-2, 2, 1}}, {10, 0, 0}));
  EXPECT_FALSE(moving_box_touches(t, {{-3, 1, 1e-9}, {-2, 2, 1}}, {10, 0, 0}));
  // Moving diagonally towards the hypotenuse: the corner reaches x + y = 4 exactly.
  EXPECT_TRUE(moving_box_touches(t, {{3, 3, -1}, {4, 4, 1}}, {-1, -1, 0}));
  EXPECT_FALSE(moving_box_touches(t, {{3, 3, -1}, {4, 4, 1}}, {-0.99, -0.99, 0}));
  // A flat (zero-thickness) box, and a box containing the whole triangle.
  EXPECT_TRUE(moving_box_touches(t, {{1, 1, 0}, {1, 1, 0}}, {0, 0, 0}));
  EXPECT_TRUE(moving_box_touches(t, {{-9, -9, -9}, {9, 9, 9}}, {0, 0, 0}));
  // Sweeping past the triangle's corner diagonally above the plane: misses.
  EXPECT_FALSE(moving_box_touches(t, {{5, -1, 0.5}, {6, 0, 1}}, {-2, 4, 0}));
}

TEST(SweptTests, MovingBoxMatchesLinearProgrammingReference) {
  Pcg32 rng(13);
  int hits = 0, tested = 0;
  for (int it = 0; it < 6000; ++it) {
    ITri t;
    for (auto& p : t) p = random_i3(rng, 4);
    if (izero(icross(isub(t[1], t[0]), isub(t[2], t[0])))) continue;
    I3 lo = random_i3(rng, 4), hi = lo;
    for (int k = 0; k < 3; ++k) hi[k] += rng.next_bounded(3);  // flat boxes too
    I3 d = random_i3(rng, 5);
    if (it % 6 == 0) d = {0, 0, 0};
    const bool expect = reference_moving_box(t, lo, hi, d);
    ASSERT_EQ(moving_box_touches(to_d(t), {to_d(lo), to_d(hi)}, to_d(d)), expect) << it;
    hits += expect, ++tested;
  }
  EXPECT_GT(hits, tested / 10);
  EXPECT_LT(hits, tested - tested / 10);
}

// ---------------------------------------------------------------------------------------------
// Meshes.

void add_triangle(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c) {
  const auto base = static_cast<uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), {a, b, c});
  m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

TriangleMesh random_soup(int n, uint64_t seed, float size) {
  Pcg32 rng(seed);
  TriangleMesh m;
  const auto near = [&](Vec3 c) {
    return c +
           Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f) * size;
  };
  for (int i = 0; i < n; ++i) {
    const Vec3 c(rng.next_float(), rng.next_float(), rng.next_float());
    add_triangle(m, near(c), near(c), near(c));
  }
  return m;
}

/// A surface from a grid of rows x cols vertices f(i, j); columns wrap around, rows wrap when
/// `wrap_rows` (a torus) and otherwise end at the last row (a sphere from pole to pole).
template <class F>
TriangleMesh grid_surface(int rows, int cols, bool wrap_rows, const F& f) {
  TriangleMesh m;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m.positions.push_back(f(i, j));
  const auto id = [&](int i, int j) { return uint32_t((i % rows) * cols + (j % cols)); };
  for (int i = 0; i < (wrap_rows ? rows : rows - 1); ++i)
    for (int j = 0; j < cols; ++j)
      m.indices.insert(m.indices.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j),
                                         id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

TriangleMesh torus(float major, float minor, int rings, int sides) {
  constexpr float kTau = 2 * std::numbers::pi_v<float>;
  return grid_surface(rings, sides, true, [&](int i, int j) {
    const float u = kTau * float(i) / float(rings), v = kTau * float(j) / float(sides);
    const float r = major + minor * std::cos(v);
    return Vec3(r * std::cos(u), r * std::sin(u), minor * std::sin(v));
  });
}

/// A UV sphere; the triangles at the poles have two equal vertices (degenerate, to be skipped).
TriangleMesh uv_sphere(float radius, int rings, int sides) {
  constexpr float kPi = std::numbers::pi_v<float>;
  return grid_surface(rings + 1, sides, false, [&](int i, int j) {
    const float theta = kPi * float(i) / float(rings), phi = 2 * kPi * float(j) / float(sides);
    const float s = (i == 0 || i == rings) ? 0.0f : std::sin(theta);
    return Vec3(radius * s * std::cos(phi), radius * s * std::sin(phi), radius * std::cos(theta));
  });
}

/// An n x n grid of unit squares (two triangles each) in the plane z = h, offset by (dx, dy).
TriangleMesh flat_grid(int n, float dx, float dy, float h) {
  TriangleMesh m;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Vec3 p(i + dx, j + dy, h);
      add_triangle(m, p, p + Vec3(1, 0, 0), p + Vec3(1, 1, 0));
      add_triangle(m, p, p + Vec3(1, 1, 0), p + Vec3(0, 1, 0));
    }
  return m;
}

Transform random_pose(Pcg32& rng, float spread) {
  const Vec3 axis(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() + 0.1f);
  const Vec3 t((rng.next_float() - 0.5f) * spread, (rng.next_float() - 0.5f) * spread,
               (rng.next_float() - 0.5f) * spread);
  return translate(t) * rotate(rng.next_float() * 360.0f, axis);
}

void expect_pairs_match_brute(const CollisionMesh& a, const CollisionMesh& b,
                              const std::string& what, size_t* found = nullptr) {
  QueryStats stats;
  const auto fast = intersecting_pairs(a, b, &stats);
  const auto slow = intersecting_pairs_brute(a, b);
  ASSERT_EQ(fast, slow) << what << ": " << fast.size() << " vs brute " << slow.size();
  EXPECT_TRUE(std::is_sorted(fast.begin(), fast.end()));
  if (found) *found += fast.size();
}

TEST(CollisionQueries, RandomSoupPairsMatchBruteForce) {
  size_t found = 0;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const TriangleMesh a = random_soup(300, seed, 0.2f), b = random_soup(250, seed + 100, 0.3f);
    expect_pairs_match_brute(CollisionMesh(a), CollisionMesh(b), "soup", &found);
  }
  EXPECT_GT(found, 500u);
}

TEST(CollisionQueries, TessellatedShapesInRandomPosesMatchBruteForce) {
  Pcg32 rng(21);
  const TriangleMesh shapes[] = {torus(1.0f, 0.3f, 24, 12), uv_sphere(0.8f, 14, 20),
                                 torus(0.7f, 0.25f, 18, 10)};
  size_t found = 0;
  for (int it = 0; it < 24; ++it) {
    const TriangleMesh& ma = shapes[it % 3];
    const TriangleMesh& mb = shapes[(it / 3) % 3];
    const CollisionMesh a(ma, random_pose(rng, 1.0f)), b(mb, random_pose(rng, 2.0f));
    expect_pairs_match_brute(a, b, "shapes " + std::to_string(it), &found);
  }
  EXPECT_GT(found, 200u);
}

TEST(CollisionQueries, CoplanarAndTouchingMeshesMatchBruteForce) {
  size_t found = 0;
  // Same plane: aligned (shared edges and vertices everywhere), half-offset, quarter-offset.
  expect_pairs_match_brute(CollisionMesh(flat_grid(8, 0, 0, 0)),
                           CollisionMesh(flat_grid(8, 0, 0, 0)), "identical grids", &found);
  expect_pairs_match_brute(CollisionMesh(flat_grid(8, 0, 0, 0)),
                           CollisionMesh(flat_grid(6, 0.5f, 0.5f, 0)), "offset grids", &found);
  expect_pairs_match_brute(CollisionMesh(flat_grid(8, 0, 0, 0)),
                           CollisionMesh(flat_grid(6, 0.25f, 0.75f, 0)), "quarter grids", &found);
  // Parallel planes (no pairs), and a grid standing on another along the line y = 3.
  expect_pairs_match_brute(CollisionMesh(flat_grid(8, 0, 0, 0)),
                           CollisionMesh(flat_grid(8, 0, 0, 1)), "parallel grids");
  const CollisionMesh standing(flat_grid(6, 0, 0, 0), translate({0, 3, 0}) * rotate(90, {1, 0, 0}));
  expect_pairs_match_brute(CollisionMesh(flat_grid(8, 0, 0, 0)), standing, "standing", &found);
  EXPECT_GT(found, 400u);
}

TEST(CollisionQueries, MeshAgainstItselfMatchesBruteForce) {
  const TriangleMesh t = torus(1.0f, 0.3f, 32, 16);
  size_t found = 0;
  // Identical: every triangle meets itself and its neighbours.
  const CollisionMesh a(t);
  expect_pairs_match_brute(a, a, "itself", &found);
  EXPECT_GE(found, t.triangle_count());
  // Translated by small offsets, along an axis and obliquely.
  for (const Vec3 d : {Vec3(0.01f, 0, 0), Vec3(1e-4f, 2e-4f, -1e-4f), Vec3(0, 0, 0.3f)})
    expect_pairs_match_brute(a, CollisionMesh(t, translate(d)), "translated", &found);
}

TEST(CollisionQueries, NewPoseRefitsWithoutRebuilding) {
  Pcg32 rng(8);
  const TriangleMesh ta = torus(1.0f, 0.3f, 20, 10), tb = uv_sphere(0.7f, 10, 16);
  const CollisionMesh a(ta);
  CollisionMesh b(tb);
  const size_t nodes = b.stats().nodes;
  for (int it = 0; it < 8; ++it) {
    const Transform pose = random_pose(rng, 1.5f);
    b.set_pose(pose);
    EXPECT_EQ(b.stats().nodes, nodes);
    const CollisionMesh fresh(tb, pose);
    EXPECT_EQ(intersecting_pairs(a, b), intersecting_pairs(a, fresh));
    expect_pairs_match_brute(a, b, "posed " + std::to_string(it));
  }
}

TEST(CollisionQueries, HierarchyCullsMostPairs) {
  const TriangleMesh t = torus(1.0f, 0.3f, 48, 24);
  const CollisionMesh a(t), b(t, translate({0.05f, 0.02f, 0}));
  QueryStats stats;
  const auto pairs = intersecting_pairs(a, b, &stats);
  EXPECT_FALSE(pairs.empty());
  EXPECT_LT(stats.exact_tests, a.triangle_count() * b.triangle_count() / 50);
  EXPECT_GE(stats.exact_tests, pairs.size());
}

TEST(CollisionQueries, DegenerateAndNonFiniteTrianglesAreSkipped) {
  TriangleMesh m = flat_grid(3, 0, 0, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  add_triangle(m, {1, 1, -1}, {1, 1, 1}, {1, 1, 2});   // collinear, crossing the grid
  add_triangle(m, {1, 1, nan}, {0, 0, 0}, {2, 2, 1});  // NaN
  add_triangle(m, {0.5f, 0.5f, 0}, {0.5f, 0.5f, 0}, {0.5f, 0.5f, 0});  // a point
  const CollisionMesh a(m), b(flat_grid(2, 0.5f, 0.5f, 0));
  EXPECT_EQ(a.valid_count(), 18u);
  const auto pairs = intersecting_pairs(a, b);
  EXPECT_EQ(pairs, intersecting_pairs_brute(a, b));
  for (const TrianglePair& p : pairs) EXPECT_LT(p.a, 18u);
  const MovingSphere s{{1, 1, -3}, {1, 1, 3}, 0.1};
  const auto touched = touched_triangles(a, s);
  EXPECT_EQ(touched, touched_triangles_brute(a, s));
  for (uint32_t id : touched) EXPECT_LT(id, 18u);
}

TEST(CollisionQueries, BadInputIsRejected) {
  TriangleMesh m = flat_grid(1, 0, 0, 0);
  m.indices.push_back(99), m.indices.push_back(0), m.indices.push_back(1);
  EXPECT_THROW(CollisionMesh{m}, Error);
  const CollisionMesh ok(flat_grid(1, 0, 0, 0));
  EXPECT_THROW(touched_triangles(ok, MovingSphere{{0, 0, 0}, {1, 1, 1}, -1}), Error);
  EXPECT_THROW(touched_triangles(ok, MovingSphere{{0, 0, kNaN}, {1, 1, 1}, 1}), Error);
  EXPECT_THROW(touched_triangles(ok, MovingBox{{{1, 0, 0}, {0, 1, 1}}, {0, 0, 0}}), Error);
  // An empty mesh answers nothing.
  const CollisionMesh empty{TriangleMesh{}};
  EXPECT_TRUE(intersecting_pairs(empty, ok).empty());
  EXPECT_TRUE(touched_triangles(empty, MovingSphere{{0, 0, 0}, {1, 1, 1}, 1}).empty());
}

/// Moving spheres and boxes over a mesh: random sweeps, zero motion, sliding parallel to a face
/// at exactly the contact distance, and grazing a vertex.
TEST(CollisionQueries, SweptQueriesMatchBruteForce) {
  Pcg32 rng(99);
  const TriangleMesh meshes[] = {torus(1.0f, 0.3f, 32, 16), random_soup(600, 4, 0.15f),
                                 flat_grid(10, 0, 0, 0)};
  size_t found = 0, queries = 0;
  for (const TriangleMesh& tm : meshes) {
    const CollisionMesh mesh(tm, random_pose(rng, 0.5f));
    const Bounds3 bb = mesh.bounds();
    const auto in_box = [&] {
      const Vec3 d = bb.diagonal();
      return DVec3(bb.lo.x + d.x * (rng.next_float() * 1.4f - 0.2f),
                   bb.lo.y + d.y * (rng.next_float() * 1.4f - 0.2f),
                   bb.lo.z + d.z * (rng.next_float() * 1.4f - 0.2f));
    };
    const double scale = length_sq(DVec3(bb.diagonal()));
    for (int it = 0; it < 300; ++it) {
      // A triangle to graze: slide along its face at height r, or stop a box at its vertex.
      const uint32_t id = rng.next_bounded(uint32_t(mesh.triangle_count()));
      const DTriangle& t = mesh.triangle(id);
      const double r = std::sqrt(scale) * 0.05 * rng.next_double();
      MovingSphere s{in_box(), in_box(), r};
      DVec3 lo = in_box();
      const DVec3 size = DVec3(bb.diagonal()) * (0.1 * rng.next_double());
      MovingBox b{{lo, lo + size}, in_box() - lo};
      switch (it % 4) {
        case 0:  // zero motion
          s.to = s.from, b.displacement = {0, 0, 0};
          break;
        case 1: {  // parallel to a face at the contact distance
          if (!mesh.valid(id)) break;
          DVec3 n = cross(t[1] - t[0], t[2] - t[0]);
          n = n * (1.0 / std::sqrt(length_sq(n)));
          s.from = t[0] + n * r, s.to = t[1] + n * r;
          b.box = {t[0], t[0] + size};
          b.displacement = t[2] - t[0];
          break;
        }
        case 2:  // grazing a vertex: the box's corner ends exactly on it
          b.displacement = t[1] - b.box.lo;
          s.to = t[1] + DVec3(r, 0, 0);
          break;
        default:
          break;
      }
      QueryStats st;
      const auto fs = touched_triangles(mesh, s, &st);
      ASSERT_EQ(fs, touched_triangles_brute(mesh, s)) << "sphere " << it;
      const auto fb = touched_triangles(mesh, b);
      ASSERT_EQ(fb, touched_triangles_brute(mesh, b)) << "box " << it;
      found += fs.size() + fb.size(), queries += 2;
    }
  }
  EXPECT_GT(found, queries);  // on average more than one triangle per query
}

}  // namespace
}  // namespace penumbra::collision
