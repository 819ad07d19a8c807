#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render_helpers.h"

namespace penumbra {
namespace {

using test::render_desc;
using test::scene_from_text;

// A diffuse floor seen from straight above, lit by a point light above the centre: the centre
// pixel's radiance is (albedo / pi) I cos / r^2 with cos = 1.
TEST(Whitted, DiffuseUnderPointLightMatchesTheAnalyticRadiance) {
  const auto desc = scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [0, 10, 0], "look_at": [0, 0, 0], "up": [0, 0, 1],
               "vfov": 0.01},
    "render": {"resolution": [5, 5], "spp": 1, "integrator": "whitted"},
    "materials": {"grey": {"type": "diffuse", "albedo": [0.5, 0.25, 1.0]}},
    "lights": [{"type": "point", "position": [0, 4, 0], "intensity": [8, 8, 8]}],
    "shapes": [{"type": "quad", "origin": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0],
                "material": "grey"}]})");
  const RgbImage img = render_desc(desc);
  const Rgb c = img.at(2, 2);
  const float expected = 8.0f / 16.0f / std::numbers::pi_v<float>;
  EXPECT_NEAR(c.r, 0.5f * expected, 1e-4f);
  EXPECT_NEAR(c.g, 0.25f * expected, 1e-4f);
  EXPECT_NEAR(c.b, 1.0f * expected, 1e-4f);
}

// A mirror facing the camera shows an emitter behind the camera, scaled by its reflectance;
// the emitter's back side, seen directly, is black (one-sided emission).
TEST(Whitted, MirrorReflectsEmitterAndEmissionIsOneSided) {
  const auto desc = scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [0, 0, 0], "look_at": [0, 0, 1], "vfov": 1},
    "render": {"resolution": [3, 3], "spp": 1, "integrator": "whitted", "max_depth": 2},
    "materials": {"m": {"type": "mirror", "reflectance": [0.5, 0.8, 1.0]},
                  "black": {"type": "diffuse", "albedo": 0}},
    "shapes": [
      {"type": "quad", "origin": [-1, -1, 5], "edge1": [2, 0, 0], "edge2": [0, 2, 0], "material": "m"},
      {"type": "quad", "origin": [-1, -1, -1], "edge1": [2, 0, 0], "edge2": [0, 2, 0],
       "material": "black", "emission": [2, 3, 4]}]})");
  const Rgb c = render_desc(desc).at(1, 1);
  // The camera ray hits the mirror, reflects back to -z and sees the emitter's front (+z) side.
  EXPECT_NEAR(c.r, 1.0f, 1e-5f);
  EXPECT_NEAR(c.g, 2.4f, 1e-5f);
  EXPECT_NEAR(c.b, 4.0f, 1e-5f);

  auto flipped = desc;  // a camera behind the emitter sees its back side
  flipped.camera = SceneParams(
      nlohmann::json{
          {"type", "pinhole"}, {"position", {0, 0, -3}}, {"look_at", {0, 0, 0}}, {"vfov", 1}},
      "test.json", "/camera");
  EXPECT_EQ(render_desc(flipped).at(1, 1), Rgb(0.0f));
}

// The Cornell box: the light seen directly has exactly its radiance, the red wall is on the left
// of the image and the green wall on the right.
TEST(Whitted, CornellBoxLightWallsAndOrientation) {
  auto desc = test::bundled_scene("cornell-box.json");
  desc.render.width = desc.render.height = 64;
  desc.render.spp = 1;
  desc.render.integrator = "whitted";
  const RgbImage img = render_desc(desc);
  // The light is near the top centre of the image (rows 8 to 10 at 64x64).
  int light_pixels = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 64; ++x)
      if (img.at(x, y) == Rgb(17, 12, 4)) {
        ++light_pixels;
        EXPECT_TRUE(x > 20 && x < 44 && y >= 7 && y <= 11) << x << "," << y;
      }
  EXPECT_GT(light_pixels, 20);
  const Rgb left = img.at(3, 32), right = img.at(60, 32);
  EXPECT_GT(left.r, 2.0f * left.g);    // red wall
  EXPECT_GT(right.g, 2.0f * right.r);  // green wall
}

// Renders are bit-identical whatever the thread count.
TEST(Whitted, DeterministicAcrossThreadCounts) {
  auto desc = test::bundled_scene("whitted.json");
  desc.render.width = 96;
  desc.render.height = 64;
  desc.render.spp = 2;
  const RgbImage one = render_desc(desc, 1);
  const RgbImage two = render_desc(desc, 2);
  ASSERT_EQ(one.width(), two.width());
  EXPECT_TRUE(one == two);
}

// Self-intersection avoidance: a sphere far from the origin, lit from the camera's side, has no
// shadow acne: every pixel that sees the sphere's lit side is lit.
TEST(Whitted, NoShadowAcneFarFromTheOrigin) {
  const auto desc = scene_from_text(R"({
    "camera": {"type": "pinhole", "position": [100000, 100000, 99990], "look_at": [100000, 100000, 100000], "vfov": 20},
    "render": {"resolution": [48, 48], "spp": 1, "integrator": "whitted"},
    "materials": {"w": {"type": "diffuse", "albedo": 0.8}},
    "lights": [{"type": "point", "position": [100000, 100000, 99980], "intensity": [100, 100, 100]}],
    "shapes": [{"type": "sphere", "center": [100000, 100000, 100000], "radius": 1, "material": "w"}]})");
  const RgbImage img = render_desc(desc);
  int hit = 0, dark = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const float dx = x + 0.5f - 24, dy = y + 0.5f - 24;
      if (dx * dx + dy * dy > 11 * 11) continue;  // inside the sphere's disc (radius 13.7 px)
      ++hit;
      if (!(img.at(x, y).r > 0.0f)) ++dark;
    }
  EXPECT_GT(hit, 350);
  EXPECT_EQ(dark, 0);
}

}  // namespace
}  // namespace penumbra
