/// Analytic tests of the watertight ray-triangle test.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>

#include "penumbra/core/rng.h"
#include "penumbra/geometry/sphere_direction.h"
#include "penumbra/geometry/triangle.h"

namespace penumbra {
namespace {

struct TriHit {
  bool hit = false;
  float t = 0, u = 0, v = 0;
};

TriHit trace(Vec3 o, Vec3 d, Vec3 a, Vec3 b, Vec3 c, float tmin = 0.0f, float tmax = kInfinity) {
  const PreparedRay pr(Ray{o, d});
  TriHit h;
  h.hit = intersect_triangle(pr, a, b, c, tmin, tmax, h.t, h.u, h.v);
  return h;
}

Vec3 random_dir(Pcg32& rng) {
  return sample_uniform_sphere({rng.next_float(), rng.next_float()});
}

TEST(Triangle, InteriorHitGivesDistanceAndBarycentrics) {
  const TriHit h = trace({0.25f, 0.5f, 2.0f}, {0, 0, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  ASSERT_TRUE(h.hit);
  EXPECT_FLOAT_EQ(h.t, 2.0f);
  EXPECT_FLOAT_EQ(h.u, 0.25f);  // weight of vertex b
  EXPECT_FLOAT_EQ(h.v, 0.5f);   // weight of vertex c
}

TEST(Triangle, BothSidesAreHit) {
  EXPECT_TRUE(trace({0.2f, 0.2f, -1.0f}, {0, 0, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}).hit);
  EXPECT_TRUE(trace({0.2f, 0.2f, 1.0f}, {0, 0, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}).hit);
}

TEST(Triangle, OpenIntervalIsRespected) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, o{0.2f, 0.2f, 1.0f}, d{0, 0, -1};
  EXPECT_FALSE(trace(o, d, a, b, c, 0.0f, 1.0f).hit);  // t = 1 is not inside (0, 1)
  EXPECT_TRUE(trace(o, d, a, b, c, 0.0f, 1.0001f).hit);
  EXPECT_FALSE(trace(o, d, a, b, c, 1.0f, 5.0f).hit);
  EXPECT_FALSE(trace(o, -d, a, b, c).hit);  // behind the origin
}

TEST(Triangle, RayThroughSharedEdgeHitsAtLeastOne) {
  // Two triangles sharing the edge (p, q), in general position.
  Pcg32 rng(7, 1);
  int misses = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 p{rng.next_float(), rng.next_float(), rng.next_float()};
    const Vec3 q = p + random_dir(rng);
    const Vec3 r1 = p + random_dir(rng), r2 = p + random_dir(rng);
    const float s = rng.next_float();
    const Vec3 on_edge = p + (q - p) * s;  // rounded, so just on one side or exactly on it
    const Vec3 d = random_dir(rng);
    const Vec3 o = on_edge - d * 3.0f;
    const bool h1 = trace(o, d, p, q, r1).hit, h2 = trace(o, d, q, p, r2).hit;
    // Only when the two triangles lie on opposite sides of the edge as seen along d does their
    // union cover the edge's neighbourhood; check that configuration.
    const Vec3 n1 = cross(q - p, r1 - p), n2 = cross(p - q, r2 - q);
    const Vec3 side = cross(q - p, d);
    const bool opposite = dot(side, r1 - p) * dot(side, r2 - p) < 0.0f;
    if (opposite && dot(n1, n1) > 1e-6f && dot(n2, n2) > 1e-6f && !h1 && !h2) ++misses;
  }
  EXPECT_EQ(misses, 0);
}

TEST(Triangle, RaysThroughAFanVertexHitAtLeastOne) {
  // Six triangles around a shared vertex c, tilted out of plane; rays aimed exactly at c.
  Pcg32 rng(8, 2);
  int misses = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const Vec3 c{rng.next_float(), rng.next_float(), rng.next_float()};
    Vec3 ring[6];
    for (int k = 0; k < 6; ++k) {
      const float a = 2.0f * std::numbers::pi_v<float> * float(k) / 6.0f;
      ring[k] = c + Vec3(std::cos(a), std::sin(a), 0.3f * (rng.next_float() - 0.5f));
    }
    const Vec3 d =
        normalize(Vec3(0.3f * (rng.next_float() - 0.5f), 0.3f * (rng.next_float() - 0.5f), -1.0f));
    const Vec3 o = c - d * 2.0f;
    bool any = false;
    for (int k = 0; k < 6; ++k) any = any || trace(o, d, c, ring[k], ring[(k + 1) % 6]).hit;
    misses += !any;
  }
  EXPECT_EQ(misses, 0);
}

TEST(Triangle, GridOfSharedEdgesHasNoGaps) {
  // A 16x16 grid of unit squares split into triangles; rays through exact grid lines and vertices.
  int misses = 0;
  for (int i = 1; i < 16; ++i)
    for (int j = 1; j < 16; ++j)
      for (const Vec3 target : {Vec3(float(i), float(j), 0), Vec3(i + 0.5f, float(j), 0),
                                Vec3(float(i), j + 0.25f, 0), Vec3(i + 0.5f, j + 0.5f, 0)}) {
        const Vec3 d = normalize(Vec3(0.37f, -0.21f, -1.0f));
        const Vec3 o = target - d * 5.0f;
        bool any = false;
        for (int y = 0; y < 16; ++y)
          for (int x = 0; x < 16; ++x) {
            const Vec3 a(float(x), float(y), 0), b(x + 1.0f, float(y), 0), c(x + 1.0f, y + 1.0f, 0),
                e(float(x), y + 1.0f, 0);
            any = any || trace(o, d, a, b, c).hit || trace(o, d, a, c, e).hit;
          }
        misses += !any;
      }
  EXPECT_EQ(misses, 0);
}

TEST(Triangle, RaysInThePlaneOrParallelMiss) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_FALSE(trace({-1, 0.2f, 0}, {1, 0, 0}, a, b, c).hit);  // in the plane, through it
  EXPECT_FALSE(trace({-1, -1, 0}, normalize(Vec3(1, 1, 0)), a, b, c).hit);
  EXPECT_FALSE(trace({-1, 0.2f, 0.5f}, {1, 0, 0}, a, b, c).hit);  // parallel, above
}

