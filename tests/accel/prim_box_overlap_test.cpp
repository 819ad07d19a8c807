/// Tests of the primitive-box overlap tests against brute references: polygon clipping in double
/// (Sutherland & Hodgman 1974, "Reentrant Polygon Clipping") for triangles and parallelograms,
/// surface sampling for spheres; and the special cases the subdivisions rely on (touching,
/// lying in a face plane, missing by more than the pad).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "penumbra/accel/build/prim_box_overlap.h"
#include "penumbra/core/rng.h"

namespace penumbra::test {
namespace {

using P3 = std::array<double, 3>;

/// True when the convex polygon `poly` meets the closed box [lo, hi]: clip by the six planes.
bool clip_overlaps(std::vector<P3> poly, const P3& lo, const P3& hi) {
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      // Keep points with sign * (x - plane) <= 0: x >= lo (side 0) or x <= hi (side 1).
      const double plane = side ? hi[axis] : lo[axis], sign = side ? 1.0 : -1.0;
      std::vector<P3> out;
      const size_t n = poly.size();
      for (size_t i = 0; i < n; ++i) {
        const P3& a = poly[i];
        const P3& b = poly[(i + 1) % n];
        const double da = sign * (a[axis] - plane), db = sign * (b[axis] - plane);
        if (da <= 0) out.push_back(a);
        if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
          const double t = da / (da - db);
          P3 p;
          for (int k = 0; k < 3; ++k) p[k] = a[k] + t * (b[k] - a[k]);
          p[axis] = plane;  // exactly on the plane
          out.push_back(p);
        }
      }
      poly = std::move(out);
      if (poly.empty()) return false;
    }
  }
  return true;
}

P3 p3(Vec3 v) {
  return {v.x, v.y, v.z};
}

/// The box grown by `k` times the documented pad on each side.
std::pair<P3, P3> grown(const Bounds3& b, double k) {
  P3 lo, hi;
  for (int a = 0; a < 3; ++a) {
    const double pad = k * kOverlapPad * (std::fabs(double(b.lo[a])) + std::fabs(double(b.hi[a])));
    lo[a] = b.lo[a] - pad;
    hi[a] = b.hi[a] + pad;
  }
  return {lo, hi};
}

bool ref_triangle(Vec3 a, Vec3 b, Vec3 c, const Bounds3& box, double pad_factor) {
  const auto [lo, hi] = grown(box, pad_factor);
  return clip_overlaps({p3(a), p3(b), p3(c)}, lo, hi);
}

Vec3 rnd(Pcg32& rng, float lo, float hi) {
  return {lo + (hi - lo) * rng.next_float(), lo + (hi - lo) * rng.next_float(),
          lo + (hi - lo) * rng.next_float()};
}

