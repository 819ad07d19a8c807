/// Tests of the balanced point kd-tree: radius and k-nearest queries against brute force on
/// uniform, duplicated, flat, collinear and clustered point sets of sizes 0 to 100000 (with
/// finite and infinite radii and accept predicates), bounds, the permutation of the input, the
/// median layout, memory per point and the early stop on duplicates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "penumbra/accel/point_kdtree.h"
#include "penumbra/core/rng.h"

namespace penumbra::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// A record with a position and its index in the input, so results map back to the input.
struct TestPoint {
  Vec3 p;
  uint32_t id = 0;
};

using Points = std::vector<TestPoint>;
using Generator = std::function<Vec3(Pcg32&, uint32_t i, uint32_t n)>;

/// The same float expression as the tree's, so distances compare exactly.
float dist2(Vec3 a, Vec3 b) {
  const Vec3 d = a - b;
  return d.x * d.x + d.y * d.y + d.z * d.z;
}

float uniform(Pcg32& rng, float a, float b) {
  return a + (b - a) * rng.next_float();
}

/// A standard normal variate (Box, Muller 1958).
float gaussian(Pcg32& rng) {
  const double u1 = 1.0 - rng.next_double(), u2 = rng.next_double();
  return float(std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2));
}

Points make_points(uint32_t n, uint64_t seed, const Generator& gen) {
  Pcg32 rng(seed, 7);
  Points pts(n);
  for (uint32_t i = 0; i < n; ++i) pts[i] = {gen(rng, i, n), i};
  return pts;
}

Vec3 uniform_cube(Pcg32& rng, uint32_t, uint32_t) {
  return {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
}
Vec3 identical(Pcg32&, uint32_t, uint32_t) {
  return {0.25f, -0.5f, 0.75f};
}
/// Many copies of four points, in random order.
Vec3 few_distinct(Pcg32& rng, uint32_t, uint32_t) {
  static const Vec3 kSites[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f}, {0.5f, 0.5f, -2}};
  return kSites[rng.next_bounded(4)];
}
Vec3 plane(Pcg32& rng, uint32_t, uint32_t) {
  return {uniform(rng, -1, 1), uniform(rng, -3, 3), 0.5f};
}
/// On a line parallel to x: zero extent on two axes.
Vec3 line(Pcg32& rng, uint32_t, uint32_t) {
  return {uniform(rng, -1, 1), -0.25f, 2.0f};
}
/// Three Gaussian blobs: 70% of the points with sigma 1e-3, 25% with 0.1, 5% with 1.
Vec3 clusters(Pcg32& rng, uint32_t, uint32_t) {
  const float u = rng.next_float();
  const Vec3 center = u < 0.7f ? Vec3(0.3f, 0.3f, 0.3f) : (u < 0.95f ? Vec3(-1, 0, 0) : Vec3(0));
  const float sigma = u < 0.7f ? 1e-3f : (u < 0.95f ? 0.1f : 1.0f);
  return center + Vec3(gaussian(rng), gaussian(rng), gaussian(rng)) * sigma;
}

const uint32_t kSizes[] = {0, 1, 2, 3, 7, 1000, 100000};

Bounds3 brute_bounds(const Points& pts) {
  Bounds3 b;
  for (const TestPoint& t : pts) b.extend(t.p);
  return b;
}