TEST(Triangle, AxisAlignedSharedEdgeAndVertexAreHit) {
  // Triangles (a, b, c) and (b, a, e) share the edge a-b on the x axis.
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, e{0.5f, -1, 0}, d{0, 0, -1};
  for (float x : {0.0f, 0.25f, 0.5f, 1.0f}) {
    const Vec3 o{x, 0.0f, 1.0f};
    const TriHit h1 = trace(o, d, a, b, c), h2 = trace(o, d, b, a, e);
    EXPECT_TRUE(h1.hit || h2.hit) << x;
    if (h1.hit) {
      EXPECT_FLOAT_EQ(h1.t, 1.0f);
    }
  }
  const TriHit corner = trace({1.0f, 0.0f, 1.0f}, d, a, b, c);
  ASSERT_TRUE(corner.hit);
  EXPECT_FLOAT_EQ(corner.u, 1.0f);
  EXPECT_FLOAT_EQ(corner.v, 0.0f);
}

TEST(Triangle, DegenerateAndNonFiniteTrianglesAreNeverHit) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Pcg32 rng(9, 3);
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 a{rng.next_float(), rng.next_float(), rng.next_float()};
    const Vec3 b = a + random_dir(rng);
    const Vec3 d = random_dir(rng), o = a - d * 2.0f;  // aimed at a
    EXPECT_FALSE(trace(o, d, a, a, b).hit);
    EXPECT_FALSE(trace(o, d, a, b, a + (b - a) * 3.0f).hit);  // collinear
    EXPECT_FALSE(trace(o, d, a, a, a).hit);
    EXPECT_FALSE(trace(o, d, a, b, {nan, 0, 0}).hit);
    EXPECT_FALSE(trace(o, d, {nan, nan, nan}, b, b + d).hit);
    EXPECT_FALSE(trace(o, d, a, b, {kInfinity, 0, 0}).hit);
  }
}

