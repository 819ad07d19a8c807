// The cost view, raycast:mode=cost: the structures' own counts per pixel, as raw means and as the
// heat map with its colour bar.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/render/integrator/raycast_integrator.h"
#include "penumbra/render/render_job.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// Three primitives (a floor quad, a sphere, a quad light) seen from the front, 40 x 20.
std::string scene_json(const std::string& accel, const std::string& integrator, int spp = 2) {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 1, -3], "look_at": [0, 0.3, 0], "vfov": 50}},
    "render": {{"resolution": [40, 20], "spp": {}, "seed": 4, "accel": "{}",
                "integrator": "{}"}},
    "materials": {{"white": {{"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}}}},
    "shapes": [
      {{"type": "quad", "origin": [-2, 0, -2], "edge1": [0, 0, 4], "edge2": [4, 0, 0],
        "material": "white"}},
      {{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "white"}},
      {{"type": "quad", "origin": [-0.5, 2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1],
        "material": "white", "emission": [5, 5, 5]}}
    ]
  }})",
                     spp, accel, integrator);
}

RgbImage render(const std::string& json, RenderStats* stats = nullptr) {
  RenderJob job(test::scene_from_text(json));
  const RenderStats s = job.run();
  if (stats) *stats = s;
  return job.film->resolve();
}

/// Rendering `json` fails with an error whose message holds `fragment`.
void expect_render_error(const std::string& json, const std::string& fragment) {
  try {
    render(json);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

// Brute force tests every primitive for every ray in its one leaf: 3 tests and 1 node per pixel,
// whatever the ray sees; the raw view writes exactly these means.
TEST(CostView, BruteForceCountsEveryPrimitiveInEveryPixel) {
  const RgbImage prims = render(scene_json("brute", "raycast:mode=cost,cost=prims,raw"));
  const RgbImage nodes = render(scene_json("brute", "raycast:mode=cost,cost=nodes,raw"));
  const RgbImage both = render(scene_json("brute", "raycast:mode=cost,raw"));
  for (int y = 0; y < prims.height(); ++y)
    for (int x = 0; x < prims.width(); ++x) {
      EXPECT_NEAR(prims.at(x, y).r, 3.0f, 1e-5f);
      EXPECT_NEAR(nodes.at(x, y).g, 1.0f, 1e-6f);
      EXPECT_NEAR(both.at(x, y).b, 4.0f, 1e-5f);
    }
}

// A BVH over a row of 16 spheres tests fewer primitives than brute force's 16 on average, and
// its counts vary over the image (rays that miss the row's box count nothing).
TEST(CostView, BvhCountsLessThanBruteForceAndVaries) {
  std::string spheres;
  for (int i = 0; i < 16; ++i)
    spheres += fmt::format(R"({}{{"type": "sphere", "center": [{}, 0.5, 0], "radius": 0.1,
                               "material": "white"}})",
                           i ? "," : "", -1.5 + 0.2 * i);
  const std::string json = R"({
    "camera": {"type": "pinhole", "position": [0, 1, -3], "look_at": [0, 0.3, 0], "vfov": 50},
    "render": {"resolution": [40, 20], "spp": 2, "accel": "bvh2",
               "integrator": "raycast:mode=cost,cost=prims,raw"},
    "materials": {"white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
    "shapes": [)" + spheres + "]}";
  const RgbImage bvh = render(json);
  double sum = 0, lo = 1e9, hi = 0;
  for (int y = 0; y < bvh.height(); ++y)
    for (int x = 0; x < bvh.width(); ++x) {
      const double v = bvh.at(x, y).r;
      sum += v, lo = std::min(lo, v), hi = std::max(hi, v);
    }
  EXPECT_LT(sum / (bvh.width() * bvh.height()), 16.0);
  EXPECT_LT(lo, hi);
}