/// Query points: copies of data points (zero distances and ties), jittered data points, points
/// in the bounds grown by 10%, and one far outside.
std::vector<Vec3> make_queries(const Points& pts, int count, uint64_t seed) {
  Pcg32 rng(seed, 11);
  Bounds3 b = brute_bounds(pts);
  if (b.empty()) b = Bounds3(Vec3(-1), Vec3(1));
  const Vec3 d = b.diagonal(), margin = d * 0.1f + Vec3(1e-3f);
  std::vector<Vec3> qs;
  for (int i = 0; i < count; ++i) {
    const int kind = pts.empty() ? 2 : i % 3;
    if (kind == 0) {
      qs.push_back(pts[rng.next_bounded(uint32_t(pts.size()))].p);
    } else if (kind == 1) {
      const Vec3 j(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      qs.push_back(pts[rng.next_bounded(uint32_t(pts.size()))].p + j * 1e-3f);
    } else {
      qs.push_back({uniform(rng, b.lo.x - margin.x, b.hi.x + margin.x),
                    uniform(rng, b.lo.y - margin.y, b.hi.y + margin.y),
                    uniform(rng, b.lo.z - margin.z, b.hi.z + margin.z)});
    }
  }
  qs.push_back(b.hi + Vec3(100.0f));
  return qs;
}

/// Search radii relative to the size of the set: zero (exact matches only) up to infinity.
std::vector<float> radii2(const Points& pts) {
  const Bounds3 b = brute_bounds(pts);
  float d = b.empty() ? 1.0f : length(b.diagonal());
  if (d == 0.0f) d = 1.0f;
  std::vector<float> r2 = {0.0f, kInf};
  for (float f : {0.002f, 0.01f, 0.1f, 0.5f}) r2.push_back((f * d) * (f * d));
  return r2;
}

/// The accept predicates checked: all points, a subset by id, a half-space (as a surface
/// restriction would), by name for failure messages.
struct Predicate {
  std::string name;
  std::function<bool(const TestPoint&)> accept;
};
std::vector<Predicate> predicates(const Points& pts) {
  const float cx = brute_bounds(pts).center().x;
  return {{"all", [](const TestPoint&) { return true; }},
          {"id%3", [](const TestPoint& t) { return t.id % 3 != 0; }},
          {"x>center", [cx](const TestPoint& t) { return t.p.x > cx; }}};
}

int query_count(size_t n) {
  return n >= 100000 ? 24 : 60;
}

void check_radius(const Generator& gen, uint64_t seed) {
  for (uint32_t n : kSizes) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const Points input = make_points(n, seed + n, gen);
    const PointKdTree<TestPoint> tree(input);
    ASSERT_EQ(tree.size(), n);
    for (Vec3 q : make_queries(input, query_count(n), seed * 3 + n)) {
      for (float r2 : radii2(input)) {
        std::vector<uint32_t> got, want;
        tree.for_each_in_radius(q, r2, [&](const TestPoint& t, float d2) {
          const auto index = size_t(&t - tree.points().data());
          ASSERT_LT(index, tree.size());
          ASSERT_EQ(d2, dist2(q, t.p));
          got.push_back(t.id);
        });
        for (const TestPoint& t : input)
          if (dist2(q, t.p) <= r2) want.push_back(t.id);
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, want) << "q = (" << q.x << ", " << q.y << ", " << q.z << "), r2 = " << r2;
      }
    }
  }
}

void check_nearest(const Generator& gen, uint64_t seed) {
  std::vector<KdNeighbor> out;
  for (uint32_t n : kSizes) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const Points input = make_points(n, seed + n, gen);
    const PointKdTree<TestPoint> tree(input);
    const std::vector<float> rs = radii2(input);
    // A finite radius that cuts some neighbour lists short, and no limit.
    const float max_r2s[] = {rs[3], kInf};
    for (Vec3 q : make_queries(input, query_count(n), seed * 5 + n)) {
      for (const Predicate& pred : predicates(input)) {
        for (float max_r2 : max_r2s) {
          std::vector<float> all;
          for (const TestPoint& t : input) {
            const float d2 = dist2(q, t.p);
            if (d2 <= max_r2 && pred.accept(t)) all.push_back(d2);
          }
          std::sort(all.begin(), all.end());
          for (size_t k : {size_t(1), size_t(5), size_t(50), size_t(n) + 3}) {
            SCOPED_TRACE(pred.name + ", k = " + std::to_string(k) +
                         ", max_r2 = " + std::to_string(max_r2));
            const size_t count = tree.nearest(q, k, max_r2, out, pred.accept);
            ASSERT_EQ(count, out.size());
            const std::vector<float> want(all.begin(), all.begin() + std::min(k, all.size()));
            std::vector<float> got;
            std::vector<uint32_t> ids;
            for (const KdNeighbor& nb : out) {
              ASSERT_LT(nb.index, tree.size());
              const TestPoint& t = tree.points()[nb.index];
              ASSERT_EQ(nb.dist2, dist2(q, t.p));  // each point really is at that distance
              ASSERT_TRUE(pred.accept(t));
              got.push_back(nb.dist2);
              ids.push_back(t.id);
            }
            ASSERT_EQ(got, want);  // same sorted distance list (ties: any of the tied points)
            std::sort(ids.begin(), ids.end());
            ASSERT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end()) << "repeated";
          }
        }
      }
    }
  }
}

