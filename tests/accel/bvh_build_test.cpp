/// Tests of the BVH build methods (build=binned|median|sweep): parameters, the exactness of the
/// full-sweep SAH against brute force and binning, the balance of the median build, tree
/// invariants and determinism across thread counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "penumbra/accel/build/binned_sah.h"
#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/build/bvh_split.h"
#include "penumbra/accel/build/bvh_sweep.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

BvhBuildParams params_of(const std::string& spec) {
  return read_bvh_build_params(ParamList::parse(spec));
}

BinaryBvh build(const PrimitiveSet& prims, const std::string& spec) {
  return build_binary_bvh(make_prim_refs(prims), params_of(spec));
}

/// The SAH cost of a split as the builders compute it, in float: area(L) N(L) + area(R) N(R).
float split_cost(const Bounds3& l, size_t nl, const Bounds3& r, size_t nr) {
  return l.surface_area() * float(nl) + r.surface_area() * float(nr);
}

/// The least SAH cost over every object partition of `refs` in centroid order (centroid, then
/// id) on the three axes, by brute force: boxes of each prefix and suffix joined directly, the
/// sides' counts as the SAH's tests of blocks of 2^block_shift.
float brute_force_best_partition(std::vector<PrimRef> refs, int block_shift = 0) {
  const size_t count = refs.size();
  float best = kInfinity;
  for (int a = 0; a < 3; ++a) {
    std::sort(refs.begin(), refs.end(), [a](const PrimRef& x, const PrimRef& y) {
      const float cx = x.centroid2()[a], cy = y.centroid2()[a];
      return cx < cy || (cx == cy && x.id < y.id);
    });
    std::vector<Bounds3> suffix(count + 1);
    for (size_t i = count; i-- > 0;) suffix[i] = join(suffix[i + 1], refs[i].bounds());
    Bounds3 prefix;
    for (size_t i = 1; i < count; ++i) {
      prefix.extend(refs[i - 1].bounds());
      best = std::min(best,
                      prefix.surface_area() * sah_tests(uint32_t(i), block_shift) +
                          suffix[i].surface_area() * sah_tests(uint32_t(count - i), block_shift));
    }
  }
  return best;
}

/// An inner node with the range of references under it.
struct InnerNode {
  uint32_t node, begin, end;
  size_t depth;
};

/// Walks `t`, checking that boxes contain their children and references, that leaves hold at
/// most `max_leaf` references and cover every reference once; returns the inner nodes.
std::vector<InnerNode> walk(const BinaryBvh& t, int max_leaf) {
  std::vector<InnerNode> inner;
  std::vector<int> covered(t.refs.size(), 0);
  // Returns the reference range under node k.
  const auto visit = [&](auto&& self, uint32_t k, size_t depth) -> std::pair<uint32_t, uint32_t> {
    const BvhNode& n = t.nodes[k];
    const Bounds3 box = n.bounds();
    if (n.is_leaf()) {
      EXPECT_LE(n.count, uint32_t(max_leaf));
      for (uint32_t i = n.index; i < n.index + n.count; ++i) {
        ++covered[i];
        const Bounds3 u = join(box, t.refs[i].bounds());
        EXPECT_TRUE(u.lo == box.lo && u.hi == box.hi) << "leaf box contains its references";
      }
      return {n.index, n.index + n.count};
    }
    const auto [lb, le] = self(self, n.index, depth + 1);
    const auto [rb, re] = self(self, n.index + 1, depth + 1);
    EXPECT_EQ(le, rb) << "a subtree's references are contiguous";
    const Bounds3 u = join(t.nodes[n.index].bounds(), t.nodes[n.index + 1].bounds());
    EXPECT_TRUE(u.lo == box.lo && u.hi == box.hi) << "inner box is the union of its children";
    inner.push_back({k, lb, re, depth});
    return {lb, re};
  };
  if (!t.nodes.empty()) {
    const auto [b, e] = visit(visit, 0, 0);
    EXPECT_EQ(b, 0u);
    EXPECT_EQ(e, t.refs.size());
  }
  EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }));
  return inner;
}

