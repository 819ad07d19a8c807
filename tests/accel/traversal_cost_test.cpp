/// The counting queries (Accelerator::intersect_cost, the cost view's source): every registered
/// structure returns exactly intersect's hit while counting, brute force counts every primitive,
/// and the counts measure what the structures are for (far fewer tests than brute force).
#include <gtest/gtest.h>

#include <bit>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "penumbra/accel/registry.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

std::vector<std::string> all_structures() {
  std::vector<std::string> names;
  for (const auto& info : accelerator_list()) names.push_back(info.name);
  return names;
}

bool same_hit(const Hit& a, const Hit& b) {
  return std::bit_cast<uint32_t>(a.t) == std::bit_cast<uint32_t>(b.t) && a.prim == b.prim &&
         std::bit_cast<uint32_t>(a.u) == std::bit_cast<uint32_t>(b.u) &&
         std::bit_cast<uint32_t>(a.v) == std::bit_cast<uint32_t>(b.v);
}

class TraversalCostTest : public ::testing::TestWithParam<std::string> {};

// Counting must not change the answer: the same hit, bit for bit, on scenes of triangles only
// (the block paths) and of mixed shapes (the generic leaf paths), with rays along planes.
TEST_P(TraversalCostTest, CountingReturnsTheSameHitAsIntersect) {
  for (const TestScene& scene : {random_soup(2000, 41), mixed_shapes(42)}) {
    auto accel = make_accelerator(GetParam());
    accel->build(scene.prims);
    const std::vector<Ray> rays = mixed_rays(scene.prims, 20'000, 43);
    TraversalCost total;
    size_t hits = 0;
    for (const Ray& ray : rays) {
      Hit plain, counted;
      const bool a = accel->intersect(ray, plain);
      TraversalCost c;
      const bool b = accel->intersect_cost(ray, counted, c);
      ASSERT_EQ(a, b) << scene.name;
      if (a) {
        ASSERT_TRUE(same_hit(plain, counted)) << scene.name;
        // A hit needs a primitive test, and that a leaf (or cell) was reached.
        EXPECT_GE(c.prims, 1u);
        EXPECT_GE(c.nodes, 1u);
        ++hits;
      }
      total += c;
    }
    EXPECT_GT(hits, rays.size() / 10) << scene.name;
    EXPECT_GT(total.nodes, 0u) << scene.name;
  }
}

// The any-hit count returns occluded's answer. A ray that hits nothing visits, in any order,
// every node and primitive on its interval: its counts are then those of the closest-hit query.
// A ray that hits stops at some hit, having reached a leaf and tested a primitive. (Fewer tests
// than the closest-hit query's is no rule: the BSP tree tests the polygons in a plane before
// the near child, where the closest-hit query defers them.)
TEST_P(TraversalCostTest, AnyHitCountingReturnsOccludedsAnswer) {
  for (const TestScene& scene : {random_soup(2000, 41), mixed_shapes(42)}) {
    auto accel = make_accelerator(GetParam());
    accel->build(scene.prims);
    const std::vector<Ray> rays = mixed_rays(scene.prims, 20'000, 43);
    size_t misses = 0;
    for (const Ray& ray : rays) {
      TraversalCost any, closest;
      const bool blocked = accel->occluded_cost(ray, any);
      ASSERT_EQ(blocked, accel->occluded(ray)) << scene.name;
      Hit hit;
      ASSERT_EQ(accel->intersect_cost(ray, hit, closest), blocked) << scene.name;
      if (blocked) {
        EXPECT_GE(any.prims, 1u);
        EXPECT_GE(any.nodes, 1u);
      } else {
        ASSERT_EQ(any.nodes, closest.nodes) << scene.name;
        ASSERT_EQ(any.prims, closest.prims) << scene.name;
        ++misses;
      }
    }
    EXPECT_GT(misses, rays.size() / 10) << scene.name;
    EXPECT_LT(misses, rays.size() * 9 / 10) << scene.name;
  }
}

// Every structure tests fewer primitives per ray than brute force does, on a scene where that
// is the point of having a structure: 20,000 small triangles.
TEST_P(TraversalCostTest, TestsFarFewerPrimitivesThanBruteForce) {
  const TestScene scene = random_soup(20'000, 44);
  auto accel = make_accelerator(GetParam());
  accel->build(scene.prims);
  const std::vector<Ray> rays = mixed_rays(scene.prims, 2000, 45);
  TraversalCost total;
  for (const Ray& ray : rays) {
    Hit hit;
    accel->intersect_cost(ray, hit, total);
  }
  const double per_ray = double(total.prims) / double(rays.size());
  if (GetParam() == "brute")
    EXPECT_EQ(total.prims, uint64_t(scene.prims.size()) * rays.size());
  else
    EXPECT_LT(per_ray, 0.05 * double(scene.prims.size())) << per_ray;
}

INSTANTIATE_TEST_SUITE_P(Registry, TraversalCostTest, ::testing::ValuesIn(all_structures()),
                         [](const auto& info) { return structure_test_name(info.param); });

// Brute force: one leaf and every primitive for every ray, hit or not; a ray that cannot be
// traced (NaN direction) counts nothing.
TEST(TraversalCost, BruteForceCountsEveryPrimitiveOnce) {
  const TestScene scene = random_soup(300, 46);
  auto brute = make_accelerator("brute");
  brute->build(scene.prims);
  for (const Ray& ray : mixed_rays(scene.prims, 200, 47)) {
    TraversalCost c;
    Hit hit;
    brute->intersect_cost(ray, hit, c);
    EXPECT_EQ(c.nodes, 1u);
    EXPECT_EQ(c.prims, scene.prims.size());
  }
  Ray bad;
  bad.d = {std::nanf(""), 0.0f, 1.0f};
  TraversalCost c;
  Hit hit;
  EXPECT_FALSE(brute->intersect_cost(bad, hit, c));
  EXPECT_FALSE(brute->occluded_cost(bad, c));
  EXPECT_EQ(c.nodes + c.prims, 0u);
}

// Brute force's any-hit query tests the primitives in order up to the first one in the way: as
// many as the index of the first primitive a ray hits on its own, plus one, or all of them.
TEST(TraversalCost, BruteForceAnyHitStopsAtTheFirstPrimitiveInTheWay) {
  const TestScene scene = random_soup(300, 46);
  auto brute = make_accelerator("brute");
  brute->build(scene.prims);
  size_t stopped_early = 0;
  for (const Ray& ray : mixed_rays(scene.prims, 200, 47)) {
    const PreparedRay pr(ray);
    uint32_t first = uint32_t(scene.prims.size());
    for (uint32_t id = 0; id < scene.prims.size() && first == scene.prims.size(); ++id)
      if (scene.prims.occludes(id, pr)) first = id;
    TraversalCost c;
    EXPECT_EQ(brute->occluded_cost(ray, c), first < scene.prims.size());
    EXPECT_EQ(c.nodes, 1u);
    EXPECT_EQ(c.prims, std::min<uint64_t>(first + 1, scene.prims.size()));
    stopped_early += first + 1 < scene.prims.size();
  }
  EXPECT_GT(stopped_early, 10u);
}

// The binary BVH over three triangles: a ray through one's box counts a node and at least that
// triangle (at most all three); a ray missing the root box counts nothing.
TEST(TraversalCost, BvhCountsTheLeafItVisits) {
  const TestScene scene = random_soup(3, 48);
  auto bvh = make_accelerator("bvh2");
  bvh->build(scene.prims);
  const Bounds3 b = scene.prims.prim_bounds(0);
  Ray through;  // through the first triangle's box, so through the leaf's
  through.o = {0.5f * (b.lo.x + b.hi.x), 0.5f * (b.lo.y + b.hi.y), -5.0f};
  through.d = {0.0f, 0.0f, 1.0f};
  Ray away = through;
  away.d = {0.0f, 0.0f, -1.0f};
  TraversalCost c;
  Hit hit;
  bvh->intersect_cost(away, hit, c);
  EXPECT_EQ(c.nodes + c.prims, 0u);
  bvh->intersect_cost(through, hit, c);
  EXPECT_GE(c.nodes, 1u);
  EXPECT_GE(c.prims, 1u);
  EXPECT_LE(c.prims, 3u);
}

}  // namespace
}  // namespace penumbra::test
