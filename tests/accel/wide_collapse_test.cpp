/// Tests of the SAH-optimal collapse (bvh:collapse=sah): the planned cost is the cost of the tree
/// it makes, never above the greedy collapse's, and the least over every collapse of a small
/// tree (found by enumeration); the tree keeps every leaf, and the parameter is checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/wide_collapse.h"
#include "penumbra/accel/registry.h"
#include "penumbra/accel/wide_bvh.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

BinaryBvh binary_tree(const PrimitiveSet& prims, int max_leaf, int block_shift = 2, int bins = 16,
                      int exact_below = 0) {
  BvhBuildParams p;
  p.max_leaf = max_leaf;
  p.bins = bins;
  p.block_shift = block_shift;
  p.exact_below = exact_below;
  return build_binary_bvh(make_prim_refs(prims), p);
}

/// The least SAH cost (unnormalised) of binary node b's subtree as at most `slots` slots of a
/// wide node, by enumerating every way to cut the binary tree (exponential: small trees only).
/// Independent of SahCollapse's table: it recurses on sets of slots, not on counts. With
/// `max_leaf` > 0, an inner node of at most that many references may also be one leaf.
uint32_t subtree_refs(const BvhNodeArray& bin, uint32_t b) {
  return bin[b].is_leaf() ? bin[b].count
                          : subtree_refs(bin, bin[b].index) + subtree_refs(bin, bin[b].index + 1);
}
double best_cost(const BvhNodeArray& bin, uint32_t b, int slots, int width, float node_cost,
                 uint32_t max_leaf = 0) {
  const BvhNode& n = bin[b];
  const double area = n.bounds().surface_area();
  if (n.is_leaf()) return area * double((n.count + 3) / 4);
  const uint32_t refs = subtree_refs(bin, b);
  const double as_leaf = max_leaf > 0 && refs <= max_leaf ? area * double((refs + 3) / 4)
                                                          : std::numeric_limits<double>::infinity();
  // As one slot, b is a wide node whose children are a cut of its subtree into <= width slots.
  std::function<double(uint32_t, int)> cut = [&](uint32_t c, int k) -> double {
    // Cheapest cut of c's subtree into at most k slots (each slot a leaf or a wide node).
    double best = best_cost(bin, c, 1, width, node_cost, max_leaf);  // c itself as a slot
    if (!bin[c].is_leaf() && k >= 2)
      for (int left = 1; left < k; ++left)
        best = std::min(best, cut(bin[c].index, left) + cut(bin[c].index + 1, k - left));
    return best;
  };
  if (slots == 1) {
    double best = std::numeric_limits<double>::infinity();
    for (int left = 1; left < width; ++left)
      best = std::min(best, cut(n.index, left) + cut(n.index + 1, width - left));
    return std::min(as_leaf, node_cost * area + best);
  }
  return cut(b, slots);
}

TEST(SahCollapse, PlannedCostIsTheBuiltTreesAndAtMostTheGreedyOne) {
  for (const auto& scene : {random_soup(3000, 3), torus(40, 30), room_with_boxes(30, 4)}) {
    for (const char* width : {"8", "4"}) {
      // Object splits only and no treelet restructuring: the binary tree below is the one
      // these structures collapse.
      const std::string base = std::string("bvh:spatial=0,optimize=0,width=") + width;
      auto greedy = make_accelerator(base + ",collapse=greedy");
      auto sah = make_accelerator(base + ",collapse=sah");
      greedy->build(scene.prims);
      sah->build(scene.prims);
      const double g = extra_stat(*greedy, "sah_cost"), s = extra_stat(*sah, "sah_cost");
      EXPECT_LE(s, g * (1 + 1e-5)) << scene.name << " width " << width;
      EXPECT_GT(s, 1.0) << scene.name;
      EXPECT_EQ(sah->stats().leaves, greedy->stats().leaves) << scene.name;
      EXPECT_EQ(sah->stats().prim_refs, greedy->stats().prim_refs) << scene.name;

      // The plan's own figure for the same binary tree (the one the structure built).
      const BinaryBvh tree = binary_tree(scene.prims, 8);
      const SahCollapse plan(tree.nodes, std::stoi(width), 2.0f, 2);
      EXPECT_NEAR(plan.cost(), s, 1e-4 * s) << scene.name << " width " << width;
    }
  }
}

TEST(SahCollapse, FindsTheCheapestCollapseOfSmallTrees) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const PrimitiveSet prims = random_soup(24 + 4 * int(seed), seed).prims;
    const BinaryBvh tree = binary_tree(prims, 2);
    ASSERT_FALSE(tree.nodes[0].is_leaf());
    for (int width : {2, 3, 4}) {
      const SahCollapse plan(tree.nodes, width, 2.0f, 2);
      const double exact =
          best_cost(tree.nodes, 0, 1, width, 2.0f) / tree.nodes[0].bounds().surface_area();
      EXPECT_NEAR(plan.cost(), exact, 1e-4 * exact) << "seed " << seed << " width " << width;
    }
  }
}

// With leaves merged (the plan may make a small binary subtree one leaf), the plan's cost is still
// the least by enumeration, and never above the cost without merging on the same binary tree.
TEST(SahCollapse, FindsTheCheapestCollapseWithMergedLeaves) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const PrimitiveSet prims = random_soup(24 + 4 * int(seed), seed).prims;
    const BinaryBvh tree = binary_tree(prims, 1);
    ASSERT_FALSE(tree.nodes[0].is_leaf());
    for (int width : {2, 3, 4}) {
      for (uint32_t max_leaf : {4u, 8u}) {
        const SahCollapse plan(tree.nodes, width, 2.0f, 2, max_leaf);
        const SahCollapse unmerged(tree.nodes, width, 2.0f, 2);
        const double exact = best_cost(tree.nodes, 0, 1, width, 2.0f, max_leaf) /
                             tree.nodes[0].bounds().surface_area();
        EXPECT_NEAR(plan.cost(), exact, 1e-4 * exact) << "seed " << seed << " width " << width;
        EXPECT_LE(plan.cost(), unmerged.cost() * (1 + 1e-6)) << "seed " << seed;
      }
    }
  }
}