/// Total SAH cost of a tree relative to its root's area: trav per inner node, one per reference.
double tree_cost(const BinaryBvh& t, double trav) {
  double cost = 0;
  for (size_t k = 0; k < t.nodes.size(); ++k) {
    if (k == 1) continue;  // padding
    const BvhNode& n = t.nodes[k];
    cost += n.bounds().surface_area() * (n.is_leaf() ? double(n.count) : trav);
  }
  return cost / t.nodes[0].bounds().surface_area();
}

// make_prim_refs leaves out exactly the primitives with an empty box and the triangles with two
// bit-identical vertices (never hit: geometry/triangle.h), on the four-lane path (all
// triangles) and the generic one (a sphere added), keeping id order.
TEST(PrimRefs, TrianglesNoRayCanHitAreLeftOut) {
  const auto bits = [](Vec3 v) {
    return std::array<uint32_t, 3>{std::bit_cast<uint32_t>(v.x), std::bit_cast<uint32_t>(v.y),
                                   std::bit_cast<uint32_t>(v.z)};
  };
  for (bool with_sphere : {false, true}) {
    TestScene s = degenerate_triangles(21);
    if (with_sphere) s.prims.add_sphere({Vec3(0.5f), 0.5f}, 1);
    SCOPED_TRACE(with_sphere ? "generic path" : "triangle path");
    EXPECT_EQ(s.prims.all_triangles(), !with_sphere);
    const PrimRefs refs = make_prim_refs(s.prims);
    std::vector<uint32_t> ids;
    for (const PrimRef& r : refs.refs) ids.push_back(r.id);
    EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
    size_t repeated = 0;
    for (uint32_t id = 0; id < s.prims.size(); ++id) {
      bool expect = !s.prims.prim_bounds(id).empty();
      if (s.prims.kind(id) == PrimKind::kTriangle) {
        const Vec3* v = s.prims.triangle(id);
        const bool rep = bits(v[0]) == bits(v[1]) || bits(v[1]) == bits(v[2]) ||
                         bits(v[0]) == bits(v[2]);
        repeated += expect && rep;
        expect = expect && !rep;
      }
      EXPECT_EQ(std::binary_search(ids.begin(), ids.end(), id), expect) << id;
    }
    EXPECT_GT(repeated, 100u);  // a sixth of the scene's 1000 triangles
  }
}

TEST(BvhBuild, MethodParametersAreParsedAndChecked) {
  EXPECT_EQ(params_of("bvh").method, BvhSplitMethod::kBinned);
  EXPECT_EQ(params_of("bvh:binned").method, BvhSplitMethod::kBinned);
  EXPECT_EQ(params_of("bvh:build=binned").method, BvhSplitMethod::kBinned);
  EXPECT_EQ(params_of("bvh:median").method, BvhSplitMethod::kMedian);
  EXPECT_EQ(params_of("bvh:build=median").method, BvhSplitMethod::kMedian);
  EXPECT_EQ(params_of("bvh:sweep").method, BvhSplitMethod::kSweep);
  EXPECT_EQ(params_of("bvh:build=sweep,sweep").method, BvhSplitMethod::kSweep);
  EXPECT_EQ(params_of("bvh:sweep,leaf=3,trav=1").max_leaf, 3);
  // Names keep the bare word; every width takes the parameter.
  EXPECT_EQ(make_accelerator("bvh:median")->name(), "bvh:median");
  EXPECT_EQ(make_accelerator("bvh:build=sweep,width=4")->name(), "bvh:build=sweep,width=4");
  EXPECT_EQ(make_accelerator("bvh2:sweep,leaf=2")->name(), "bvh2:leaf=2,sweep");
  EXPECT_NO_THROW(make_accelerator("bvh4:median"));
  for (const char* bad : {"bvh:build=quick", "bvh:median,sweep", "bvh:build=median,sweep",
                          "bvh:sweep=false", "bvh:median=2", "bvh:median,bins=8",
                          "bvh:build=sweep,bins=8", "bvh:median,trav=1", "bvh:sweep,leaf=0"}) {
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
  }
  try {
    make_accelerator("bvh:sweep,bins=8");
    ADD_FAILURE() << "bins with sweep accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'bins' applies only to build=binned"), std::string::npos)
        << e.what();
  }
}

