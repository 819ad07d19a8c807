/// Moving primitives in PrimitiveSet: a primitive at time t is the linear interpolation of its
/// two ends, hit exactly where the static primitive at that position is; its bounds cover the
/// whole interval; static primitives stay on the static path.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "penumbra/core/rng.h"
#include "penumbra/geometry/sphere_direction.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {
namespace {

Vec3 random_vec(Pcg32& rng) {
  return {rng.next_float(), rng.next_float(), rng.next_float()};
}

Vec3 random_dir(Pcg32& rng) {
  return sample_uniform_sphere({rng.next_float(), rng.next_float()});
}

/// The interpolation the documentation promises, in double: (1 - t) a + t b.
Vec3 lerp_d(double t, Vec3 a, Vec3 b) {
  const auto f = [t](float x, float y) { return float((1.0 - t) * x + t * y); };
  return {f(a.x, b.x), f(a.y, b.y), f(a.z, b.z)};
}

bool near(Vec3 a, Vec3 b, float tol) {
  return std::fabs(a.x - b.x) <= tol && std::fabs(a.y - b.y) <= tol && std::fabs(a.z - b.z) <= tol;
}

/// One moving primitive of each kind, from random ends.
PrimitiveSet moving_set(Pcg32& rng) {
  PrimitiveSet set;
  TriangleMesh m;
  m.positions = {random_vec(rng), random_vec(rng), random_vec(rng)};
  m.indices = {0, 1, 2};
  set.add_moving_mesh(m, Transform(), translate(random_vec(rng)) * rotate(20.0f, random_dir(rng)),
                      0);
  set.add_moving_sphere({random_vec(rng), 0.3f}, {random_vec(rng) + Vec3(1.0f), 0.5f}, 1);
  set.add_moving_quad({random_vec(rng), random_dir(rng), random_dir(rng)},
                      {random_vec(rng), random_dir(rng), random_dir(rng)}, 2);
  return set;
}

TEST(MovingPrimitive, IsTheLinearInterpolationOfItsEnds) {
  Pcg32 rng(1, 1);
  const PrimitiveSet set = moving_set(rng);
  ASSERT_TRUE(set.has_motion());
  EXPECT_EQ(set.moving_count(), 3u);
  for (float t : {0.0f, 0.125f, 0.3f, 0.5f, 0.77f, 1.0f}) {
    Vec3 v[3];
    set.triangle_at(0, t, v);
    for (int k = 0; k < 3; ++k)
      EXPECT_TRUE(near(v[k], lerp_d(t, set.triangle(0)[k], set.triangle_end(0)[k]), 1e-6f)) << t;
    const SphereData s = set.sphere_at(1, t);
    EXPECT_TRUE(near(s.center, lerp_d(t, set.sphere(1).center, set.sphere_end(1).center), 1e-6f));
    EXPECT_NEAR(s.radius, 0.3f + 0.2f * t, 1e-6f);
    const QuadData q = set.quad_at(2, t);
    EXPECT_TRUE(near(q.p, lerp_d(t, set.quad(2).p, set.quad_end(2).p), 1e-6f));
    EXPECT_TRUE(near(q.e1, lerp_d(t, set.quad(2).e1, set.quad_end(2).e1), 1e-6f));
    EXPECT_TRUE(near(q.e2, lerp_d(t, set.quad(2).e2, set.quad_end(2).e2), 1e-6f));
  }
  // The ends exactly; times outside [0, 1] (and NaN) stay at the ends.
  Vec3 v[3];
  for (float t : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    set.triangle_at(0, t, v);
    EXPECT_EQ(v[2], set.triangle(0)[2]) << t;
    EXPECT_EQ(set.sphere_at(1, t).center, set.sphere(1).center) << t;
    EXPECT_EQ(set.quad_at(2, t).e1, set.quad(2).e1) << t;
  }
  for (float t : {1.0f, 7.0f}) {
    set.triangle_at(0, t, v);
    EXPECT_EQ(v[1], set.triangle_end(0)[1]) << t;
    EXPECT_EQ(set.sphere_at(1, t).radius, 0.5f) << t;
    EXPECT_EQ(set.quad_at(2, t).p, set.quad_end(2).p) << t;
  }
}

// The moving primitive at time t, hit by rays of time t, gives bit for bit the hits of a static
// primitive placed at its interpolated position: same hit or miss, same t, u, v.
TEST(MovingPrimitive, IsHitExactlyWhereTheStaticPrimitiveAtItsPositionIs) {
  Pcg32 rng(2, 2);
  size_t hits = 0;
  for (int scene = 0; scene < 50; ++scene) {
    const PrimitiveSet set = moving_set(rng);
    for (int i = 0; i < 200; ++i) {
      const float time = rng.next_float();
      PrimitiveSet frozen;  // the three primitives at `time`, static
      TriangleMesh m;
      m.positions.resize(3);
      set.triangle_at(0, time, m.positions.data());
      m.indices = {0, 1, 2};
      frozen.add_mesh(m, Transform(), 0);
      frozen.add_sphere(set.sphere_at(1, time), 1);
      frozen.add_quad(set.quad_at(2, time), 2);
      ASSERT_FALSE(frozen.has_motion());
      // Rays aimed at a random point near the primitives.
      Ray ray;
      ray.o = random_vec(rng) * 6.0f - Vec3(2.0f);
      ray.d = normalize(random_vec(rng) * 2.0f - ray.o);
      ray.time = time;
      const PreparedRay pr(ray);
      for (uint32_t id = 0; id < 3; ++id) {
        Hit a, b;
        const bool ha = set.intersect(id, pr, a), hb = frozen.intersect(id, pr, b);
        ASSERT_EQ(ha, hb) << "prim " << id << " time " << time;
        if (!ha) continue;
        ++hits;
        EXPECT_EQ(a.t, b.t);
        EXPECT_EQ(a.u, b.u);
        EXPECT_EQ(a.v, b.v);
        EXPECT_EQ(set.occludes(id, pr), frozen.occludes(id, pr));
      }
    }
  }
  EXPECT_GT(hits, 2000u);  // the comparison saw many hits, not only misses
}

// Bounds over the interval: the union of both ends' boxes, containing the primitive at any time.
TEST(MovingPrimitive, BoundsCoverTheWholeInterval) {
  Pcg32 rng(3, 3);
  for (int scene = 0; scene < 100; ++scene) {
    const PrimitiveSet set = moving_set(rng);
    Bounds3 tri = Bounds3::of_point(set.triangle(0)[0]);
    for (int k = 0; k < 3; ++k) tri.extend(set.triangle(0)[k]), tri.extend(set.triangle_end(0)[k]);
    EXPECT_EQ(set.prim_bounds(0).lo, tri.lo);
    EXPECT_EQ(set.prim_bounds(0).hi, tri.hi);
    for (int i = 0; i <= 64; ++i) {
      const float t = float(i) / 64.0f;
      Vec3 v[3];
      set.triangle_at(0, t, v);
      for (const Vec3& p : v) EXPECT_TRUE(set.prim_bounds(0).contains(p)) << t;
      const SphereData s = set.sphere_at(1, t);
      EXPECT_TRUE(set.prim_bounds(1).contains(s.center + Vec3(s.radius)));
      EXPECT_TRUE(set.prim_bounds(1).contains(s.center - Vec3(s.radius)));
      const QuadData q = set.quad_at(2, t);
      for (const Vec3& p : {q.p, q.p + q.e1, q.p + q.e2, q.p + q.e1 + q.e2})
        EXPECT_TRUE(set.prim_bounds(2).contains(p)) << t;
    }
  }
}

// A ray of time 1 misses where the primitive was at time 0, and hits where it went.
TEST(MovingPrimitive, RaysSeeThePrimitiveAtTheirTime) {
  PrimitiveSet set;
  set.add_moving_sphere({{0, 0, 0}, 1}, {{10, 0, 0}, 1}, 0);
  Ray ray{{0, 0, -5}, {0, 0, 1}};
  for (float t : {0.0f, 0.05f, 0.5f, 1.0f}) {
    ray.time = t;
    Hit h;
    EXPECT_EQ(set.intersect(0, PreparedRay(ray), h), t <= 0.05f) << t;
  }
  ray.o = {5, 0, -5};  // the centre at time 0.5
  ray.time = 0.5f;
  Hit h;
  ASSERT_TRUE(set.intersect(0, PreparedRay(ray), h));
  EXPECT_FLOAT_EQ(h.t, 4.0f);
}

// Primitives whose ends coincide are static: no end copy, the static path, all_triangles kept.
TEST(MovingPrimitive, EqualEndsMakeAStaticPrimitive) {
  PrimitiveSet set;
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  set.add_moving_mesh(m, translate({1, 2, 3}), translate({1, 2, 3}), 0);
  EXPECT_FALSE(set.has_motion());
  EXPECT_FALSE(set.moving(0));
  EXPECT_TRUE(set.all_triangles());
  EXPECT_EQ(set.triangle_end(0), set.triangle(0));
  set.add_moving_mesh(m, Transform(), translate({0, 0, 1}), 0);
  EXPECT_TRUE(set.has_motion());
  EXPECT_TRUE(set.moving(1));
  EXPECT_FALSE(set.all_triangles());  // accelerators must not copy static vertices
  EXPECT_EQ(set.kind(1), PrimKind::kTriangle);
  EXPECT_EQ(set.triangle(1)[0], Vec3(0, 0, 0));
  EXPECT_EQ(set.triangle_end(1)[0], Vec3(0, 0, 1));
  // A later static triangle still reads its own vertices (the moving one took two slots).
  set.add_mesh(m, translate({5, 0, 0}), 0);
  EXPECT_FALSE(set.moving(2));
  EXPECT_EQ(set.triangle(2)[1], Vec3(6, 0, 0));
  const SphereData s{{1, 1, 1}, 2};
  set.add_moving_sphere(s, s, 0);
  EXPECT_FALSE(set.moving(3));
  EXPECT_EQ(set.moving_count(), 1u);
}

// A non-finite end makes the primitive invalid (empty bounds), like a non-finite static one.
TEST(MovingPrimitive, NonFiniteEndGivesEmptyBounds) {
  PrimitiveSet set;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  set.add_moving_sphere({{0, 0, 0}, 1}, {{nan, 0, 0}, 1}, 0);
  set.add_moving_quad({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, 0}, {kInfinity, 0, 0}, {0, 1, 0}},
                      0);
  EXPECT_TRUE(set.prim_bounds(0).empty());
  EXPECT_TRUE(set.prim_bounds(1).empty());
  EXPECT_TRUE(set.bounds().empty());
}

}  // namespace
}  // namespace penumbra