TEST(PointKdTree, RadiusMatchesBruteForceOnUniformCube) {
  check_radius(uniform_cube, 101);
}
TEST(PointKdTree, NearestMatchesBruteForceOnUniformCube) {
  check_nearest(uniform_cube, 102);
}
TEST(PointKdTree, RadiusMatchesBruteForceOnIdenticalPoints) {
  check_radius(identical, 201);
}
TEST(PointKdTree, NearestMatchesBruteForceOnIdenticalPoints) {
  check_nearest(identical, 202);
}
TEST(PointKdTree, RadiusMatchesBruteForceOnFewDistinctPoints) {
  check_radius(few_distinct, 301);
}
TEST(PointKdTree, NearestMatchesBruteForceOnFewDistinctPoints) {
  check_nearest(few_distinct, 302);
}
TEST(PointKdTree, RadiusMatchesBruteForceOnPlane) {
  check_radius(plane, 401);
}
TEST(PointKdTree, NearestMatchesBruteForceOnPlane) {
  check_nearest(plane, 402);
}
TEST(PointKdTree, RadiusMatchesBruteForceOnLine) {
  check_radius(line, 501);
}
TEST(PointKdTree, NearestMatchesBruteForceOnLine) {
  check_nearest(line, 502);
}
TEST(PointKdTree, RadiusMatchesBruteForceOnClusters) {
  check_radius(clusters, 601);
}
TEST(PointKdTree, NearestMatchesBruteForceOnClusters) {
  check_nearest(clusters, 602);
}

TEST(PointKdTree, EmptyTreeFindsNothing) {
  const PointKdTree<TestPoint> tree(Points{});
  EXPECT_TRUE(tree.empty());
  EXPECT_TRUE(tree.bounds().empty());
  EXPECT_EQ(tree.bytes(), 0u);
  int calls = 0;
  tree.for_each_in_radius(Vec3(0), kInf, [&](const TestPoint&, float) { ++calls; });
  EXPECT_EQ(calls, 0);
  std::vector<KdNeighbor> out = {{1, 2.0f}};
  EXPECT_EQ(tree.nearest(Vec3(0), 5, kInf, out), 0u);
  EXPECT_TRUE(out.empty());
  const PointKdTree<TestPoint> defaulted;
  EXPECT_EQ(defaulted.nearest(Vec3(0), 5, kInf, out), 0u);
}

TEST(PointKdTree, KZeroReturnsNothingAndClearsOut) {
  const PointKdTree<TestPoint> tree(make_points(100, 7, uniform_cube));
  std::vector<KdNeighbor> out = {{1, 2.0f}};
  EXPECT_EQ(tree.nearest(Vec3(0), 0, kInf, out), 0u);
  EXPECT_TRUE(out.empty());
}