TEST(BvhBuild, VariantsAreListedButNotOfferedAsNames) {
  size_t found = 0;
  for (const auto& info : accelerator_list())
    found += info.name == "bvh:median" || info.name == "bvh:sweep";
  EXPECT_EQ(found, 2u);
  try {
    make_accelerator("nope");
    ADD_FAILURE();
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bvh, bvh2"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("bvh:median"), std::string::npos) << msg;
  }
}

// At every inner node above the depth limit the sweep picks a partition whose SAH cost is the
// minimum over all object partitions in centroid order on the three axes (checked by brute
// force), and so no more than any binned split of the same references (every binned partition
// is one of those). Both are computed in the same float expression, so the comparisons are exact.
TEST(BvhBuild, SweepSplitIsTheExactSahMinimumAtEveryNode) {
  for (const TestScene& s : {random_soup(600, 21), room_with_boxes(12, 22), thin_and_large(23),
                             mixed_shapes(24), torus(12, 10)}) {
    SCOPED_TRACE(s.name);
    const BinaryBvh t = build(s.prims, "bvh:sweep,leaf=4");
    size_t checked = 0, binned_checked = 0;
    for (const InnerNode& in : walk(t, 4)) {
      const BvhNode& n = t.nodes[in.node];
      const BvhNode &l = t.nodes[n.index], &r = t.nodes[n.index + 1];
      std::vector<PrimRef> refs(t.refs.begin() + in.begin, t.refs.begin() + in.end);
      const size_t count = refs.size();
      // The chosen split: the left child's size is the number of references under it.
      const auto under = [&](uint32_t k) {
        size_t c = 0;
        std::vector<uint32_t> stack{k};
        while (!stack.empty()) {
          const BvhNode& m = t.nodes[stack.back()];
          stack.pop_back();
          if (m.is_leaf())
            c += m.count;
          else
            stack.insert(stack.end(), {m.index, m.index + 1});
        }
        return c;
      };
      const size_t left = under(n.index);
      const float chosen = split_cost(l.bounds(), left, r.bounds(), count - left);
      // Brute force over every prefix of every axis' centroid order.
      const float best = brute_force_best_partition(refs);
      Bounds3 centroids;
      for (const PrimRef& p : refs) centroids.extend(p.centroid2());
      EXPECT_EQ(chosen, best) << "node " << in.node << " of " << count << " references";
      // Binning with the default and with the most bins.
      for (int bins : {16, kMaxBins}) {
        const SahSplit binned = find_binned_split(refs, BinMapping(centroids, bins), false);
        if (binned.axis < 0) continue;  // the bins do not separate these references
        EXPECT_LE(chosen, binned.cost) << bins << " bins";
        ++binned_checked;
      }
      ++checked;
    }
    EXPECT_GT(checked, 10u);
    EXPECT_GT(binned_checked, checked);
  }
}

