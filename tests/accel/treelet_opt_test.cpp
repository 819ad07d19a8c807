/// Tests of treelet restructuring (bvh:optimize=N): every treelet becomes the cheapest binary tree
/// over its subtrees (checked against an enumeration of every topology), the tree keeps every
/// leaf with each box holding its children, the inner area never grows, the tree is the same at
/// every thread count, and the parameter is checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/treelet_opt.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

double area(const Bounds3& b) {
  const double dx = double(b.hi.x) - b.lo.x, dy = double(b.hi.y) - b.lo.y,
               dz = double(b.hi.z) - b.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

struct Walk {
  double inner_area = 0;
  size_t depth = 0;
  std::vector<std::tuple<uint32_t, uint32_t, std::vector<float>>> leaves;  // index, count, box
  bool boxes_hold_children = true;
};

/// Walks the tree from the root: its leaves (sorted), the sum of its inner nodes' areas, its
/// depth, and whether every inner box holds its children's boxes.
Walk walk(const BvhNodeArray& nodes) {
  Walk w;
  std::vector<std::pair<uint32_t, size_t>> todo{{0u, 0}};
  while (!todo.empty()) {
    const auto [x, d] = todo.back();
    todo.pop_back();
    const BvhNode& n = nodes[x];
    if (n.is_leaf()) {
      w.leaves.emplace_back(n.index, n.count, std::vector<float>(n.box, n.box + 6));
      w.depth = std::max(w.depth, d);
      continue;
    }
    w.inner_area += area(n.bounds());
    for (const uint32_t c : {n.index, n.index + 1}) {
      const Bounds3 b = n.bounds(), k = nodes[c].bounds();
      w.boxes_hold_children &= b.lo.x <= k.lo.x && b.lo.y <= k.lo.y && b.lo.z <= k.lo.z &&
                               k.hi.x <= b.hi.x && k.hi.y <= b.hi.y && k.hi.z <= b.hi.z;
      todo.push_back({c, d + 1});
    }
  }
  std::sort(w.leaves.begin(), w.leaves.end());
  return w;
}

/// The least sum of inner areas of any binary tree over `boxes`, by trying every split of the
/// set into two (each unordered split once) recursively: exponential, small sets only.
double cheapest_topology(const std::vector<Bounds3>& boxes) {
  if (boxes.size() == 1) return 0.0;
  Bounds3 all = boxes[0];
  for (const Bounds3& b : boxes) all.extend(b);
  double best = std::numeric_limits<double>::infinity();
  const size_t n = boxes.size();
  for (uint32_t m = 1; m < (1u << n) - 1; ++m) {
    if (!(m & 1u)) continue;  // the first box on the left: each split once
    std::vector<Bounds3> left, right;
    for (size_t i = 0; i < n; ++i) (m >> i & 1u ? left : right).push_back(boxes[i]);
    best = std::min(best, cheapest_topology(left) + cheapest_topology(right));
  }
  return area(all) + best;
}

/// A binary tree over single-primitive leaves with the given boxes, of a random topology, laid
/// out as build_binary_bvh lays it out (root, padding, then child pairs).
BvhNodeArray random_tree(const std::vector<Bounds3>& boxes, std::mt19937& rng) {
  BvhNodeArray nodes(2);
  nodes[1] = BvhNode{};
  // Builds the node for boxes [begin, end) in slot `slot`, children split at a random point.
  std::vector<uint32_t> order(boxes.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  const auto make = [&](auto&& self, uint32_t slot, size_t begin, size_t end) -> Bounds3 {
    if (end - begin == 1) {
      nodes[slot].set_bounds(boxes[order[begin]]);
      nodes[slot].index = order[begin];
      nodes[slot].count = 1;
      return boxes[order[begin]];
    }
    const size_t mid = std::uniform_int_distribution<size_t>(begin + 1, end - 1)(rng);
    const auto pair = uint32_t(nodes.size());
    nodes.resize(nodes.size() + 2);
    Bounds3 b = self(self, pair, begin, mid);
    b.extend(self(self, pair + 1, mid, end));
    nodes[slot].set_bounds(b);
    nodes[slot].index = pair;
    nodes[slot].count = 0;
    return b;
  };
  make(make, 0, 0, boxes.size());
  return nodes;
}

std::vector<Bounds3> random_boxes(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> pos(-10.0f, 10.0f), size(0.01f, 6.0f);
  std::vector<Bounds3> boxes(n);
  for (Bounds3& b : boxes) {
    b.lo = {pos(rng), pos(rng), pos(rng)};
    b.hi = b.lo + Vec3(size(rng), size(rng), size(rng));
  }
  return boxes;
}

// A tree of at most seven leaves is one treelet at the root (its children's treelets are
// rewritten first, then the root's over all its leaves): its topology must be the cheapest of all.
TEST(TreeletOpt, TreeOfUpToSevenLeavesBecomesTheCheapestTopology) {
  std::mt19937 rng(7);
  int improved = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const size_t n = 3 + size_t(trial % 5);
    const std::vector<Bounds3> boxes = random_boxes(n, rng);
    BvhNodeArray nodes = random_tree(boxes, rng);
    const Walk before = walk(nodes);
    const TreeletStats st = optimize_treelets(nodes, 1);
    const Walk after = walk(nodes);
    const double best = cheapest_topology(boxes);
    ASSERT_NEAR(after.inner_area, best, 1e-9 * best) << "trial " << trial << ", " << n;
    ASSERT_EQ(after.leaves, before.leaves);
    ASSERT_TRUE(after.boxes_hold_children);
    EXPECT_EQ(st.max_depth, after.depth);
    improved += st.treelets > 0;
    // Already cheapest: left as it was.
    if (before.inner_area <= best * (1 + 1e-12)) {
      EXPECT_EQ(st.treelets, 0u);
    }
  }
  EXPECT_GT(improved, 150);  // random topologies are mostly not the cheapest
}

// On built trees (object and spatial splits): every leaf is kept, each box holds its children,
// the inner area does not grow and the stats say what the walk finds.
TEST(TreeletOpt, KeepsEveryLeafAndNeverAddsArea) {
  size_t rewritten = 0;
  for (const auto& scene : {random_soup(3000, 3), torus(40, 30), room_with_boxes(30, 4)}) {
    for (const float spatial : {0.0f, 1.0f}) {
      BvhBuildParams p;
      p.block_shift = 2;
      p.spatial_budget = spatial;
      BinaryBvh tree =
          build_binary_bvh(make_prim_refs(scene.prims, size_t(spatial * scene.prims.size()) + 1), p,
                           true, &scene.prims);
      const Walk before = walk(tree.nodes);
      const TreeletStats st = optimize_treelets(tree.nodes, 3);
      const Walk after = walk(tree.nodes);
      EXPECT_EQ(after.leaves, before.leaves);
      EXPECT_TRUE(after.boxes_hold_children);
      EXPECT_LE(after.inner_area, before.inner_area * (1 + 1e-12));
      const double root = area(tree.nodes[0].bounds());
      EXPECT_NEAR(st.area_before, before.inner_area / root, 1e-9 * st.area_before);
      EXPECT_NEAR(st.area_after, after.inner_area / root, 1e-9 * st.area_after);
      EXPECT_EQ(st.max_depth, after.depth);
      rewritten += st.treelets;
    }
  }
  EXPECT_GT(rewritten, 0u);
}

// Large enough for the pass's parallel subtrees (below depth 8): the same nodes at every thread
// count.
TEST(TreeletOpt, SameTreeForEveryThreadCount) {
  const TestScene s = torus(200, 100);
  std::vector<unsigned char> reference;
  for (int threads : {1, 2, 3, 8}) {
    const ThreadLimit limit(threads);
    BvhBuildParams p;
    p.block_shift = 2;
    BinaryBvh tree = build_binary_bvh(make_prim_refs(s.prims), p);
    const TreeletStats st = optimize_treelets(tree.nodes, 2);
    EXPECT_GT(st.treelets, 0u);
    const auto* bytes = reinterpret_cast<const unsigned char*>(tree.nodes.data());
    const std::vector<unsigned char> now(bytes, bytes + tree.nodes.size() * sizeof(BvhNode));
    if (reference.empty()) {
      reference = now;
      continue;
    }
    ASSERT_EQ(now.size(), reference.size());
    EXPECT_EQ(std::memcmp(now.data(), reference.data(), now.size()), 0) << threads << " threads";
  }
}

TEST(TreeletOpt, ParameterIsCheckedAndAutoOptimisesSmallSets) {
  for (const char* ok :
       {"bvh:optimize=0", "bvh:optimize=3", "bvh:optimize=auto", "bvh4:optimize=1"})
    EXPECT_NO_THROW(make_accelerator(ok)) << ok;
  for (const char* bad : {"bvh:optimize=-1", "bvh:optimize=17", "bvh:optimize=yes"})
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
  const TestScene s = random_soup(2000, 11);
  auto automatic = make_accelerator("bvh");
  automatic->build(s.prims);
  EXPECT_GT(extra_stat(*automatic, "treelets rewritten"), 0.0);
  auto off = make_accelerator("bvh:optimize=0");
  off->build(s.prims);
  for (const auto& [key, value] : off->stats().extra) EXPECT_NE(key, "treelets rewritten");
  EXPECT_LT(extra_stat(*automatic, "inner area after"),
            extra_stat(*automatic, "inner area before"));
}

}  // namespace
}  // namespace penumbra::test