TEST(PointKdTree, BoundsMatchBruteForce) {
  for (const Generator& gen : {Generator(uniform_cube), Generator(plane), Generator(clusters)})
    for (uint32_t n : kSizes) {
      const Points input = make_points(n, 900 + n, gen);
      const PointKdTree<TestPoint> tree(input);
      EXPECT_EQ(tree.bounds(), brute_bounds(input)) << "n = " << n;
    }
}

TEST(PointKdTree, HoldsAPermutationOfTheInput) {
  for (uint32_t n : kSizes) {
    const Points input = make_points(n, 1000 + n, clusters);
    const PointKdTree<TestPoint> tree(input);
    ASSERT_EQ(tree.points().size(), n);
    std::vector<int> seen(n, 0);
    for (const TestPoint& t : tree.points()) {
      ASSERT_LT(t.id, n);
      ++seen[t.id];
      EXPECT_EQ(t.p, input[t.id].p);
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(n)) << "n = " << n;
  }
}

/// Checks the implicit layout: the node of [lo, hi) is at the middle and splits its subrange on
/// the axis of largest extent of the subrange's bounds (<= on the left, >= on the right).
void check_medians(const std::vector<TestPoint>& pts, size_t lo, size_t hi) {
  if (hi - lo < 2) return;
  Bounds3 b;
  for (size_t i = lo; i < hi; ++i) b.extend(pts[i].p);
  const int axis = b.max_extent_axis();
  const size_t mid = lo + (hi - lo) / 2;
  const float split = pts[mid].p[axis];
  for (size_t i = lo; i < mid; ++i) ASSERT_LE(pts[i].p[axis], split) << "left of " << mid;
  for (size_t i = mid + 1; i < hi; ++i) ASSERT_GE(pts[i].p[axis], split) << "right of " << mid;
  check_medians(pts, lo, mid);
  check_medians(pts, mid + 1, hi);
}

TEST(PointKdTree, EveryNodeIsTheMedianOnItsWidestAxis) {
  for (const Generator& gen :
       {Generator(uniform_cube), Generator(plane), Generator(clusters), Generator(few_distinct)})
    for (uint32_t n : {7u, 1000u, 100000u}) {
      SCOPED_TRACE("n = " + std::to_string(n));
      const PointKdTree<TestPoint> tree(make_points(n, 1100 + n, gen));
      check_medians(tree.points(), 0, tree.size());
    }
}

TEST(PointKdTree, BytesAreOneRecordPlusOneBytePerPoint) {
  Points input = make_points(1000, 1200, uniform_cube);
  input.reserve(4000);  // slack from growth is dropped by the build
  const PointKdTree<TestPoint> tree(std::move(input));
  EXPECT_EQ(tree.bytes(), 1000 * (sizeof(TestPoint) + 1));
}

TEST(PointKdTree, NearestOnDuplicatesStopsAfterK) {
  // With 100000 copies of one point, once k are found at distance 0 nothing closer exists: the
  // search must stop instead of testing every copy.
  const PointKdTree<TestPoint> tree(make_points(100000, 1300, identical));
  std::vector<KdNeighbor> out;
  int tested = 0;
  const auto count = [&](const TestPoint&) { return ++tested, true; };
  EXPECT_EQ(tree.nearest(Vec3(0.25f, -0.5f, 0.75f), 8, kInf, out, count), 8u);
  EXPECT_EQ(tested, 8);
  for (const KdNeighbor& nb : out) EXPECT_EQ(nb.dist2, 0.0f);
}

TEST(PointKdTree, KLargerThanSizeReturnsAllWithinRadius) {
  const Points input = make_points(7, 1400, uniform_cube);
  const PointKdTree<TestPoint> tree(input);
  std::vector<KdNeighbor> out;
  EXPECT_EQ(tree.nearest(Vec3(0), 1000, kInf, out), 7u);
  for (size_t i = 1; i < out.size(); ++i) EXPECT_LE(out[i - 1].dist2, out[i].dist2);
}

}  // namespace
}  // namespace penumbra::test
