// Every registered 2D structure against brute force on many random rays and inputs: the first
// hit must be the same shape at the same parameter, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "penumbra/accel2d/object_bsp.h"
#include "penumbra/accel2d/random_segments.h"
#include "penumbra/accel2d/registry2d.h"
#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"

namespace penumbra::lab2d {
namespace {

/// Random rays: origins in the scene's box grown by a third, uniform directions; every fourth
/// aimed exactly at a segment endpoint, every eighth axis-aligned, some starting on a segment,
/// some grazing along a segment's line.
std::vector<Ray2> random_rays(const Scene2D& scene, size_t count, uint64_t seed) {
  Pcg32 rng(seed, 7);
  const Box2d b = scene.bounds();
  const Vec2d ext = b.extent();
  std::vector<Ray2> rays;
  for (size_t i = 0; i < count; ++i) {
    Ray2 r;
    r.o = {b.lo.x - ext.x / 3 + rng.next_double() * ext.x * 5 / 3,
           b.lo.y - ext.y / 3 + rng.next_double() * ext.y * 5 / 3};
    const double angle = 2 * std::numbers::pi * rng.next_double();
    r.d = {std::cos(angle), std::sin(angle)};
    const Shape2& s = scene.shapes[rng.next_bounded(uint32_t(scene.shapes.size()))];
    if (i % 4 == 1) r.d = s.v[rng.next_bounded(uint32_t(s.v.size()))] - r.o;
    if (i % 8 == 2) r.d = i % 16 == 2 ? Vec2d{r.d.x, 0} : Vec2d{0, r.d.y};
    if (i % 8 == 3) r.o = lerp(s.v[0], s.v[1], rng.next_double());  // starts on a shape
    if (i % 16 == 5) r.tmax = rng.next_double() * (ext.x + ext.y);
    if (i % 8 == 6) {
      // Grazing: along a shape's edge line, turned by up to 1e-6 rad, from behind its start.
      const Vec2d e = s.v[1] - s.v[0];
      const double turn =
          (rng.next_double() - 0.5) * std::pow(10.0, -6.0 - 6.0 * rng.next_double());
      r.o = s.v[0] - e * (0.5 + 3 * rng.next_double());
      r.d = {e.x * std::cos(turn) - e.y * std::sin(turn),
             e.x * std::sin(turn) + e.y * std::cos(turn)};
    }
    if (r.d.x == 0 && r.d.y == 0) r.d = {1, 0};
    rays.push_back(r);
  }
  return rays;
}

/// Checks every registered structure that takes the scene against brute force.
void expect_all_agree(const Scene2D& scene, size_t rays, uint64_t seed) {
  Brute2D brute;
  brute.build(scene);
  const auto all_rays = random_rays(scene, rays, seed);
  for (const auto& info : accel2d_list()) {
    if (info.segments_only && !scene.all_segments()) continue;
    auto accel = make_accel2d(info.name);
    accel->build(scene);
    size_t hits = 0;
    for (size_t i = 0; i < all_rays.size(); ++i) {
      const Hit2 want = brute.shoot(all_rays[i]), got = accel->shoot(all_rays[i]);
      hits += want.hit();
      ASSERT_EQ(got.id, want.id) << info.name << " " << scene.source << " ray " << i;
      ASSERT_EQ(got.t, want.t) << info.name << " " << scene.source << " ray " << i;
    }
    EXPECT_GT(hits, rays / 10) << info.name << ": too few hits to test anything";
  }
}

TEST(Accel2D, EveryStructureMatchesBruteForceOnRandomSegments) {
  for (size_t n : {1, 2, 5, 30, 300, 2000})
    for (uint64_t seed : {1, 2, 3}) expect_all_agree(random_segments(n, seed), 2000, seed * 31 + n);
}

TEST(Accel2D, EveryStructureMatchesBruteForceOnTheCombAndAxisAlignedInputs) {
  expect_all_agree(comb_segments(60), 4000, 5);
  // Axis-aligned segments on shared lines (collinear but disjoint): stored at BSP nodes.
  std::string text;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      text += fmt::format("{} {} {} {}\n{} {} {} {}\n", i * 3, j * 3, i * 3 + 2, j * 3, i * 3 + 0.5,
                          j * 3 + 1, i * 3 + 0.5, j * 3 + 2);
  expect_all_agree(parse_scene2d(text, "aligned"), 4000, 6);
}

TEST(Accel2D, ObjectBspMatchesBruteForceOnPolygonsAndSegments) {
  // Triangles and squares in a lattice with a few segments between them.
  std::string text;
  Pcg32 rng(3, 3);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const double x = i * 4 + rng.next_double(), y = j * 4 + rng.next_double();
      if ((i + j) % 3 == 0)
        text += fmt::format("poly {} {} {} {} {} {}\n", x, y, x + 2, y, x + 1, y + 2.5);
      else if ((i + j) % 3 == 1)
        text +=
            fmt::format("poly {} {} {} {} {} {} {} {}\n", x, y, x + 2, y, x + 2, y + 2, x, y + 2);
      else
        text += fmt::format("{} {} {} {}\n", x, y, x + 2.5, y + 1.5);
    }
  expect_all_agree(parse_scene2d(text, "objects"), 4000, 8);
}

TEST(Accel2D, ObjectBspLeavesHoldAtMostOneObject) {
  // Disjoint convex objects always have a separating edge line (separating axis theorem), so the
  // rule never gives up: on polygons, on random segments, and on the comb (whose own lines all
  // leave the other segments on one side or cut them).
  std::string text;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      text += fmt::format("poly {} {} {} {} {} {}\n", i * 3, j * 3, i * 3 + 2,
                          j * 3 + 0.5 * (i % 3), i * 3 + 1, j * 3 + 2);
  for (const Scene2D& scene :
       {parse_scene2d(text, "triangles"), random_segments(400, 2), comb_segments(60)}) {
    auto bsp = make_accel2d("objects");
    bsp->build(scene);
    const Stats2D st = bsp->stats();
    EXPECT_GE(st.leaves, scene.shapes.size()) << scene.source;
    const auto& tree = static_cast<const ObjectBsp&>(*bsp).tree();
    for (const LineNode& n : tree.nodes) {
      if (!n.leaf()) continue;
      EXPECT_LE(n.count, 1u) << scene.source;
    }
  }
}

TEST(Accel2D, RegistryRejectsUnknownNamesAndParameters) {
  EXPECT_THROW(make_accel2d("octree"), Error);
  EXPECT_THROW(make_accel2d("bsp:order=best"), Error);
  EXPECT_THROW(make_accel2d("quadtree:leafs=3"), Error);
  try {
    make_accel2d("nope");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("quadtree"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::lab2d