// The 16-wide structure with merged leaves reports the plan's cost for its binary tree (leaves
// of up to 8, 32 bins, nodes of up to 64 references split exactly: exact=auto).
TEST(SahCollapse, MergedPlanCostIsTheBuiltTrees) {
  for (const auto& scene : {random_soup(3000, 3), torus(40, 30), room_with_boxes(30, 4)}) {
    for (const int exact : {64, 0, 20}) {
      const std::string spec = "bvh:spatial=0,optimize=0,width=16,binleaf=8" +
                               (exact == 64 ? std::string() : ",exact=" + std::to_string(exact));
      auto merged = make_accelerator(spec);
      merged->build(scene.prims);
      const double s = extra_stat(*merged, "sah_cost");
      const BinaryBvh tree = binary_tree(scene.prims, 8, 3, 32, exact);
      const SahCollapse plan(tree.nodes, 16, 2.0f, 3, 16);
      EXPECT_NEAR(plan.cost(), s, 1e-4 * s) << scene.name << " " << spec;
      EXPECT_EQ(merged->stats().prim_refs, scene.prims.size()) << scene.name;
    }
  }
}

TEST(SahCollapse, ChildrenPartitionTheSubtreeIntoAtMostWidthSlots) {
  const BinaryBvh tree = binary_tree(random_soup(5000, 9).prims, 8);
  const SahCollapse plan(tree.nodes, 8, 2.0f, 2);
  // Walk the wide tree the plan makes and count the leaves' references: each exactly once.
  std::vector<int> seen(tree.refs.size(), 0);
  std::vector<uint32_t> todo = {0};
  while (!todo.empty()) {
    const uint32_t b = todo.back();
    todo.pop_back();
    uint32_t kids[8];
    const int n = plan.children(b, kids);
    ASSERT_GE(n, 2);
    ASSERT_LE(n, 8);
    for (int i = 0; i < n; ++i) {
      const BvhNode& k = tree.nodes[kids[i]];
      if (k.is_leaf())
        for (uint32_t r = k.index; r < k.index + k.count; ++r) ++seen[r];
      else
        todo.push_back(kids[i]);
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), long(seen.size()));
}

/// The bytes of a wide BVH's nodes (nothing for another structure).
template <int W>
std::vector<unsigned char> bytes_of(const WideBvh<W>& bvh) {
  const auto nodes = bvh.nodes();
  const auto* p = reinterpret_cast<const unsigned char*>(nodes.data());
  return {p, p + nodes.size_bytes()};
}
std::vector<unsigned char> node_bytes(const Accelerator& accel) {
  if (const auto* w = dynamic_cast<const WideBvh<16>*>(&accel)) return bytes_of(*w);
  if (const auto* w = dynamic_cast<const WideBvh<8>*>(&accel)) return bytes_of(*w);
  if (const auto* w = dynamic_cast<const WideBvh<4>*>(&accel)) return bytes_of(*w);
  return {};
}

// Large enough for the plan's parallel tasks (over 2^16 rows) and the collapse's: the wide tree
// must be the same bytes at every thread count.
TEST(SahCollapse, SameWideTreeForEveryThreadCount) {
  const TestScene s = torus(400, 250);
  // `bvh` is one of the two explicit widths (which, by target), so it is not built a third time.
  for (const char* spec :
       {"bvh:width=8", "bvh:width=16", "bvh:width=16,binleaf=8", "bvh:collapse=greedy", "bvh4"}) {
    std::vector<unsigned char> reference;
    for (int threads : {1, 2, 3, 8}) {
      const ThreadLimit limit(threads);
      // The build's own code, whose classes node_bytes() knows (isa=, registry.h).
      const std::string own =
          std::string(spec) + (std::strchr(spec, ':') ? "," : ":") + "isa=native";
      auto accel = make_accelerator(own);
      accel->build(s.prims);
      const std::vector<unsigned char> bytes = node_bytes(*accel);
      ASSERT_FALSE(bytes.empty()) << spec;
      if (reference.empty()) {
        reference = bytes;
        continue;
      }
      ASSERT_EQ(bytes.size(), reference.size()) << spec << ", " << threads << " threads";
      EXPECT_EQ(std::memcmp(bytes.data(), reference.data(), bytes.size()), 0)
          << spec << ", " << threads << " threads";
    }
  }
}

TEST(SahCollapse, ParameterIsChecked) {
  EXPECT_NO_THROW(make_accelerator("bvh:collapse=greedy"));
  EXPECT_NO_THROW(make_accelerator("bvh:collapse=sah,nodes=compressed"));
  EXPECT_NO_THROW(make_accelerator("bvh4:collapse=sah"));
  EXPECT_THROW(make_accelerator("bvh:collapse=optimal"), Error);
  EXPECT_THROW(make_accelerator("bvh:width=2,collapse=sah"), Error);  // binary: nothing to collapse
  EXPECT_THROW(SahCollapse(BvhNodeArray{}, 17, 2.0f, 2), Error);
  EXPECT_THROW(SahCollapse(BvhNodeArray{}, 1, 2.0f, 2), Error);
}

}  // namespace
}  // namespace penumbra::test
