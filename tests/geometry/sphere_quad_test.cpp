/// Analytic tests of the ray-sphere and ray-parallelogram tests and of PrimitiveSet dispatch.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "penumbra/geometry/primitive_set.h"
#include "penumbra/geometry/quad.h"
#include "penumbra/geometry/sphere.h"

namespace penumbra {
namespace {

bool sphere_t(Vec3 o, Vec3 d, Vec3 c, float r, float& t, float tmin = 0.0f,
              float tmax = kInfinity) {
  return intersect_sphere(Ray{o, d}, c, r, tmin, tmax, t);
}

TEST(Sphere, FromOutsideHitsTheNearSide) {
  float t;
  ASSERT_TRUE(sphere_t({0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f, t));
  EXPECT_FLOAT_EQ(t, 4.0f);
  ASSERT_TRUE(sphere_t({0, 0, -5}, {0, 0, 2}, {0, 0, 0}, 1.0f, t));  // unnormalised direction
  EXPECT_FLOAT_EQ(t, 2.0f);
  EXPECT_FALSE(sphere_t({0, 0, -5}, {0, 0, -1}, {0, 0, 0}, 1.0f, t));  // pointing away
}

TEST(Sphere, FromInsideHitsTheFarSide) {
  float t;
  ASSERT_TRUE(sphere_t({0, 0, 0.5f}, {0, 0, 1}, {0, 0, 0}, 1.0f, t));
  EXPECT_FLOAT_EQ(t, 0.5f);
  ASSERT_TRUE(sphere_t({0, 0, 0.5f}, {0, 0, -1}, {0, 0, 0}, 1.0f, t));
  EXPECT_FLOAT_EQ(t, 1.5f);
}

TEST(Sphere, NearTangentRaysHitInsideAndMissOutside) {
  float t;
  for (float r : {1.0f, 1e-3f, 1e3f}) {
    EXPECT_TRUE(sphere_t({r * 0.9999f, 0, -5 * r}, {0, 0, 1}, {0, 0, 0}, r, t)) << r;
    EXPECT_NEAR(t, 5 * r, 0.02f * r) << r;
    EXPECT_FALSE(sphere_t({r * 1.0001f, 0, -5 * r}, {0, 0, 1}, {0, 0, 0}, r, t)) << r;
  }
}

TEST(Sphere, DistantSmallSphereIsAccurate) {
  // Far from the origin the textbook discriminant loses the sphere; Haines et al.'s form does not.
  float t;
  ASSERT_TRUE(sphere_t({0, 0, 0}, {0, 0, 1}, {0.5f, 0, 1e5f}, 1.0f, t));
  EXPECT_NEAR(t, 1e5f - std::sqrt(0.75f), 0.02f);
}

TEST(Sphere, IntervalIsRespected) {
  float t;
  EXPECT_FALSE(sphere_t({0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f, t, 0.0f, 4.0f));
  ASSERT_TRUE(sphere_t({0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f, t, 4.5f, 10.0f));
  EXPECT_FLOAT_EQ(t, 6.0f);  // the far side once the near one is excluded
}

bool quad_hit(Vec3 o, Vec3 d, const QuadData& q, float& t, float& u, float& v) {
  return intersect_quad(Ray{o, d}, q.p, q.e1, q.e2, 0.0f, kInfinity, t, u, v);
}

TEST(Quad, CornersAndEdgesAreInside) {
  const QuadData q{{0, 0, 0}, {2, 0, 0}, {0, 3, 0}};
  float t, u, v;
  for (const Vec3 p : {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0), Vec3(2, 3, 0), Vec3(1, 0, 0),
                       Vec3(2, 1.5f, 0)}) {
    ASSERT_TRUE(quad_hit(p + Vec3(0, 0, 1), {0, 0, -1}, q, t, u, v)) << p.x << " " << p.y;
    EXPECT_FLOAT_EQ(t, 1.0f);
    EXPECT_FLOAT_EQ(u, p.x / 2.0f);
    EXPECT_FLOAT_EQ(v, p.y / 3.0f);
  }
  EXPECT_FALSE(quad_hit({2.001f, 1, 1}, {0, 0, -1}, q, t, u, v));
  EXPECT_FALSE(quad_hit({1, -0.001f, 1}, {0, 0, -1}, q, t, u, v));
}

TEST(Quad, ParallelAndDegenerateQuadsMiss) {
  float t, u, v;
  EXPECT_FALSE(quad_hit({-1, 1, 0}, {1, 0, 0}, {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}}, t, u, v));
  EXPECT_FALSE(quad_hit({1, 1, 1}, {0, 0, -1}, {{0, 0, 0}, {2, 0, 0}, {4, 0, 0}}, t, u, v));
  EXPECT_FALSE(quad_hit({0, 0, 1}, {0, 0, -1}, {{0, 0, 0}, {0, 0, 0}, {0, 1, 0}}, t, u, v));
}

TEST(PrimitiveSet, IntersectUpdatesOnlyOnCloserHits) {
  PrimitiveSet prims;
  TriangleMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  const uint32_t tri = prims.add_mesh(m, Transform(), 0);
  const uint32_t sph = prims.add_sphere({{0, 0, 3}, 1.0f}, 1);
  const uint32_t quad = prims.add_quad({{-1, -1, 1}, {2, 0, 0}, {0, 2, 0}}, 2);
  EXPECT_EQ(prims.size(), 3u);
  EXPECT_FALSE(prims.all_triangles());
  const PreparedRay pr(Ray{{0, 0, 10}, {0, 0, -1}});
  Hit hit;
  EXPECT_TRUE(prims.intersect(tri, pr, hit));
  EXPECT_FLOAT_EQ(hit.t, 10.0f);
  EXPECT_TRUE(prims.intersect(quad, pr, hit));  // closer
  EXPECT_FLOAT_EQ(hit.t, 9.0f);
  EXPECT_EQ(hit.prim, quad);
  EXPECT_TRUE(prims.intersect(sph, pr, hit));
  EXPECT_FLOAT_EQ(hit.t, 6.0f);
  EXPECT_EQ(hit.prim, sph);
  EXPECT_FALSE(prims.intersect(tri, pr, hit));  // farther than the current hit
  EXPECT_FALSE(prims.intersect(quad, pr, hit));
  EXPECT_EQ(hit.prim, sph);
  EXPECT_TRUE(prims.occludes(sph, pr));
}

TEST(PrimitiveSet, NonFinitePrimitivesHaveEmptyBounds) {
  PrimitiveSet prims;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, nan, 0}, {kInfinity, 0, 0}};
  m.indices = {0, 1, 2, 0, 1, 3, 0, 4, 2};
  prims.add_mesh(m, Transform(), 0);
  prims.add_sphere({{0, 0, nan}, 1.0f}, 1);
  prims.add_sphere({{0, 0, 0}, kInfinity}, 1);
  prims.add_quad({{0, 0, 0}, {nan, 0, 0}, {0, 1, 0}}, 2);
  EXPECT_FALSE(prims.prim_bounds(0).empty());
  for (uint32_t id = 1; id < prims.size(); ++id) EXPECT_TRUE(prims.prim_bounds(id).empty()) << id;
  EXPECT_EQ(prims.bounds(), Bounds3({0, 0, 0}, {1, 1, 0}));
}

}  // namespace
}  // namespace penumbra