// exact=N: the binned build splits every node of at most N references by the exact SAH, the
// least cost over all object partitions in centroid order (checked by brute force); larger
// nodes stay binned. The direct call leaves the references in the chosen axis' order with the
// left side first, and prefers counts that fill blocks when the SAH counts blocks.
TEST(BvhBuild, ExactSplitOfSmallNodesIsTheSahMinimum) {
  EXPECT_EQ(params_of("bvh:exact=64").exact_below, 64);
  EXPECT_EQ(params_of("bvh").exact_below, 0);
  EXPECT_EQ(params_of("bvh:exact=auto").exact_below, 0);
  EXPECT_THROW(params_of("bvh:exact=257"), Error);
  EXPECT_THROW(params_of("bvh:exact=-1"), Error);
  EXPECT_THROW(params_of("bvh:sweep,exact=8"), Error);
  EXPECT_THROW(params_of("bvh:median,exact=8"), Error);
  for (const TestScene& s : {random_soup(900, 51), room_with_boxes(14, 52), torus(14, 12)}) {
    SCOPED_TRACE(s.name);
    const BinaryBvh t = build(s.prims, "bvh:exact=48,leaf=4");
    const auto inner = walk(t, 4);
    size_t exact = 0, binned_cheaper_somewhere = 0;
    for (const InnerNode& in : inner) {
      const uint32_t count = in.end - in.begin;
      if (count > 48 || in.depth >= size_t(kMaxSahDepth)) continue;
      const BvhNode& n = t.nodes[in.node];
      // The left child's references are the first ones of the range: its size is its range's.
      const auto first_of = [&](auto&& self, uint32_t k) -> uint32_t {
        const BvhNode& m = t.nodes[k];
        return m.is_leaf() ? m.index + m.count : self(self, m.index + 1);
      };
      const uint32_t left = first_of(first_of, n.index) - in.begin;
      const float chosen =
          split_cost(t.nodes[n.index].bounds(), left, t.nodes[n.index + 1].bounds(), count - left);
      std::vector<PrimRef> refs(t.refs.begin() + in.begin, t.refs.begin() + in.end);
      EXPECT_EQ(chosen, brute_force_best_partition(refs)) << "node of " << count;
      Bounds3 centroids;
      for (const PrimRef& p : refs) centroids.extend(p.centroid2());
      const SahSplit binned = find_binned_split(refs, BinMapping(centroids, 16), false);
      binned_cheaper_somewhere += binned.axis >= 0 && binned.cost > chosen;
      ++exact;
    }
    EXPECT_GT(exact, 20u);
    EXPECT_GT(binned_cheaper_somewhere, 0u) << "the exact split differs from binning somewhere";
  }
  // 24 unit boxes in a row, blocks of eight: the cheapest partition fills blocks (8 | 16 or
  // 16 | 8), which 16 bins over the centroids cannot separate exactly.
  std::vector<PrimRef> row;
  for (uint32_t i = 0; i < 24; ++i) {
    const float x = float(23 - i);  // ids in the reverse of the x order
    row.push_back(make_prim_ref(Bounds3{{x, 0, 0}, {x + 1, 1, 1}}, i));
  }
  const float best = brute_force_best_partition(row, 3);
  const SahSplit split = find_exact_split(row, 3);
  EXPECT_EQ(split.axis, 0);
  EXPECT_EQ(split.cost, best);
  EXPECT_EQ(split.left_count % 8, 0u) << split.left_count;
  EXPECT_EQ(split.left_count + split.right_count, 24u);
  for (size_t i = 0; i < row.size(); ++i) EXPECT_EQ(row[i].id, 23 - i) << "sorted along x";
  EXPECT_EQ(split.left.hi.x, float(split.left_count));
  EXPECT_EQ(split.right.lo.x, float(split.left_count));
}

// The binned builder skips binning a node that fits a leaf costing no more than a traversal
// step (the SAH test cannot choose a split there): every node of at most `leaf` references must
// still be a leaf exactly when its binned split loses to a leaf, whatever the traversal cost and
// SIMD block width (a shortcut that ignored either would split or merge nodes here).
TEST(BvhBuild, BinnedLeafDecisionIsTheSahTerminationTest) {
  for (const TestScene& s : {random_soup(800, 41), room_with_boxes(12, 42), torus(16, 12)}) {
    for (const float trav : {0.25f, 1.0f, 2.0f, 5.0f}) {
      for (const int shift : {0, 2}) {
        SCOPED_TRACE(s.name + " trav " + std::to_string(trav) + " shift " + std::to_string(shift));
        BvhBuildParams p = params_of("bvh:leaf=8");
        p.traversal_cost = trav, p.block_shift = shift;
        const BinaryBvh t = build_binary_bvh(make_prim_refs(s.prims), p);
        size_t small = 0, split = 0;
        // Each node with its reference range, checked where it holds 2..8 references.
        const auto visit = [&](auto&& self, uint32_t k) -> std::pair<uint32_t, uint32_t> {
          const BvhNode& n = t.nodes[k];
          std::pair<uint32_t, uint32_t> range{n.index, n.index + n.count};
          if (!n.is_leaf()) {
            const auto l = self(self, n.index);
            const auto r = self(self, n.index + 1);
            range = {l.first, r.second};
          }
          const uint32_t count = range.second - range.first;
          if (count >= 2 && count <= 8) {
            const std::span<const PrimRef> refs(t.refs.data() + range.first, count);
            Bounds3 centroids;
            for (const PrimRef& r : refs) centroids.extend(r.centroid2());
            const SahSplit best = find_binned_split(
                refs, BinMapping(centroids, std::max(4, int(count))), false, shift);
            const bool leaf =
                best.axis < 0 || sah_prefers_leaf(count, n.bounds(), best.cost, trav, shift);
            EXPECT_EQ(n.is_leaf(), leaf) << "node " << k << " of " << count << " references";
            ++small, split += !n.is_leaf();
          }
          return range;
        };
        visit(visit, 0);
        EXPECT_GT(small, 20u);
        if (trav < 1.0f) {
          EXPECT_GT(split, 0u) << "cheap traversal splits some small nodes";
        }
      }
    }
  }
}

