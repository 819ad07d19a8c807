/// End-to-end tests of the pbrt importer: a scene written by hand in penumbra's JSON and in pbrt
/// form renders the same bits, and pbrt's image orientation is kept (an object on pbrt's +x side
/// of a plain LookAt camera is on the right of the picture).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "penumbra/scene/pbrt_parser.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

using test::region_mean;
using test::render_desc;
using test::scene_from_text;

// pbrt form: a plain LookAt camera, whose picture is the mirror image of penumbra's from the
// same numbers, so the importer mirrors the world (x -> -x).
const char* const kPbrt = R"(
LookAt 0 1 -4  0 1 0  0 1 0
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 32 "integer yresolution" 24
Sampler "independent" "integer pixelsamples" 4
PixelFilter "box"
Integrator "path" "integer maxdepth" 3
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [8 8 8]
  Shape "trianglemesh" "point3 P" [-0.5 2.5 -0.5  0.5 2.5 -0.5  0.5 2.5 0.5  -0.5 2.5 0.5]
    "integer indices" [0 1 2  0 2 3]
AttributeEnd
Material "diffuse" "rgb reflectance" [0.8 0.8 0.8]
Shape "trianglemesh" "point3 P" [-2 0 -2  2 0 -2  2 0 2  -2 0 2] "integer indices" [0 2 1  0 3 2]
Material "diffuse" "rgb reflectance" [0.8 0.1 0.1]
AttributeBegin
  Translate 0.7 0.5 0
  Shape "sphere" "float radius" 0.5
AttributeEnd
)";

// The same scene in penumbra's JSON, mirrored by hand: every shape gets the reflection
// scale(-1, 1, 1) after its own transform; the camera numbers are unchanged (x = 0).
const char* const kJson = R"({
  "camera": {"type": "pinhole", "position": [0, 1, -4], "look_at": [0, 1, 0], "up": [0, 1, 0],
             "vfov": 40},
  "render": {"resolution": [32, 24], "spp": 4, "sampler": "independent", "filter": "box:radius=0.5",
             "integrator": "path", "max_depth": 3},
  "materials": {"grey": {"type": "diffuse", "albedo": 0.5},
                "white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]},
                "red": {"type": "diffuse", "albedo": [0.8, 0.1, 0.1]}},
  "shapes": [
    {"type": "mesh", "material": "grey", "emission": [8, 8, 8],
     "positions": [[-0.5, 2.5, -0.5], [0.5, 2.5, -0.5], [0.5, 2.5, 0.5], [-0.5, 2.5, 0.5]],
     "indices": [[0, 1, 2], [0, 2, 3]], "transform": [{"scale": [-1, 1, 1]}]},
    {"type": "mesh", "material": "white",
     "positions": [[-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2]],
     "indices": [[0, 2, 1], [0, 3, 2]], "transform": [{"scale": [-1, 1, 1]}]},
    {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "red",
     "transform": [{"translate": [0.7, 0.5, 0]}, {"scale": [-1, 1, 1]}]}
  ]
})";

TEST(PbrtRender, SameSceneInJsonAndPbrtRendersTheSameBits) {
  const SceneDesc pbrt = parse_pbrt_scene(kPbrt, "test.pbrt", "");
  EXPECT_TRUE(pbrt.warnings.empty()) << pbrt.warnings.front();
  const RgbImage a = render_desc(pbrt, 2);
  const RgbImage b = render_desc(scene_from_text(kJson), 2);
  ASSERT_EQ(a.width(), 32);
  ASSERT_EQ(a.height(), 24);
  EXPECT_EQ(test::differing_values(a, b), 0u);
  // Not trivially equal: the light and the sphere are in the picture.
  EXPECT_GT(region_mean(a, 0, 0, 32, 24).r, 0.05f);
}

// The bundled Cornell box in both formats (scenes/cornell-box.pbrt is written from the JSON by
// scripts/cornell_to_pbrt.py) renders the same bits, given the same max depth.
TEST(PbrtRender, BundledCornellBoxInPbrtAndJsonRendersTheSameBits) {
  SceneDesc pbrt = test::bundled_scene("cornell-box.pbrt");
  SceneDesc json = test::bundled_scene("cornell-box.json");
  EXPECT_TRUE(pbrt.warnings.empty()) << pbrt.warnings.front();
  EXPECT_EQ(pbrt.render.spp, json.render.spp);
  EXPECT_EQ(pbrt.render.sampler, json.render.sampler);
  for (SceneDesc* s : {&pbrt, &json}) {
    s->render.width = s->render.height = 32;
    s->render.spp = 4;
    s->render.max_depth = 6;
  }
  const RgbImage a = render_desc(pbrt, 2), b = render_desc(json, 2);
  EXPECT_EQ(test::differing_values(a, b), 0u);
  EXPECT_GT(region_mean(a, 0, 0, 32, 32).r, 0.05f);
}

TEST(PbrtRender, AnObjectOnPbrtsPlusXSideIsOnTheRight) {
  SceneDesc s = load_scene(std::string(PENUMBRA_TEST_DATA) + "/pbrt/two-spheres.pbrt");
  s.render.spp = 4;
  const RgbImage img = render_desc(s, 2);
  // Redness (r - g) where each sphere is: the red one at pbrt x = +1 is on the right (pixels
  // 28-40 of 48), the grey metal one at x = -1 on the left (8-20). Mirrored, they would swap.
  const Rgb left = region_mean(img, 8, 10, 20, 22), right = region_mean(img, 28, 10, 40, 22);
  EXPECT_GT(right.r - right.g, 4.0f * std::max(0.0f, left.r - left.g) + 0.01f)
      << "left " << left.r << " " << left.g << ", right " << right.r << " " << right.g;
}

