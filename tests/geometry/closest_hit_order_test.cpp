// The closest hit is the least (t, primitive id) over the primitives a ray hits (hit.h,
// tie_bound): testing the same primitives in any order must give the same hit, bit for bit, so
// that a structure's traversal order (its tree, packets of rays, interleaved rays) never decides
// between two surfaces at the same distance.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <numeric>
#include <vector>

#include "penumbra/core/rng.h"
#include "penumbra/core/transform.h"
#include "penumbra/geometry/primitive_set.h"
#include "penumbra/geometry/sphere_direction.h"
#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {
namespace {

Vec3 random_point(Pcg32& rng) {
  return {rng.next_float(), rng.next_float(), rng.next_float()};
}

/// One float up or down from `v`, or `v`, by `k` (0, 1, 2).
float nudge(float v, uint32_t k) {
  return k == 0 ? v : (k == 1 ? next_float_up(v) : next_float_down(v));
}

/// Near-coincident surfaces: triangles with several copies each (the same vertices, the
/// vertices rotated, one vertex moved by an ulp), spheres and parallelograms with exact copies
/// and copies an ulp larger. The copies' ids are interleaved with the originals' (added in a
/// shuffled order), so that a higher id is as often first as a lower one.
PrimitiveSet coincident_surfaces(Pcg32& rng) {
  struct Item {
    int kind;  // 0 triangle, 1 sphere, 2 quad
    Vec3 a, b, c;
    float r;
  };
  std::vector<Item> items;
  for (int i = 0; i < 12; ++i) {
    const Vec3 a = random_point(rng), b = random_point(rng), c = random_point(rng);
    items.push_back({0, a, b, c, 0});
    items.push_back({0, a, b, c, 0});  // exact copy: ties at every hit
    items.push_back({0, b, c, a, 0});  // rotated: t rounds differently, by an ulp or so
    items.push_back({0, Vec3(nudge(a.x, 1 + i % 2), a.y, a.z), b, c, 0});
  }
  for (int i = 0; i < 4; ++i) {
    const Vec3 c = random_point(rng);
    const float r = 0.05f + 0.2f * rng.next_float();
    items.push_back({1, c, {}, {}, r});
    items.push_back({1, c, {}, {}, r});
    items.push_back({1, c, {}, {}, next_float_up(r)});
  }
  for (int i = 0; i < 4; ++i) {
    const Vec3 p = random_point(rng), e1 = random_point(rng) - Vec3(0.5f),
               e2 = random_point(rng) - Vec3(0.5f);
    items.push_back({2, p, e1, e2, 0});
    items.push_back({2, p, e1, e2, 0});
  }
  for (size_t i = items.size(); i > 1; --i) std::swap(items[i - 1], items[rng.next_bounded(i)]);
  PrimitiveSet prims;
  for (const Item& it : items) {
    if (it.kind == 0) {
      TriangleMesh m;
      m.positions = {it.a, it.b, it.c};
      m.indices = {0, 1, 2};
      prims.add_mesh(m, Transform(), 0);
    } else if (it.kind == 1) {
      prims.add_sphere({it.a, it.r}, 0);
    } else {
      prims.add_quad({it.a, it.b, it.c}, 0);
    }
  }
  return prims;
}

/// The definition: every primitive tested alone, the least (t, id) kept.
Hit least_hit(const PrimitiveSet& prims, const PreparedRay& pr) {
  Hit best;
  best.t = pr.ray.tmax;
  for (uint32_t id = 0; id < prims.size(); ++id) {
    Hit h;
    h.t = pr.ray.tmax;
    if (!prims.intersect(id, pr, h)) continue;
    if (!best.valid() || h.t < best.t || (h.t == best.t && id < best.prim)) best = h;
  }
  return best;
}

void expect_same(const Hit& got, const Hit& want, int it) {
  ASSERT_EQ(got.prim, want.prim) << "ray " << it;
  EXPECT_EQ(std::bit_cast<uint32_t>(got.t), std::bit_cast<uint32_t>(want.t)) << "ray " << it;
  EXPECT_EQ(std::bit_cast<uint32_t>(got.u), std::bit_cast<uint32_t>(want.u)) << "ray " << it;
  EXPECT_EQ(std::bit_cast<uint32_t>(got.v), std::bit_cast<uint32_t>(want.v)) << "ray " << it;
}

TEST(ClosestHitOrder, TheLeastTAndIdWhateverTheOrderOfTests) {
  // Rays from random points aimed at a point of a random primitive, tested in increasing,
  // decreasing and shuffled id order: the same hit, the least (t, id). Exact ties (copies) must
  // come out as the lower id in each order.
  Pcg32 rng(2026, 12);
  int ties = 0, near_ties = 0;
  for (int scene = 0; scene < 40; ++scene) {
    const PrimitiveSet prims = coincident_surfaces(rng);
    std::vector<uint32_t> order(prims.size());
    std::iota(order.begin(), order.end(), 0u);
    for (int r = 0; r < 500; ++r) {
      const int it = scene * 1000 + r;
      const Bounds3 b = prims.prim_bounds(rng.next_bounded(uint32_t(prims.size())));
      const Vec3 w = random_point(rng);
      const Vec3 target = b.lo + (b.hi - b.lo) * w;
      Ray ray{random_point(rng) * 3.0f - Vec3(1.0f), {}};
      ray.d = target - ray.o;
      if (r % 5 == 0) ray.tmax = 0.5f + rng.next_float();
      const PreparedRay pr(ray);
      const Hit want = least_hit(prims, pr);
      for (int pass = 0; pass < 3; ++pass) {
        if (pass == 1) std::reverse(order.begin(), order.end());
        if (pass == 2)
          for (size_t i = order.size(); i > 1; --i)
            std::swap(order[i - 1], order[rng.next_bounded(uint32_t(i))]);
        Hit got;
        got.t = ray.tmax;
        bool any = false;
        for (uint32_t id : order) any |= prims.intersect(id, pr, got);
        EXPECT_EQ(any, want.valid()) << "ray " << it;
        expect_same(got, want, it);
      }
      if (!want.valid()) continue;
      // Count the cases that decide: another primitive at the same t, or within a few ulps.
      bool tie = false, near = false;
      for (uint32_t id = 0; id < prims.size(); ++id) {
        Hit h;
        h.t = ray.tmax;
        if (id == want.prim || !prims.intersect(id, pr, h)) continue;
        tie |= h.t == want.t;
        near |= h.t != want.t && std::fabs(h.t - want.t) <= 4e-7f * want.t;
      }
      ties += tie, near_ties += near;
    }
  }
  EXPECT_GT(ties, 2000);
  EXPECT_GT(near_ties, 500);
}

TEST(ClosestHitOrder, ATieGoesToTheLowerIdAndNeverPastTmax) {
  PrimitiveSet prims;
  TriangleMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  prims.add_mesh(m, Transform(), 0);
  prims.add_mesh(m, Transform(), 0);
  const PreparedRay pr(Ray{{0, 0, 2}, {0, 0, -1}});
  Hit hit;
  EXPECT_TRUE(prims.intersect(1, pr, hit));
  EXPECT_EQ(hit.prim, 1u);
  EXPECT_TRUE(prims.intersect(0, pr, hit));  // the same t, a lower id
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_EQ(hit.t, 2.0f);
  EXPECT_FALSE(prims.intersect(1, pr, hit));  // the same t, a higher id
  EXPECT_EQ(hit.prim, 0u);
  // A hit exactly at the ray's tmax is outside its open interval, whatever the id.
  Ray ends{{0, 0, 2}, {0, 0, -1}};
  ends.tmax = 2.0f;
  Hit none;
  none.t = ends.tmax;
  EXPECT_FALSE(prims.intersect(0, PreparedRay(ends), none));
  EXPECT_FALSE(prims.occludes(0, PreparedRay(ends)));
  EXPECT_EQ(tie_bound(none, 0), 2.0f);
  EXPECT_EQ(tie_bound(hit, 0), 2.0f);  // not below its own id
  Hit other = hit;
  other.prim = 5;
  EXPECT_EQ(tie_bound(other, 3), next_float_up(2.0f));
}

}  // namespace
}  // namespace penumbra