// Two identical vertices make the determinant exactly zero (repeated_vertex's argument), so no
// ray hits such a triangle, whichever two vertices they are, not even a ray through the segment
// it spans, at any scale; the structures leave these triangles out on that ground. +0 and -0 are
// different bits, so they do not make a vertex repeated.
TEST(Triangle, RepeatedVertexTrianglesAreNeverHit) {
  Pcg32 rng(11, 5);
  int through_segment = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const float scale = std::ldexp(1.0f, int(rng.next_bounded(41)) - 20);
    const Vec3 p = Vec3{rng.next_float(), rng.next_float(), rng.next_float()} * scale;
    const Vec3 q = p + random_dir(rng) * scale;
    const Vec3 target = p + (q - p) * rng.next_float();
    const Vec3 d = random_dir(rng), o = target - d * (3.0f * scale);
    const Vec3 tris[3][3] = {{p, p, q}, {q, p, p}, {p, q, p}};
    for (const auto& v : tris) {
      EXPECT_TRUE(repeated_vertex(v[0], v[1], v[2]));
      EXPECT_FALSE(trace(o, d, v[0], v[1], v[2]).hit) << trial;
    }
    // The same ray hits a proper triangle with that segment as an edge about half the time.
    through_segment += trace(o, d, p, q, p + cross(q - p, d) * 2.0f).hit;
  }
  EXPECT_GT(through_segment, 5000);  // the rays do pass where the segment is
  EXPECT_FALSE(repeated_vertex({0, 0, 1}, {1, 0, 0}, {0, 1, 0}));
  EXPECT_FALSE(repeated_vertex({0.0f, 1, 2}, {-0.0f, 1, 2}, {3, 4, 5}));
  EXPECT_TRUE(repeated_vertex({-0.0f, 1, 2}, {3, 4, 5}, {-0.0f, 1, 2}));
}

// The watertight test's permutation and shear (PreparedRay's selects; a branchless rewrite was
// tried and measured no faster, docs/accel.md) against the rule as written in the paper (kz the
// axis of largest |d|, ties resolved as max_dimension resolves them; x and y the next two axes
// cyclically, swapped when d[kz] < 0): every direction with components in
// {-2, -1, -0, 0, 1, 2} (ties of every kind, both zeros) and a million random ones.
TEST(PreparedRayTest, PermutationAndShearMatchTheRuleOnEveryTieAndSign) {
  const auto check = [](Vec3 d) {
    const PreparedRay pr(Ray{{0, 0, 0}, d});
    const Vec3 ad = abs(d);
    const int kz = max_dimension(ad);
    int kx = kz + 1 == 3 ? 0 : kz + 1, ky = kx + 1 == 3 ? 0 : kx + 1;
    if (std::signbit(d[kz])) std::swap(kx, ky);
    ASSERT_EQ(pr.kz, kz) << d.x << " " << d.y << " " << d.z;
    ASSERT_EQ(pr.kx, kx) << d.x << " " << d.y << " " << d.z;
    ASSERT_EQ(pr.ky, ky) << d.x << " " << d.y << " " << d.z;
    const float sz = 1.0f / d[kz];
    EXPECT_EQ(std::bit_cast<uint32_t>(pr.sz), std::bit_cast<uint32_t>(sz));
    EXPECT_EQ(std::bit_cast<uint32_t>(pr.sx), std::bit_cast<uint32_t>(d[kx] * sz));
    EXPECT_EQ(std::bit_cast<uint32_t>(pr.sy), std::bit_cast<uint32_t>(d[ky] * sz));
  };
  const float values[] = {-2.0f, -1.0f, -0.0f, 0.0f, 1.0f, 2.0f};
  for (float x : values)
    for (float y : values)
      for (float z : values)
        if (x != 0.0f || y != 0.0f || z != 0.0f) check({x, y, z});
  Pcg32 rng(7);
  for (int i = 0; i < 1000000; ++i)
    check({2 * rng.next_float() - 1, 2 * rng.next_float() - 1, 2 * rng.next_float() - 1});
}

}  // namespace
}  // namespace penumbra