// The whole tree is not guaranteed cheaper: greedy top-down choices need not be globally best
// (e.g. thin_and_large(23): sweep 29.59, binned with 64 bins 29.34). So this compares figures on
// fixed scenes: the sweep tree within 1% of the default binned one (observed: 0.4% to 8% cheaper
// on these) and much cheaper than the SAH-blind median tree (observed: 15% to 50%).
TEST(BvhBuild, SweepTreeCostIsNoWorseThanBinnedAndBeatsMedian) {
  for (const TestScene& s : {random_soup(3000, 31), room_with_boxes(40, 32), torus(60, 40)}) {
    const double binned = tree_cost(build(s.prims, "bvh"), 2.0);
    const double sweep = tree_cost(build(s.prims, "bvh:sweep"), 2.0);
    const double median = tree_cost(build(s.prims, "bvh:median"), 2.0);
    EXPECT_LE(sweep, binned * 1.01) << s.name << " binned " << binned << " median " << median;
    EXPECT_LT(sweep, median) << s.name;
  }
}

// Halving every node larger than a leaf gives depth ceil(log2(N / leaf)) exactly (the largest
// node at depth d holds ceil(N / 2^d) references) and leaves of at least (leaf + 1) / 2.
TEST(BvhBuild, MedianTreeIsBalanced) {
  for (int n : {1, 7, 1000, 4097}) {
    for (int leaf : {1, 4, 8}) {
      const TestScene s = random_soup(n, 40 + uint64_t(n));
      const BinaryBvh t = build(s.prims, "bvh:median,leaf=" + std::to_string(leaf));
      size_t depth = 0;
      for (int m = n; m > leaf; m = (m + 1) / 2) ++depth;
      EXPECT_EQ(t.max_depth, depth) << n << " refs, leaf " << leaf;
      walk(t, leaf);
      if (n <= leaf) continue;
      for (size_t k = 2; k < t.nodes.size(); ++k)
        if (t.nodes[k].is_leaf()) {
          EXPECT_GE(int(t.nodes[k].count), (leaf + 1) / 2);
        }
    }
  }
}

TEST(BvhBuild, CoincidentAndExponentialPrimitivesStayWithinTheStackDepth) {
  PrimitiveSet same, octaves;
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int i = 0; i < 3000; ++i) m.indices.insert(m.indices.end(), {0, 1, 2});
  same.add_mesh(m, Transform(), 0);
  for (int i = 0; i < 3000; ++i) {
    const float s = std::ldexp(1.0f, -(i % 60));
    octaves.add_sphere({{s, 0, 0}, s * 0.25f}, 0);
  }
  for (const char* spec : {"bvh:sweep,leaf=1", "bvh:median,leaf=1", "bvh:sweep,leaf=2"}) {
    for (const PrimitiveSet* prims : {&same, &octaves}) {
      const BinaryBvh t = build(*prims, spec);
      walk(t, std::atoi(std::strchr(spec, '=') + 1));
      EXPECT_LE(int(t.max_depth), kBvhStackSize) << spec;
    }
  }
}