// The heat map: the largest mean is white (the top of the map) unless a scale is given, the
// colour bar runs from black at the bottom to white at the top after a black column, and the
// summary's note states the scale.
TEST(CostView, HeatMapWithColourBarAndScale) {
  RenderStats stats;
  const RgbImage img = render(scene_json("brute", "raycast:mode=cost"), &stats);
  const int w = img.width(), h = img.height();
  // Every picture pixel is 4 = the largest mean: white; the bar is 4 pixels wide at w = 40.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w - 5; ++x) EXPECT_NEAR(img.at(x, y).g, 1.0f, 1e-5f);
    EXPECT_EQ(img.at(w - 5, y).r, 0.0f);
  }
  EXPECT_EQ(img.at(w - 1, h - 1).r, 0.0f);  // bar bottom: black
  EXPECT_NEAR(img.at(w - 1, 0).b, 1.0f, 1e-6f);  // bar top: white
  EXPECT_LT(img.at(w - 1, h / 2).b, img.at(w - 1, 0).b);
  EXPECT_NE(stats.note.find("to 4 (top)"), std::string::npos) << stats.note;
  // With scale=8 the means sit halfway up the map, the colour of the bar's middle.
  const RgbImage half = render(scene_json("brute", "raycast:mode=cost,scale=8"));
  const Rgb mid = heat_colour(0.5f);
  EXPECT_NEAR(half.at(3, 3).r, mid.r, 1e-5f);
  EXPECT_NEAR(half.at(3, 3).g, mid.g, 1e-5f);
  EXPECT_NEAR(half.at(3, 3).b, mid.b, 1e-5f);
}

// The colour map rises in brightness from black to white and clamps outside [0, 1].
TEST(CostView, ColourMapIsMonotoneInBrightness) {
  const auto lum = [](Rgb c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
  float prev = -1.0f;
  for (int i = 0; i <= 100; ++i) {
    const float l = lum(heat_colour(float(i) / 100.0f));
    EXPECT_GT(l, prev) << i;
    prev = l;
  }
  EXPECT_EQ(lum(heat_colour(-1.0f)), 0.0f);
  EXPECT_EQ(lum(heat_colour(std::nanf(""))), 0.0f);
  EXPECT_EQ(lum(heat_colour(7.0f)), lum(heat_colour(1.0f)));
}

// rays=bounce and rays=shadow count the secondary query from each camera hit, nothing for a
// camera ray that misses. Brute force makes the counts exact: a bounce ray tests all 3
// primitives in its one leaf; a shadow ray (1 node) stops at the first primitive in its way, so
// floor points the sphere shades test 2 (the floor, then the sphere), lit ones all 3 (the light
// itself, which the ray stops short of, included).
TEST(CostView, BounceAndShadowRaysCountTheQueriesFromTheCameraHits) {
  const int spp = 4;
  const RgbImage bounce = render(scene_json("brute", "raycast:mode=cost,rays=bounce,raw", spp));
  const RgbImage nodes =
      render(scene_json("brute", "raycast:mode=cost,rays=shadow,cost=nodes,raw", spp));
  const RgbImage prims =
      render(scene_json("brute", "raycast:mode=cost,rays=shadow,cost=prims,raw", spp));
  int missed = 0, all_hit = 0, stopped_early = 0;
  for (int y = 0; y < bounce.height(); ++y)
    for (int x = 0; x < bounce.width(); ++x) {
      // Each sample adds 4 (1 node + 3 tests) or 0.
      const float k = bounce.at(x, y).r * spp / 4.0f;
      EXPECT_NEAR(k, std::round(k), 1e-4f) << x << ", " << y;
      missed += k < 0.5f;
      all_hit += k > spp - 0.5f;
      // The shadow rays: one node each, and from 1 to 3 tests each.
      const float n = nodes.at(x, y).r * spp, p = prims.at(x, y).r * spp;
      EXPECT_NEAR(n, std::round(n), 1e-4f) << x << ", " << y;
      EXPECT_LE(n, std::round(k) + 1e-4f);
      EXPECT_GE(p, n - 1e-4f);
      EXPECT_LE(p, 3 * n + 1e-4f);
      stopped_early += n > 0.5f && p < 3 * n - 0.5f;
    }
  EXPECT_GT(missed, 0);
  EXPECT_GT(all_hit, bounce.width() * bounce.height() / 4);
  EXPECT_GT(stopped_early, 0);
}

// rays=shadow needs a light; an unknown rays names the valid ones.
TEST(CostView, ShadowRaysNeedALightAndUnknownRaysAreAnError) {
  std::string dark = scene_json("bvh", "raycast:mode=cost,rays=shadow");
  dark.replace(dark.find(R"(, "emission": [5, 5, 5])"), 23, "");
  expect_render_error(dark, "needs a light");
  expect_render_error(scene_json("bvh", "raycast:mode=cost,rays=bogus"),
                      "valid: camera, bounce, shadow");
}

TEST(CostView, UnknownCostIsAnErrorListingTheValidOnes) {
  expect_render_error(scene_json("bvh", "raycast:mode=cost,cost=bogus"),
                      "valid: nodes, prims, both");
  EXPECT_ANY_THROW(render(scene_json("bvh", "raycast:mode=normal,cost=nodes")));  // unused key
}

}  // namespace
}  // namespace penumbra
