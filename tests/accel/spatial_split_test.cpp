/// Tests of spatial splits (accel/build/spatial_split.h, the default `bvh`'s SBVH build): the
/// two sides of a split cover every triangle, the binned search finds the cheapest of its planes,
/// the tree is the same at every thread count and within its budget, a height field's tree stays
/// compact, and on long triangles the tree does less work per ray than object splits alone,
/// finding the same hits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <vector>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/bvh_split.h"
#include "penumbra/accel/build/spatial_split.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/geometry/triangle_mesh.h"

#include "test_scenes.h"

namespace penumbra {
namespace {

using test::TestScene;

// Long, thin triangles across the unit cube, and little ones: the case for spatial splits.
TestScene slivers(int n, int small, uint64_t seed) {
  return test::large_triangles(n, small, seed, true);
}

TEST(SpatialSplit, TheTwoSidesCoverEveryTriangle) {
  const TestScene s = slivers(400, 400, 1);
  const PrimRefs refs = make_prim_refs(s.prims);
  const std::span<const PrimRef> all(refs.refs.data(), refs.refs.size());
  const SpatialSplit split = find_spatial_split(all, refs.bounds, 16, 0);
  ASSERT_GE(split.axis, 0);
  SpatialSides sides;
  apply_spatial_split(s.prims, all, split, sides);
  EXPECT_GT(sides.left.size() + sides.right.size(), all.size());  // slivers were split
  EXPECT_LT(sides.left.size(), all.size());
  EXPECT_LT(sides.right.size(), all.size());
  std::map<uint32_t, std::vector<Bounds3>> pieces;
  const auto check_side = [&](const std::vector<PrimRef>& side, const Bounds3& box,
                              const Bounds3& centroids) {
    Bounds3 b, c;
    for (const PrimRef& r : side) {
      pieces[r.id].push_back(r.bounds());
      b.extend(r.bounds()), c.extend(r.centroid2());
    }
    EXPECT_EQ(b.lo, box.lo);
    EXPECT_EQ(b.hi, box.hi);
    EXPECT_EQ(c.lo, centroids.lo);
    EXPECT_EQ(c.hi, centroids.hi);
  };
  check_side(sides.left, sides.left_box, sides.left_centroids);
  check_side(sides.right, sides.right_box, sides.right_centroids);
  ASSERT_EQ(pieces.size(), all.size());
  // Every vertex, every edge's midpoint and random points of each triangle lie in a piece of it;
  // a piece split off lies on its side of the plane.
  Pcg32 rng(9, 1);
  for (const auto& [id, boxes] : pieces) {
    const Vec3* v = s.prims.triangle(id);
    std::vector<Vec3> points = {
        v[0], v[1], v[2], (v[0] + v[1]) * 0.5f, (v[1] + v[2]) * 0.5f, (v[2] + v[0]) * 0.5f};
    for (int k = 0; k < 100; ++k) {
      float a = rng.next_float(), b = rng.next_float();
      if (a + b > 1) a = 1 - a, b = 1 - b;
      points.push_back(v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * b);
    }
    for (const Vec3& p : points) {
      const bool covered =
          std::any_of(boxes.begin(), boxes.end(), [&](const Bounds3& b) { return b.contains(p); });
      ASSERT_TRUE(covered) << "triangle " << id;
    }
  }
  for (const PrimRef& r : sides.left)
    if (r.hi[split.axis] > split.pos) {  // whole (unsplit): its box is the triangle's
      const PrimRef& orig = refs.refs[r.id];
      EXPECT_EQ(r.lo, orig.lo);
      EXPECT_EQ(r.hi, orig.hi);
    }
}

TEST(SpatialSplit, TheSearchFindsTheCheapestOfItsPlanes) {
  // The estimate from all references equals spatial_split_cost at the plane it returns, and no
  // other bin plane of any axis is cheaper by that cost.
  const TestScene s = slivers(300, 700, 2);
  const PrimRefs refs = make_prim_refs(s.prims);
  const std::span<const PrimRef> all(refs.refs.data(), refs.refs.size());
  const int bins = 16;
  const SpatialSplit best = find_spatial_split(all, refs.bounds, bins, 0);
  ASSERT_GE(best.axis, 0);
  const float at_best = spatial_split_cost(all, best);
  EXPECT_NEAR(best.cost, at_best, 1e-5 * at_best);
  for (int a = 0; a < 3; ++a) {
    const float lo = refs.bounds.lo[a], extent = refs.bounds.hi[a] - lo;
    for (int k = 1; k < bins; ++k) {
      SpatialSplit other;
      other.axis = a, other.pos = lo + extent * (float(k) / float(bins));
      EXPECT_GE(spatial_split_cost(all, other), at_best * (1 - 1e-5f)) << a << " " << k;
    }
  }
  // A sample estimates the same plane's cost within a few percent.
  const SpatialSplit sampled = find_spatial_split(all, refs.bounds, bins, 128);
  ASSERT_GE(sampled.axis, 0);
  EXPECT_NEAR(spatial_split_cost(all, sampled), at_best, 0.1 * at_best);
}

/// The binary tree with spatial splits, as the wide BVH builds it.
BinaryBvh spatial_tree(const PrimitiveSet& prims, float budget) {
  BvhBuildParams p;
  p.block_shift = 2;
  p.spatial_budget = budget;
  p.parallel_min = 256;  // parallel subtrees and binning on a small scene
  return build_binary_bvh(make_prim_refs(prims), p, true, &prims);
}

/// The leaves of a binary tree, as (box, references) in depth-first order.
std::vector<std::pair<BvhNode, std::vector<PrimRef>>> leaves_of(const BinaryBvh& t) {
  std::vector<std::pair<BvhNode, std::vector<PrimRef>>> out;
  std::vector<uint32_t> stack = {0};
  while (!stack.empty()) {
    const BvhNode& n = t.nodes[stack.back()];
    stack.pop_back();
    if (n.is_leaf()) {
      out.push_back({n, {t.refs.begin() + n.index, t.refs.begin() + n.index + n.count}});
      continue;
    }
    stack.push_back(n.index + 1), stack.push_back(n.index);
  }
  return out;
}

TEST(SpatialSplit, SameTreeAtEveryThreadCountAndWithinTheBudget) {
  const TestScene s = slivers(3000, 3000, 3);
  const size_t n = s.prims.size();
  for (float budget : {0.25f, 1.0f}) {
    std::vector<std::pair<BvhNode, std::vector<PrimRef>>> reference;
    BvhNodeArray reference_nodes;
    for (int threads : {1, 2, 3}) {
      const ThreadLimit limit(threads);
      const BinaryBvh t = spatial_tree(s.prims, budget);
      auto leaves = leaves_of(t);
      size_t refs = 0;
      std::map<uint32_t, int> seen;
      for (const auto& [node, r] : leaves) {
        refs += r.size();
        for (const PrimRef& ref : r) {
          EXPECT_TRUE(node.bounds().contains(ref.lo) && node.bounds().contains(ref.hi));
          ++seen[ref.id];
        }
      }
      EXPECT_EQ(seen.size(), n);  // every triangle is in the tree
      EXPECT_GT(refs, n + n / 20) << "spatial splits were made";
      EXPECT_LE(refs, size_t(double(n) * (1.0 + budget))) << "the budget holds";
      if (threads == 1) {
        reference = std::move(leaves);
        reference_nodes.assign(t.nodes.begin(), t.nodes.begin() + 2 * t.leaves);
        continue;
      }
      ASSERT_EQ(leaves.size(), reference.size()) << threads;
      EXPECT_EQ(std::memcmp(t.nodes.data(), reference_nodes.data(),
                            reference_nodes.size() * sizeof(BvhNode)),
                0)
          << budget << ", " << threads << " threads";
      for (size_t i = 0; i < leaves.size(); ++i) {
        ASSERT_EQ(leaves[i].second.size(), reference[i].second.size());
        ASSERT_EQ(std::memcmp(leaves[i].second.data(), reference[i].second.data(),
                              leaves[i].second.size() * sizeof(PrimRef)),
                  0)
            << budget << ", " << threads << " threads, leaf " << i;
      }
    }
  }
}

// A height field: cells of two triangles each, small against the upper nodes. There the best
// spatial plane duplicates a few per cent of a node's references or none (a plane on a grid line
// is the object split at that plane), so the upper nodes get no room for more references, and a
// subtree without room neither searches nor splits spatially: every leaf's range stays within
// the first n slots, and no time goes into moving references up for room that no split uses
// (bvh_builder.cpp, kRoomStraddlers). Long triangles still get their splits (the slivers of the
// tests before and after this one).
TEST(SpatialSplit, AHeightFieldOfSmallTrianglesKeepsItsReferencesCompact) {
  constexpr int kCells = 128;
  TriangleMesh m;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const float x = float(i) / 8.0f, y = float(j) / 8.0f;
      m.positions.push_back({x, y, 2.0f * std::sin(0.9f * x) * std::cos(0.7f * y) + 0.1f * x});
    }
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const auto v = static_cast<uint32_t>(j * (kCells + 1) + i);
      const uint32_t w = kCells + 1;
      for (uint32_t k : {v, v + 1, v + w + 1, v, v + w + 1, v + w}) m.indices.push_back(k);
    }
  PrimitiveSet prims;
  prims.add_mesh(m, Transform(), 0);
  const size_t n = prims.size();
  const BinaryBvh t = spatial_tree(prims, 1.0f);
  size_t refs = 0, end = 0;
  for (const auto& [node, r] : leaves_of(t)) {
    refs += r.size();
    end = std::max<size_t>(end, node.index + node.count);
  }
  EXPECT_EQ(refs, n) << "no spatial split pays on a height field";
  EXPECT_EQ(end, n) << "no node was given room";
}

