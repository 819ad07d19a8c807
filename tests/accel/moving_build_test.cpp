/// The builders' handling of moving primitives: swept boxes in the exact overlap and clipping
/// tests, and the BSP's objects (closest hits are checked against brute force in
/// differential_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "penumbra/accel/build/bsp_builder.h"
#include "penumbra/accel/build/kd_clip.h"
#include "penumbra/accel/build/prim_box_overlap.h"
#include "penumbra/core/rng.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

/// A triangle in the plane z = 0 near the origin moving by (4, 0, 0), a sphere moving by
/// (0, 4, 0) and a parallelogram moving by (0, 0, 4).
PrimitiveSet three_movers() {
  PrimitiveSet set;
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2};
  set.add_moving_mesh(m, Transform(), translate({4, 0, 0}), 0);
  set.add_moving_sphere({{0, 0, 0}, 0.5f}, {{0, 4, 0}, 0.5f}, 0);
  set.add_moving_quad({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, 4}, {1, 0, 0}, {0, 1, 0}}, 0);
  return set;
}

// A box that neither end touches but the motion crosses holds the primitive; a box beside the
// swept box does not.
TEST(MovingBuild, OverlapTestsUseTheSweptBox) {
  const PrimitiveSet set = three_movers();
  const Bounds3 mid_x({2.2f, 0.1f, -0.1f}, {2.4f, 0.2f, 0.1f});   // the triangle passes at t ~ 0.5
  const Bounds3 mid_y({-0.1f, 1.9f, -0.1f}, {0.1f, 2.1f, 0.1f});  // inside the sphere's path
  const Bounds3 mid_z({0.4f, 0.4f, 1.9f}, {0.6f, 0.6f, 2.1f});
  EXPECT_TRUE(prim_box_overlap(set, 0, mid_x));
  EXPECT_TRUE(prim_box_overlap(set, 0, set.prim_bounds(0), mid_x));
  EXPECT_TRUE(prim_box_overlap(set, 1, mid_y));
  EXPECT_TRUE(prim_box_overlap(set, 2, mid_z));
  const Bounds3 beside({2.2f, 1.5f, -0.1f}, {2.4f, 1.6f, 0.1f});  // above the triangle's sweep
  EXPECT_FALSE(prim_box_overlap(set, 0, beside));
  EXPECT_FALSE(prim_box_overlap(set, 2, Bounds3({0.4f, 0.4f, 4.5f}, {0.6f, 0.6f, 5.0f})));
  // Clipping for the kd-tree: the swept box within the cell, not the start triangle's part.
  const Bounds3 cell({2, -1, -1}, {3, 3, 1});
  const Bounds3 clip = clip_prim_bounds(set, 0, cell);
  EXPECT_EQ(clip.lo, Vec3(2, 0, 0));
  EXPECT_EQ(clip.hi, Vec3(3, 1, 0));
  Bounds3 below, above;
  split_prim_bounds(set, 0, set.prim_bounds(0), 0, 2.5f, true, below, above);
  EXPECT_EQ(below.hi.x, 2.5f);
  EXPECT_EQ(above.lo.x, 2.5f);
  EXPECT_EQ(above.hi.x, 5.0f);
}

// Moving polygons are BSP objects, sent to every side they reach at some time, and a set of
// moving triangles is split by their mid-motion planes instead of staying one brute-force leaf.
TEST(MovingBuild, BspSplitsMovingMeshesIntoSmallLeaves) {
  // 1000 small random triangles, every one moving: no fragment at all to split by.
  PrimitiveSet set;
  Pcg32 rng(5, 5);
  for (int i = 0; i < 1000; ++i) {
    TriangleMesh m;
    const Vec3 c(rng.next_float(), rng.next_float(), rng.next_float());
    for (int k = 0; k < 3; ++k)
      m.positions.push_back(c + Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 0.05f);
    m.indices = {0, 1, 2};
    set.add_moving_mesh(m, Transform(), translate({0.05f * rng.next_float(), 0.02f, 0}), 0);
  }
  ASSERT_EQ(set.moving_count(), 1000u);
  const BspBuildResult r = build_bsp(set, BspBuildParams{});
  size_t largest = 0, refs = 0;
  for (const BspNode& n : r.nodes)
    if (n.is_leaf()) largest = std::max<size_t>(largest, n.count), refs += n.count;
  EXPECT_EQ(r.planar, 0u);
  EXPECT_GT(r.leaves, 50u);
  EXPECT_LT(largest, 100u) << "a leaf holds " << largest << " of 1000 primitives";
  EXPECT_GE(refs, 1000u);  // every moving triangle is in some leaf
  // The triangle moving along x straddles a plane x = 2 for part of its motion: both sides.
  PrimitiveSet one = three_movers();
  TriangleMesh wall;  // a static triangle in the plane x = 2 to split by
  wall.positions = {{2, -10, -10}, {2, 10, -10}, {2, 0, 10}};
  wall.indices = {0, 1, 2};
  one.add_mesh(wall, Transform(), 1);
  BspBuildParams p;
  p.order = BspOrder::kFirst;
  const BspBuildResult w = build_bsp(one, p);
  ASSERT_EQ(w.nodes.size(), 3u);  // the wall's node and two leaves
  for (int side = 0; side < 2; ++side) {
    const BspNode& leaf = w.nodes[w.nodes[0].child[side]];
    ASSERT_TRUE(leaf.is_leaf());
    EXPECT_TRUE(std::find(w.refs.begin() + leaf.first, w.refs.begin() + leaf.first + leaf.count,
                          0u) != w.refs.begin() + leaf.first + leaf.count)
        << "side " << side;
  }
}

}  // namespace
}  // namespace penumbra::test