// A pbrt spot light on pbrt's +x side, aimed straight down, lights the right of the image (where
// pbrt puts it) and nothing on the left; a loopsubdiv octahedron in its cone renders lit, with
// finite values everywhere (limit normals as shading normals).
TEST(PbrtRender, SpotOnPbrtsPlusXSideLightsTheRightOfTheImage) {
  const SceneDesc s = parse_pbrt_scene(R"(
LookAt 0 5 0  0 0 0  0 0 1
Camera "perspective" "float fov" 60
Film "rgb" "integer xresolution" 32 "integer yresolution" 32
Sampler "independent" "integer pixelsamples" 4
Integrator "path" "integer maxdepth" 1
WorldBegin
LightSource "spot" "point3 from" [1.5 3 0] "point3 to" [1.5 0 0] "float coneangle" 20
  "float conedeltaangle" 5 "rgb I" [10 10 10]
Shape "trianglemesh" "point3 P" [-5 0 -5 5 0 -5 5 0 5 -5 0 5] "integer indices" [0 1 2 0 2 3]
AttributeBegin
Translate 1.5 0.4 0.6
Scale 0.3 0.3 0.3
Shape "loopsubdiv" "integer levels" 2 "point3 P" [1 0 0 -1 0 0 0 1 0 0 -1 0 0 0 1 0 0 -1]
  "integer indices" [0 2 4 2 1 4 1 3 4 3 0 4 2 0 5 1 2 5 3 1 5 0 3 5]
AttributeEnd
)",
                                       "spot.pbrt", "");
  const RgbImage img = render_desc(s, 2);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) ASSERT_TRUE(std::isfinite(img.at(x, y).g)) << x << "," << y;
  // pbrt x = 1.5 is at pixel 16 + 1.5 / (5 tan 30 deg) * 16 = 24; the lit disc has radius 3
  // tan 20 deg = 1.1, about 6 pixels.
  const Rgb right = region_mean(img, 21, 13, 27, 19), left = region_mean(img, 5, 13, 11, 19);
  EXPECT_GT(right.g, 0.05f);
  EXPECT_EQ(left.g, 0.0f);
}

// A sphere moving during the shutter (pbrt's ActiveTransform EndTime) and its JSON twin with
// "transform_end" and "shutter" render the same bits: the motion blur is the same.
TEST(PbrtRender, MovingSphereInPbrtAndJsonRendersTheSameBits) {
  std::string pbrt = kPbrt;
  const std::string sphere = "  Translate 0.7 0.5 0\n";
  ASSERT_NE(pbrt.find(sphere), std::string::npos);
  pbrt.replace(pbrt.find(sphere), sphere.size(),
               sphere + "  ActiveTransform EndTime\n  Translate -1.2 0 0\n  ActiveTransform All\n");
  const SceneDesc p = parse_pbrt_scene(pbrt, "moving.pbrt", "");
  EXPECT_TRUE(p.warnings.empty()) << p.warnings.front();
  nlohmann::json j = nlohmann::json::parse(kJson);
  j["camera"]["shutter"] = {0, 1};
  j["shapes"][2]["transform_end"] = nlohmann::json::parse(
      R"([{"translate": [-1.2, 0, 0]}, {"translate": [0.7, 0.5, 0]}, {"scale": [-1, 1, 1]}])");
  const RgbImage a = render_desc(p, 2), b = render_desc(scene_from_text(j.dump()), 2);
  EXPECT_EQ(test::differing_values(a, b), 0u);
  // The blur is there: the same scene with the sphere at rest differs.
  const RgbImage still = render_desc(scene_from_text(kJson), 2);
  EXPECT_GT(test::differing_values(a, still), 100u);
}

// pbrt's screenwindow: the right half of the default window, at half the width, is the right
// half of the full picture (the same rays, up to rounding), not the left.
TEST(PbrtRender, ScreenWindowShowsItsPartOfTheImagePlane) {
  const auto raycast = [](std::string text) {
    SceneDesc s = parse_pbrt_scene(text, "window.pbrt", "");
    s.render.integrator = "raycast";
    s.render.sampler = "regular";
    s.render.spp = 1;
    return render_desc(s, 2);
  };
  const RgbImage full = raycast(kPbrt);
  std::string half = kPbrt;
  const std::string cam = "\"float fov\" 40";
  half.replace(half.find(cam), cam.size(), cam + " \"float screenwindow\" [0 1.3333333 -1 1]");
  const std::string film = "\"integer xresolution\" 32";
  half.replace(half.find(film), film.size(), "\"integer xresolution\" 16");
  const RgbImage right = raycast(half);
  ASSERT_EQ(right.width(), 16);
  int same = 0, same_left = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 16; ++x) {
      const Rgb c = right.at(x, y), r = full.at(x + 16, y), l = full.at(x, y);
      same += std::abs(c.r - r.r) + std::abs(c.g - r.g) + std::abs(c.b - r.b) < 1e-3f;
      same_left += std::abs(c.r - l.r) + std::abs(c.g - l.g) + std::abs(c.b - l.b) < 1e-3f;
    }
  // All but pixels on an edge (a ray rounded to the other side) agree; the left half, which lacks
  // the red sphere (about 50 pixels), does not.
  EXPECT_GE(same, 16 * 24 - 8);
  EXPECT_LT(same_left, same - 40);
}

}  // namespace
}  // namespace penumbra