// few_bins caps the bins of nodes under 256 references only: over 200 references the tree is
// the one binned with few_bins throughout; over thousands its upper levels use all the bins.
TEST(BvhBuild, FewBinsApplyToSmallNodesOnly) {
  const auto tree = [](const TestScene& s, int bins, int few_bins) {
    BvhBuildParams p;
    p.bins = bins, p.few_bins = few_bins, p.parallel_min = 1u << 30;
    return build_binary_bvh(make_prim_refs(s.prims), p);
  };
  const auto same = [](const BinaryBvh& a, const BinaryBvh& b) {
    return a.nodes.size() == b.nodes.size() &&
           std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)) == 0;
  };
  const TestScene small = random_soup(200, 41), large = random_soup(20000, 42);
  EXPECT_TRUE(same(tree(small, 64, 8), tree(small, 8, 0)));
  EXPECT_FALSE(same(tree(small, 64, 0), tree(small, 8, 0)));
  EXPECT_FALSE(same(tree(large, 64, 8), tree(large, 8, 0)));
  EXPECT_FALSE(same(tree(large, 64, 8), tree(large, 64, 0)));
}

TEST(BvhBuild, SameTreeForEveryThreadCount) {
  // Large enough for parallel sorts, sweeps, partitions and subtrees.
  const TestScene s = torus(200, 125);
  for (const char* spec : {"bvh:sweep", "bvh:median"}) {
    BinaryBvh reference;
    for (int threads : {1, 2, 3}) {
      const ThreadLimit limit(threads);
      BinaryBvh t = build(s.prims, spec);
      if (threads == 1) {
        reference = std::move(t);
        continue;
      }
      ASSERT_EQ(t.nodes.size(), reference.nodes.size()) << spec << " " << threads;
      EXPECT_EQ(
          std::memcmp(t.nodes.data(), reference.nodes.data(), t.nodes.size() * sizeof(BvhNode)), 0)
          << spec << " " << threads << " threads";
      EXPECT_EQ(std::memcmp(t.refs.data(), reference.refs.data(), t.refs.size() * sizeof(PrimRef)),
                0)
          << spec << " " << threads << " threads";
    }
  }
}

/// The nodes of `t` in depth-first order from the root, each inner node's child index replaced
/// by its position in that order: the tree, whatever slots its nodes took.
std::vector<BvhNode> depth_first(const BinaryBvh& t) {
  std::vector<BvhNode> out;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t k = stack.back();
    stack.pop_back();
    BvhNode n = t.nodes[k];
    if (!n.is_leaf()) {
      stack.push_back(n.index + 1), stack.push_back(n.index);
      n.index = 0;  // the order itself records the structure
    }
    out.push_back(n);
  }
  return out;
}

TEST(BvhBuild, UncompactedTreeTakesOnlyItsOwnSlotsAndIsTheSameForEveryThreadCount) {
  // Binned builds with and without spatial splits, with parallel subtrees from 64 references
  // on, so that many subtrees build concurrently and take their slots in a changing order.
  const TestScene s = torus(200, 125);
  for (const float spatial : {0.0f, 1.0f}) {
    BvhBuildParams p = params_of("bvh");
    p.parallel_min = 64;
    p.spatial_budget = spatial;
    std::vector<BvhNode> reference;
    for (int threads : {1, 2, 3}) {
      const ThreadLimit limit(threads);
      const size_t spare = size_t(spatial * float(s.prims.size())) + 1;
      const BinaryBvh t = build_binary_bvh(make_prim_refs(s.prims, spare), p, false, &s.prims);
      // Slots: the root, the padding and one pair per inner node, nothing beyond.
      uint32_t highest = 0;
      std::vector<uint32_t> stack{0};
      while (!stack.empty()) {
        const uint32_t k = stack.back();
        stack.pop_back();
        highest = std::max(highest, k);
        if (!t.nodes[k].is_leaf()) {
          EXPECT_EQ(t.nodes[k].index % 2, 0u) << "a pair starts at an even slot";
          EXPECT_GT(t.nodes[k].index, k) << "children follow their parent";
          stack.push_back(t.nodes[k].index), stack.push_back(t.nodes[k].index + 1);
        }
      }
      EXPECT_EQ(size_t(highest) + 1, 2 * t.leaves) << spatial << " " << threads << " threads";
      const std::vector<BvhNode> tree = depth_first(t);
      if (threads == 1) {
        reference = tree;
        continue;
      }
      ASSERT_EQ(tree.size(), reference.size()) << spatial << " " << threads << " threads";
      EXPECT_EQ(std::memcmp(tree.data(), reference.data(), tree.size() * sizeof(BvhNode)), 0)
          << spatial << " " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace penumbra::test