TEST(PrimBoxOverlap, TriangleAgreesWithClippingOnRandomCases) {
  Pcg32 rng(3, 1);
  int overlaps = 0;
  for (int i = 0; i < 200'000; ++i) {
    const Bounds3 box(rnd(rng, -1, 1), rnd(rng, -1, 1));
    // Sizes from tiny to large, so all thirteen axes get to separate.
    const float s = std::pow(10.0f, -2.0f + 3.0f * rng.next_float());
    const Vec3 c = rnd(rng, -1.5f, 1.5f);
    const Vec3 a = c + rnd(rng, -s, s), b = c + rnd(rng, -s, s), d = c + rnd(rng, -s, s);
    const bool got = triangle_box_overlap(a, b, d, box);
    // No false negative against the exact closed box; no positive beyond the pad.
    if (ref_triangle(a, b, d, box, 0.0)) {
      EXPECT_TRUE(got) << i;
    }
    if (got) {
      EXPECT_TRUE(ref_triangle(a, b, d, box, 2.0)) << i;
    }
    overlaps += got;
  }
  EXPECT_GT(overlaps, 5'000);  // both outcomes are well represented
  EXPECT_LT(overlaps, 180'000);
}

TEST(PrimBoxOverlap, TriangleInOrTouchingAFacePlaneOverlaps) {
  const Bounds3 box({0, 0, 0}, {1, 1, 1});
  // Lying in the face planes z = 1 and x = 0, inside the face and partly outside it.
  EXPECT_TRUE(triangle_box_overlap({0.2f, 0.2f, 1}, {0.8f, 0.2f, 1}, {0.5f, 0.9f, 1}, box));
  EXPECT_TRUE(triangle_box_overlap({0, -1, -1}, {0, 3, -1}, {0, 0.5f, 3}, box));
  // Touching the box at one edge from outside, and at a corner.
  EXPECT_TRUE(triangle_box_overlap({1, 0, 0}, {1, 1, 0}, {2, 0.5f, -1}, box));
  EXPECT_TRUE(triangle_box_overlap({1, 1, 1}, {2, 1, 3}, {3, 2, 1}, box));
  // A face-plane triangle of a grid cell: shared by both cells.
  const Bounds3 left({0, 0, 0}, {0.5f, 1, 1}), right({0.5f, 0, 0}, {1, 1, 1});
  for (const Bounds3& b : {left, right})
    EXPECT_TRUE(
        triangle_box_overlap({0.5f, 0.1f, 0.1f}, {0.5f, 0.9f, 0.1f}, {0.5f, 0.5f, 0.9f}, b));
  // Degenerate triangles: a segment through the box, a point on its face.
  EXPECT_TRUE(triangle_box_overlap({-1, 0.5f, 0.5f}, {2, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, box));
  EXPECT_TRUE(triangle_box_overlap({1, 0.3f, 0.3f}, {1, 0.3f, 0.3f}, {1, 0.3f, 0.3f}, box));
}

TEST(PrimBoxOverlap, TriangleMissingByMoreThanThePadIsSeparated) {
  const Bounds3 box({0, 0, 0}, {1, 1, 1});
  // Beyond a face plane by 1e-4 (the pad here is about 2e-6).
  EXPECT_FALSE(
      triangle_box_overlap({0.2f, 0.2f, 1.0001f}, {0.8f, 0.2f, 1.0001f}, {0.5f, 0.9f, 1.2f}, box));
  // Its bounding box overlaps the box, but the triangle passes beside the corner: an edge-cross
  // axis separates (first), the triangle's plane (second).
  EXPECT_FALSE(triangle_box_overlap({2.1f, 0, 0.5f}, {0, 2.1f, 0.5f}, {2.1f, 2.1f, 0.5f}, box));
  EXPECT_FALSE(triangle_box_overlap({2, 0, 0}, {0, 2, 0}, {0, 0, 2},
                                    Bounds3({0.7f, 0.7f, 0.7f}, {1, 1, 1})));
  EXPECT_FALSE(triangle_box_overlap({-1, 0.5f, 2}, {2, 0.5f, 2}, {2, 0.5f, 1.01f}, box));
  // A degenerate triangle (a segment) passing the box diagonally near a corner.
  EXPECT_FALSE(triangle_box_overlap({2.1f, 0, 0.5f}, {0, 2.1f, 0.5f}, {1.05f, 1.05f, 0.5f}, box));
}

TEST(PrimBoxOverlap, SphereAgreesWithSurfaceSampling) {
  Pcg32 rng(5, 2);
  for (int i = 0; i < 3000; ++i) {
    const Bounds3 box(rnd(rng, -1, 1), rnd(rng, -1, 1));
    const Vec3 c = rnd(rng, -1.5f, 1.5f);
    const float r = 0.05f + rng.next_float();
    const bool got = sphere_box_overlap(c, r, box);
    // Any surface sample inside the box proves an overlap.
    bool sampled = false;
    for (int k = 0; k < 400 && !sampled; ++k) {
      const float z = 1.0f - 2.0f * rng.next_float(), phi = 6.2831853f * rng.next_float();
      const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
      sampled = box.contains(c + Vec3(s * std::cos(phi), s * std::sin(phi), z) * r);
    }
    if (sampled) {
      EXPECT_TRUE(got) << i;
    }
  }
  const Bounds3 box({0, 0, 0}, {1, 1, 1});
  EXPECT_TRUE(sphere_box_overlap({2, 0.5f, 0.5f}, 1.0f, box));       // touches the face x = 1
  EXPECT_TRUE(sphere_box_overlap({2, 2, 2}, std::sqrt(3.0f), box));  // touches the corner
  EXPECT_FALSE(sphere_box_overlap({2, 2, 2}, 1.7f, box));            // just short of it
  EXPECT_FALSE(sphere_box_overlap({0.5f, 0.5f, 0.5f}, 5.0f, box));   // box inside the sphere
  EXPECT_TRUE(sphere_box_overlap({0.5f, 0.5f, 0.5f}, 0.1f, box));    // sphere inside the box
}

TEST(PrimBoxOverlap, QuadAgreesWithClipping) {
  Pcg32 rng(9, 3);
  for (int i = 0; i < 50'000; ++i) {
    const Bounds3 box(rnd(rng, -1, 1), rnd(rng, -1, 1));
    const Vec3 p = rnd(rng, -1.5f, 1.5f), e1 = rnd(rng, -1, 1), e2 = rnd(rng, -1, 1);
    const bool got = quad_box_overlap(p, e1, e2, box);
    const P3 a = p3(p), b = p3(p + e1), c = p3(p + e1 + e2), d = p3(p + e2);
    const auto [lo0, hi0] = grown(box, 0.0);
    const auto [lo2, hi2] = grown(box, 2.0);
    if (clip_overlaps({a, b, c, d}, lo0, hi0)) {
      EXPECT_TRUE(got) << i;
    }
    if (got) {
      EXPECT_TRUE(clip_overlaps({a, b, c, d}, lo2, hi2)) << i;
    }
  }
  // Touching the box only with the far corner p + e1 + e2.
  EXPECT_TRUE(
      quad_box_overlap({-1, -1, 0.5f}, {1, 0, 0}, {0, 1, 0}, Bounds3({0, 0, 0}, {1, 1, 1})));
}

TEST(PrimBoxOverlap, BoxShortcutsAgreeWithTheExactTest) {
  // The variant taking the primitive's box answers from boxes when it can; it must agree with
  // the exact test (both are conservative by the same pad).
  PrimitiveSet prims;
  Pcg32 rng(11, 4);
  TriangleMesh m;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 c = rnd(rng, -1, 1);
    const float s = 0.02f + rng.next_float();
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(c + rnd(rng, -s, s));
      m.indices.push_back(uint32_t(m.positions.size() - 1));
    }
  }
  prims.add_mesh(m, Transform(), 0);
  for (int i = 0; i < 300; ++i)
    prims.add_sphere({rnd(rng, -1, 1), 0.01f + 0.5f * rng.next_float()}, 1);
  for (int i = 0; i < 300; ++i)
    prims.add_quad({rnd(rng, -1, 1), rnd(rng, -0.5f, 0.5f), rnd(rng, -0.5f, 0.5f)}, 2);
  for (uint32_t id = 0; id < prims.size(); ++id) {
    for (int k = 0; k < 10; ++k) {
      const Vec3 lo = rnd(rng, -1, 1);
      const Bounds3 box(lo, lo + rnd(rng, 0.01f, 0.6f));
      EXPECT_EQ(prim_box_overlap(prims, id, prims.prim_bounds(id), box),
                prim_box_overlap(prims, id, box))
          << id;
    }
  }
}

}  // namespace
}  // namespace penumbra::test
