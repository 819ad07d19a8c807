// The segment BSP: fragments cover their segments exactly and lie in their cells, the same seed
// gives the same tree, a hand-built example gives its known path, and the orders differ as the
// lecture says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "penumbra/accel2d/random_segments.h"
#include "penumbra/accel2d/segment_bsp.h"

namespace penumbra::lab2d {
namespace {

/// A small example in the style of the lecture: s1 on y = 0, s2 and s3 above it, s4, s5 below.
const char* kExample =
    "# five segments\n"
    "0 0 4 0\n"
    "1 2 1 4\n"
    "3 1 3 3\n"
    "0 -2 4 -2\n"
    "2 -4 2 -3\n";

TEST(SegmentBsp, FirstOrderOnTheExampleGivesTheKnownTreeAndPaths) {
  SegmentBsp bsp(BspOrder::kFirst, 1);
  bsp.build(parse_scene2d(kExample, "example"));
  // Preorder, ℓ⁺ first: l1 = ℓ(s1), l2 = ℓ(s2) with an empty leaf and s3, l3 = ℓ(s4) with an
  // empty leaf and s5.
  const LineTree& t = bsp.tree();
  ASSERT_EQ(t.nodes.size(), 7u);
  std::vector<std::string> labels;
  for (uint32_t k = 0; k < t.nodes.size(); ++k) labels.push_back(t.label(k));
  EXPECT_EQ(labels, (std::vector<std::string>{"l1", "l2", "empty", "s3", "l3", "empty", "s5"}));
  EXPECT_EQ(bsp.stats().fragments, 5u);
  EXPECT_EQ(bsp.stats().depth, 2u);

  // Up and right from (0.5, 0.5): across ℓ(s2) (testing s2, a miss) into s3's leaf.
  TraceLog a;
  Hit2 h = bsp.shoot({{0.5, 0.5}, {1, 0.4}}, &a);
  EXPECT_EQ(h.id, 2u);
  EXPECT_DOUBLE_EQ(h.t, 2.5);
  EXPECT_EQ(a.str(), "l1 l2 empty l2 s3");
  // Left: nothing; the walk returns to the root.
  TraceLog b;
  EXPECT_FALSE(bsp.shoot({{0.5, 0.5}, {-1, 0}}, &b).hit());
  EXPECT_EQ(b.str(), "l1 l2 empty l2 l1");
  // Down from (2, 1): s3's leaf, then back at l1 the ray crosses ℓ(s1) and hits s1, stored
  // there; nothing below comes near ℓ(s1), so the walk ends at l1, as in the lecture.
  TraceLog c;
  h = bsp.shoot({{2, 1}, {0, -1}}, &c);
  EXPECT_EQ(h.id, 0u);
  EXPECT_DOUBLE_EQ(h.t, 1.0);
  EXPECT_EQ(c.str(), "l1 l2 s3 l2 l1");
}

/// Checks that the fragments of every segment tile [0, 1] exactly and sum to its length.
void expect_fragments_cover(const SegmentBsp& bsp) {
  std::map<uint32_t, std::vector<Fragment>> by_seg;
  for (const Fragment& f : bsp.fragments()) by_seg[f.seg].push_back(f);
  ASSERT_EQ(by_seg.size(), bsp.segments().size());
  for (auto& [seg, frags] : by_seg) {
    std::sort(frags.begin(), frags.end(), [](auto& x, auto& y) { return x.t0 < y.t0; });
    EXPECT_EQ(frags.front().t0, 0.0);
    EXPECT_EQ(frags.back().t1, 1.0);
    const Segment2& s = bsp.segments()[seg];
    double sum = 0;
    for (size_t i = 0; i < frags.size(); ++i) {
      EXPECT_LT(frags[i].t0, frags[i].t1);
      if (i + 1 < frags.size()) {
        ASSERT_EQ(frags[i].t1, frags[i + 1].t0) << "gap or overlap";
      }
      sum += length(s.at(frags[i].t1) - s.at(frags[i].t0));
    }
    EXPECT_NEAR(sum, length(s.b - s.a), 1e-12 * length(s.b - s.a) * double(frags.size()));
    // The ends chain: each fragment's end point is the next one's start point, bit for bit.
    EXPECT_EQ(s.at(frags.front().t0), s.a);
    EXPECT_EQ(s.at(frags.back().t1), s.b);
  }
}

/// Checks that every fragment lies in its node's cell: on the right side (within the tolerance)
/// of every line on the path from the root, and in the line of the node that stores it.
void expect_fragments_in_cells(const SegmentBsp& bsp) {
  const LineTree& t = bsp.tree();
  const double eps = bsp.eps();
  struct Job {
    uint32_t node;
    std::vector<std::pair<Line2, int>> path;  // line and side (+1, -1)
  };
  std::vector<Job> jobs{{0, {}}};
  size_t checked = 0;
  while (!jobs.empty()) {
    Job job = std::move(jobs.back());
    jobs.pop_back();
    const LineNode& n = t.nodes[job.node];
    for (uint32_t k = n.first; k < n.first + n.count; ++k) {
      const Fragment& f = bsp.fragments()[k];
      const Segment2& s = bsp.segments()[f.seg];
      for (double u : {f.t0, f.t1, 0.5 * (f.t0 + f.t1)}) {
        const Vec2d p = s.at(u);
        for (const auto& [line, side] : job.path) ASSERT_GE(side * line.eval(p), -2 * eps);
        if (!n.leaf()) {
          ASSERT_LE(std::abs(n.line.eval(p)), 2 * eps);
        }
      }
      ++checked;
    }
    if (n.leaf()) {
      EXPECT_LE(n.count, 1u) << "a leaf holds at most one fragment";
      continue;
    }
    for (int side = 0; side < 2; ++side) {
      Job child{n.child[side], job.path};
      child.path.push_back({n.line, side == 0 ? 1 : -1});
      jobs.push_back(std::move(child));
    }
  }
  EXPECT_EQ(checked, bsp.fragments().size());
}

TEST(SegmentBsp, FragmentsCoverEachSegmentExactlyAndLieInTheirCells) {
  for (BspOrder order : {BspOrder::kRandom, BspOrder::kFirst, BspOrder::kFewestCuts})
    for (uint64_t seed : {1, 2}) {
      SegmentBsp bsp(order, seed);
      bsp.build(random_segments(1500, seed));
      EXPECT_GT(bsp.fragments().size(), 1500u) << "expected some cuts";
      expect_fragments_cover(bsp);
      expect_fragments_in_cells(bsp);
    }
  SegmentBsp comb(BspOrder::kFirst, 1);
  comb.build(comb_segments(80));
  expect_fragments_cover(comb);
  expect_fragments_in_cells(comb);
}

TEST(SegmentBsp, SameSeedSameTreeOtherSeedOtherTree) {
  const Scene2D scene = random_segments(2000, 4);
  auto signature = [&](uint64_t seed) {
    SegmentBsp bsp(BspOrder::kRandom, seed);
    bsp.build(scene);
    std::vector<double> sig;
    for (const LineNode& n : bsp.tree().nodes)
      sig.insert(sig.end(), {n.line.a, n.line.b, n.line.c, double(n.child[0]), double(n.count)});
    for (const Fragment& f : bsp.fragments()) sig.insert(sig.end(), {double(f.seg), f.t0, f.t1});
    return sig;
  };
  EXPECT_EQ(signature(7), signature(7));
  EXPECT_NE(signature(7), signature(8));
  // And the generator: same seed, same segments.
  const Scene2D again = random_segments(2000, 4);
  for (size_t k = 0; k < scene.shapes.size(); ++k) ASSERT_EQ(scene.shapes[k].v, again.shapes[k].v);
}

TEST(SegmentBsp, FirstOrderIsQuadraticOnTheCombRandomIsNot) {
  // Every line ℓ(si) cuts every later sj: the first-segment order makes n(n-1)/2 cuts plus the
  // n segments.
  const size_t n = 200;
  SegmentBsp first(BspOrder::kFirst, 1), random(BspOrder::kRandom, 1);
  const Scene2D comb = comb_segments(n);
  first.build(comb);
  random.build(comb);
  EXPECT_EQ(first.stats().fragments, n + n * (n - 1) / 2);
  EXPECT_LT(double(random.stats().fragments), 4.0 * n * std::log(double(n)));
}

TEST(SegmentBsp, RandomOrderFragmentsGrowLikeNLogN) {
  // The expected number of fragments of 2DRANDOMBSP is O(n log n) (de Berg et al., Theorem 12.1):
  // fragments / (n ln n) must not grow from n = 500 to n = 8000 (averaged over 3 seeds).
  auto ratio = [](size_t n) {
    double sum = 0;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      SegmentBsp bsp(BspOrder::kRandom, seed);
      bsp.build(random_segments(n, seed));
      sum += double(bsp.stats().fragments) / (double(n) * std::log(double(n)));
    }
    return sum / 3;
  };
  const double small = ratio(500), large = ratio(8000);
  EXPECT_LT(large, small * 1.1) << small << " " << large;
  EXPECT_GT(large, 0.0);
}

TEST(SegmentBsp, SegmentsInOneLineAreStoredAtTheNode) {
  SegmentBsp bsp(BspOrder::kFirst, 1);
  bsp.build(parse_scene2d("0 0 1 0\n2 0 3 0\n5 0 9 0\n0 1 1 2\n", "collinear"));
  const LineNode& root = bsp.tree().nodes[0];
  EXPECT_EQ(root.count, 3u);
  EXPECT_EQ(bsp.tree().label(root.child[0]), "s4");
  EXPECT_EQ(bsp.tree().label(root.child[1]), "empty");
  const Hit2 h = bsp.shoot({{10, 0}, {-1, 0}});  // along the line: enters s3 first
  EXPECT_EQ(h.id, 2u);
  EXPECT_EQ(h.t, 1.0);
}

}  // namespace
}  // namespace penumbra::lab2d