// The point of it: on long triangles the tree with spatial splits tests fewer triangles, visits
// fewer nodes and has a lower SAH cost than object splits alone, with the same hits.
TEST(SpatialSplit, LongTrianglesCostLessWorkPerRay) {
  const TestScene s = slivers(2000, 2000, 4);
  auto plain = make_accelerator("bvh:spatial=0"), split = make_accelerator("bvh");
  plain->build(s.prims);
  split->build(s.prims);
  EXPECT_GT(split->stats().prim_refs, plain->stats().prim_refs);
  EXPECT_LE(split->stats().prim_refs, 2 * plain->stats().prim_refs);
  const auto rays = test::mixed_rays(s.prims, 20000, 5);
  TraversalCost a, b;
  test::trace_both(*plain, *split, rays, a, b);
  for (const Ray& ray : rays) ASSERT_EQ(plain->occluded(ray), split->occluded(ray));

  EXPECT_LT(double(b.prims), 0.8 * double(a.prims));
  EXPECT_LT(double(b.nodes), 0.9 * double(a.nodes));
  const auto sah = [](const Accelerator& acc) { return test::extra_stat(acc, "sah_cost"); };
  EXPECT_LT(sah(*split), 0.9 * sah(*plain));
}

TEST(SpatialSplit, SmallSetsKeepTheCheaperOfTheTwoTrees) {
  // Up to 4,096 primitives `bvh` builds with and without spatial splits and keeps the tree of
  // lower wide SAH cost: never dearer than object splits alone, cheaper on slivers.
  const auto sah = [](const Accelerator& acc) { return test::extra_stat(acc, "sah_cost"); };
  for (const TestScene& scene :
       {test::room_with_boxes(5, 1), test::random_soup(500, 2), slivers(300, 300, 3)}) {
    auto split = make_accelerator("bvh"), plain = make_accelerator("bvh:spatial=0");
    split->build(scene.prims);
    plain->build(scene.prims);
    EXPECT_LE(sah(*split), sah(*plain)) << scene.name;
    if (scene.name == std::string("slivers")) {
      EXPECT_LT(sah(*split), 0.95 * sah(*plain));
    }
  }
}

TEST(SpatialSplit, ParametersAreChecked) {
  for (const char* good :
       {"bvh:spatial=0", "bvh:spatial=4", "bvh:spatial=0.5,alpha=0", "bvh:build=median",
        "bvh:sweep", "bvh4:spatial=1", "bvh:nodes=compressed,spatial=2,alpha=1e-5"})
    EXPECT_NO_THROW(make_accelerator(good)) << good;
  for (const char* bad :
       {"bvh:spatial=-1", "bvh:spatial=4.5", "bvh:build=median,spatial=1", "bvh:sweep,spatial=0.5",
        "bvh:spatial=0,alpha=1e-3", "bvh:alpha=2", "bvh:width=2,spatial=1"})
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
  // Sets with other shapes are built without spatial splits (nothing to clip them by).
  const TestScene mixed = test::mixed_shapes(4);
  auto acc = make_accelerator("bvh"), plain = make_accelerator("bvh:spatial=0");
  acc->build(mixed.prims);
  plain->build(mixed.prims);
  EXPECT_EQ(acc->stats().prim_refs, plain->stats().prim_refs);
  EXPECT_EQ(acc->stats().nodes, plain->stats().nodes);
}

}  // namespace
}  // namespace penumbra
