/// Scenes at the edges of float: what the renderer refuses at load (with the file, the shape and
/// the value) and what it renders exactly, whatever the structure.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "render_helpers.h"

namespace penumbra::test {
namespace {

/// The message World's construction throws for `shapes` (JSON array items), or "no error".
std::string world_error(const std::string& shapes) {
  const SceneDesc desc = scene_from_text(fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0], "vfov": 40}},
    "render": {{"resolution": [8, 8], "spp": 1, "integrator": "raycast"}},
    "materials": {{"m": {{"type": "diffuse"}}}},
    "shapes": [{}]
  }})",
                                                     shapes));
  try {
    World world(desc, "bvh");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ExtremeScene, CoordinatesBeyondTheLimitAreRefusedWithFileShapeAndValue) {
  const std::string tri = world_error(
      R"({"type": "mesh", "material": "m", "positions": [[0, 0, 0], [1, 0, 0], [0, 2e12, 0]],
          "indices": [[0, 1, 2]]})");
  EXPECT_NE(tri.find("test.json:/shapes/0"), std::string::npos) << tri;
  EXPECT_NE(tri.find("triangle 0"), std::string::npos) << tri;
  EXPECT_NE(tri.find("2e+12"), std::string::npos) << tri;
  EXPECT_NE(tri.find("1e+12"), std::string::npos) << tri;  // the limit is named

  // A sphere whose box passes the limit, and a quad (the second shape: its own path).
  const std::string sphere =
      world_error(R"({"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 3e12})");
  EXPECT_NE(sphere.find("/shapes/0"), std::string::npos) << sphere;
  EXPECT_NE(sphere.find("3e+12"), std::string::npos) << sphere;
  const std::string quad = world_error(
      R"({"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1},
         {"type": "quad", "material": "m", "origin": [0, 0, 0], "edge1": [2e12, 0, 0],
          "edge2": [0, 1, 0]})");
  EXPECT_NE(quad.find("/shapes/1"), std::string::npos) << quad;
  EXPECT_NE(quad.find("quad"), std::string::npos) << quad;

  // A transform that overflows a vertex to infinity.
  const std::string scaled = world_error(
      R"({"type": "mesh", "material": "m", "positions": [[0, 0, 0], [1, 0, 0], [0, 1e20, 0]],
          "indices": [[0, 1, 2]], "transform": [{"scale": [1, 1e20, 1]}]})");
  EXPECT_NE(scaled.find("inf"), std::string::npos) << scaled;
}

TEST(ExtremeScene, TooSmallASceneIsRefusedWithItsExtent) {
  const std::string tiny = world_error(
      R"({"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1e-12})");
  EXPECT_NE(tiny.find("test.json:/shapes"), std::string::npos) << tiny;
  EXPECT_NE(tiny.find("extent"), std::string::npos) << tiny;
  EXPECT_NE(tiny.find("1e-10"), std::string::npos) << tiny;
}

TEST(ExtremeScene, ScenesAtTheLimitAreAccepted) {
  EXPECT_EQ(world_error(R"({"type": "mesh", "material": "m",
      "positions": [[-1e12, -1e12, 0], [1e12, -1e12, 0], [0, 1e12, 0]], "indices": [[0, 1, 2]]})"),
            "no error");
  EXPECT_EQ(world_error(R"({"type": "sphere", "material": "m", "center": [0, 0, 0],
      "radius": 5e11})"),
            "no error");
}

/// A diffuse sphere on a floor lit by a directional light (with its shadow), at scale s and
/// offset by `offset` along x: camera and geometry scaled, so the image stays the same.
RgbImage scaled_scene(double s, double offset, const std::string& accel) {
  const auto v = [&](double x, double y, double z) {
    return fmt::format("[{:.9g}, {:.9g}, {:.9g}]", x * s + offset, y * s, z * s);
  };
  SceneDesc desc = scene_from_text(fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": {}, "look_at": {}, "vfov": 40}},
    "render": {{"resolution": [24, 24], "spp": 1, "integrator": "whitted", "accel": "{}"}},
    "materials": {{"m": {{"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}}}},
    "lights": [{{"type": "directional", "direction": [-2, -3, 1], "irradiance": 2}}],
    "shapes": [{{"type": "sphere", "material": "m", "center": {}, "radius": {:.9g}}},
               {{"type": "quad", "material": "m", "origin": {}, "edge1": [{:.9g}, 0, 0],
                 "edge2": [0, 0, {:.9g}]}}]
  }})",
                                               v(0, 0, -5), v(0, 0, 0), accel, v(0, 0, 0), s,
                                               v(-3, -1, -3), 6 * s, 6 * s));
  return render_desc(desc, 1);
}

TEST(ExtremeScene, TheSameImageFrom1em10To1e11AndFarFromTheOrigin) {
  const RgbImage ref = scaled_scene(1.0, 0.0, "brute");
  double ref_sum = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) ref_sum += ref.at(x, y).g;
  ASSERT_GT(ref_sum, 1.0);  // the sphere and the floor are lit
  for (const double s : {1e-10, 1e-5, 1e5, 1e11}) {
    for (const std::string accel : {"brute", "bvh", "kdtree", "grid"}) {
      SCOPED_TRACE(fmt::format("scale {:g}, {}", s, accel));
      const RgbImage img = scaled_scene(s, 0.0, accel);
      // The same picture up to rounding: every pixel within 1e-3 relative of scale 1 (the
      // image depends on ratios only; float rounding at any scale is relative).
      int bad = 0;
      for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x)
          bad += std::fabs(img.at(x, y).g - ref.at(x, y).g) > 1e-3f * (1.0f + ref.at(x, y).g);
      EXPECT_LE(bad, 2) << "pixels that differ from the scene at scale 1";
    }
  }
  // Far from the origin (1e6 scene units away: an ulp there is 0.06) the picture stays.
  const RgbImage far = scaled_scene(1.0, 1e6, "bvh");
  double far_sum = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) far_sum += far.at(x, y).g;
  EXPECT_NEAR(far_sum, ref_sum, 0.05 * ref_sum);
}

// Two facing mirrors and 30,000 bounces: the recursive integrators refuse the depth instead of
// overflowing the call stack; path (iterative) renders it.
TEST(ExtremeScene, RecursionDeeperThanSupportedIsRefused) {
  const auto desc = [](const std::string& integrator) {
    SceneDesc d = scene_from_text(R"({
      "camera": {"type": "pinhole", "position": [0, 0, 0.5], "look_at": [0, 0, -1], "vfov": 20},
      "render": {"resolution": [4, 4], "spp": 1, "max_depth": 30000},
      "materials": {"mirror": {"type": "mirror"}},
      "lights": [{"type": "point", "position": [0, 0, 0], "intensity": 1}],
      "shapes": [{"type": "quad", "material": "mirror", "origin": [-5, -5, -1],
                  "edge1": [10, 0, 0], "edge2": [0, 10, 0]},
                 {"type": "quad", "material": "mirror", "origin": [-5, -5, 1],
                  "edge1": [0, 10, 0], "edge2": [10, 0, 0]}]
    })");
    d.render.integrator = integrator;
    return d;
  };
  for (const char* name : {"whitted", "distribution"}) {
    try {
      render_desc(desc(name), 1);
      ADD_FAILURE() << name << " accepted max_depth 30000";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("30000"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("1000"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(render_desc(desc("path"), 1));
}

}  // namespace
}  // namespace penumbra::test
