// path's lanes (eight paths shaded at once) against its one-path-at-a-time code: the same bits on
// every image, for every strategy and parameter, and on a world whose primitives and lights take
// every scalar fallback of the lanes.
#include <gtest/gtest.h>

#include <string>

#include <fmt/format.h>

#include "penumbra/render/integrator/integrator_registry.h"
#include "penumbra/render/integrator/path_integrator.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// A room with every kind of primitive, emitter and material that the lanes hand to scalar code:
/// a quad wall, a glass sphere, a moving metal sphere, a textured mesh with shading normals, a
/// mirrored mesh (its front side flipped), a one-triangle light, a rectangular quad light
/// (sampled by solid angle), a sphere light and a two-sided parallelogram light of two
/// triangles, beside plain diffuse triangles (the floor, the ceiling, a box) that the lanes shade
/// themselves: 18 of its 28 primitives, so the lanes serve it.
std::string mixed_scene(const std::string& integrator, const std::string& sampler,
                        const std::string& camera = R"("pinhole")") {
  return fmt::format(R"({{
    "camera": {{"type": {}, "position": [0, 1, -3.5], "look_at": [0, 1, 0], "vfov": 60,
                "shutter": [0, 1]}},
    "render": {{"resolution": [20, 20], "spp": 16, "seed": 11, "integrator": "{}",
                "sampler": "{}"}},
    "materials": {{"white": {{"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
                   "red": {{"type": "diffuse", "albedo": [0.7, 0.1, 0.1]}},
                   "black": {{"type": "diffuse", "albedo": [0, 0, 0]}},
                   "glass": {{"type": "dielectric", "ior": 1.5}},
                   "metal": {{"type": "conductor", "roughness": 0.3,
                              "reflectance": [0.9, 0.8, 0.6]}},
                   "checker": {{"type": "diffuse",
                                "albedo": {{"type": "checkerboard", "scale": [4, 4],
                                            "colors": [[0.8, 0.8, 0.2], [0.1, 0.1, 0.5]]}}}}}},
    "shapes": [
      {{"type": "mesh", "material": "white",
        "positions": [[-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2]],
        "indices": [[0, 2, 1], [0, 3, 2]]}},
      {{"type": "mesh", "material": "white",
        "positions": [[-2, 2.5, -2], [2, 2.5, -2], [2, 2.5, 2], [-2, 2.5, 2]],
        "indices": [[0, 1, 2], [0, 2, 3]]}},
      {{"type": "quad", "origin": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 2.5, 0],
        "material": "red"}},
      {{"type": "mesh", "material": "red",
        "positions": [[-0.2, 0, -0.5], [0.4, 0, -0.5], [0.4, 0, 0.1], [-0.2, 0, 0.1],
                      [-0.2, 0.4, -0.5], [0.4, 0.4, -0.5], [0.4, 0.4, 0.1], [-0.2, 0.4, 0.1]],
        "indices": [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6],
                    [3, 0, 4], [3, 4, 7], [4, 5, 6], [4, 6, 7], [0, 3, 2], [0, 2, 1]]}},
      {{"type": "sphere", "center": [0.8, 0.5, 0.5], "radius": 0.5, "material": "glass"}},
      {{"type": "sphere", "center": [-0.6, 1.4, 0.8], "radius": 0.3, "material": "metal",
        "transform_end": [{{"translate": [0.4, 0.1, 0]}}]}},
      {{"type": "mesh", "material": "checker",
        "positions": [[-2, 0, -2], [-2, 0, 2], [-2, 2.5, 2], [-2, 2.5, -2]],
        "normals": [[1, 0.2, 0], [1, 0, 0.1], [1, -0.1, 0], [1, 0, 0]],
        "indices": [[0, 1, 2], [0, 2, 3]]}},
      {{"type": "mesh", "material": "white", "transform": [{{"scale": [-1, 1, 1]}}],
        "positions": [[-2, 0, -2], [-2, 0, 2], [-2, 2.5, 2], [-2, 2.5, -2]],
        "indices": [[0, 2, 1], [0, 3, 2]]}},
      {{"type": "mesh", "material": "black", "emission": [6, 5, 4],
        "positions": [[-0.5, 2.49, 0], [0.5, 2.49, 0], [0, 2.49, 0.6]],
        "indices": [[0, 2, 1]]}},
      {{"type": "quad", "origin": [-1.5, 2.45, -1], "edge1": [0.4, 0, 0], "edge2": [0, 0, 0.4],
        "material": "black", "emission": [3, 3, 8]}},
      {{"type": "sphere", "center": [-1, 0.3, 0.8], "radius": 0.15, "material": "black",
        "emission": [10, 6, 2]}},
      {{"type": "mesh", "material": "black", "emission": [2, 4, 2], "two_sided": true,
        "positions": [[1.2, 1.5, 1], [1.8, 1.5, 1], [1.8, 2.0, 1.2], [1.2, 2.0, 1.2]],
        "indices": [[0, 1, 2], [0, 2, 3]]}}
    ]
  }})",
                     camera, integrator, sampler);
}

/// A room with a box, lit by one emitter of five triangles: a parallelogram pair and three
/// triangles of different sizes, so the lanes pick among four units by their own search (one
/// light, all of its units planar). 16 of its 21 primitives are plain diffuse triangles.
std::string one_light_scene(const std::string& integrator) {
  return fmt::format(R"({{
    "camera": {{"type": "pinhole", "position": [0, 1, -3.5], "look_at": [0, 1, 0], "vfov": 60}},
    "render": {{"resolution": [20, 20], "spp": 16, "seed": 5, "integrator": "{}"}},
    "materials": {{"white": {{"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
                   "green": {{"type": "diffuse", "albedo": [0.1, 0.6, 0.2]}}}},
    "shapes": [
      {{"type": "mesh", "material": "white",
        "positions": [[-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2]],
        "indices": [[0, 2, 1], [0, 3, 2]]}},
      {{"type": "mesh", "material": "green",
        "positions": [[-2, 0, 2], [2, 0, 2], [2, 2.5, 2], [-2, 2.5, 2]],
        "indices": [[0, 1, 2], [0, 2, 3]]}},
      {{"type": "mesh", "material": "white",
        "positions": [[-0.2, 0, -0.5], [0.4, 0, -0.5], [0.4, 0, 0.1], [-0.2, 0, 0.1],
                      [-0.2, 0.4, -0.5], [0.4, 0.4, -0.5], [0.4, 0.4, 0.1], [-0.2, 0.4, 0.1]],
        "indices": [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6],
                    [3, 0, 4], [3, 4, 7], [4, 5, 6], [4, 6, 7], [0, 3, 2], [0, 2, 1]]}},
      {{"type": "mesh", "material": "white", "emission": [5, 4, 3],
        "positions": [[-1, 2.4, 0], [-0.5, 2.4, 0], [-0.5, 2.4, 0.5], [-1, 2.4, 0.5],
                      [0, 2.4, 0], [0.6, 2.4, 0], [0, 2.4, 0.2],
                      [0.8, 2.3, -1], [1.0, 2.3, -1], [0.8, 2.3, -0.9],
                      [-1.5, 1.5, 1.9], [-1.2, 1.5, 1.9], [-1.5, 1.9, 1.9]],
        "indices": [[0, 1, 2], [0, 2, 3], [4, 5, 6], [7, 8, 9], [10, 11, 12]]}}
    ]
  }})",
                     integrator);
}

/// `spec` with one more parameter.
std::string with(const std::string& spec, const std::string& param) {
  return spec + (spec.find(':') == std::string::npos ? ":" : ",") + param;
}

RgbImage render_json(const std::string& json, int threads) {
  return test::render_desc(test::scene_from_text(json), threads);
}

/// Whether `spec` on the scene `desc` shades by lanes.
bool uses_lanes(const SceneDesc& desc, const std::string& spec) {
  const World world(desc, "bvh");
  const auto integrator = make_integrator(spec, world, desc.render);
  return dynamic_cast<const PathIntegrator&>(*integrator).uses_lanes();
}

bool uses_lanes(const std::string& json, const std::string& spec) {
  return uses_lanes(test::scene_from_text(json), spec);
}

/// Sum of every channel of every pixel.
double total(const RgbImage& img) {
  double s = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) s += img.at(x, y).r + img.at(x, y).g + img.at(x, y).b;
  return s;
}

/// The mixed scene under a sky, with a point light, a spot and the sun.
std::string lamps_scene(const std::string& integrator) {
  std::string json = mixed_scene(integrator, "sobol");
  json.replace(json.find(R"("sampler": "sobol")"), std::string(R"("sampler": "sobol")").size(),
               R"("sampler": "sobol", "background": [0.2, 0.3, 0.5])");
  json.replace(json.find(R"("shapes": [)"), std::string(R"("shapes": [)").size(),
               R"("lights": [{"type": "point", "position": [0.5, 2, 0], "intensity": [2, 2, 2]},
                             {"type": "spot", "position": [-1, 2.2, -1], "look_at": [0, 0, 1],
                              "intensity": [4, 3, 2], "cone_angle": 40},
                             {"type": "directional", "direction": [0.2, -1, 0.3],
                              "irradiance": [1, 0.9, 0.8]}],
                  "shapes": [)");
  return json;
}

TEST(PathLanes, ServeWhereMeasuredFasterOrWhenAsked) {
  // lanes=auto: plain diffuse triangles lit by an area light of planar units.
  EXPECT_TRUE(uses_lanes(test::bundled_scene("cornell-box.json"), "path"));
  EXPECT_TRUE(uses_lanes(one_light_scene("path"), "path"));
  EXPECT_FALSE(uses_lanes(one_light_scene("path"), "path:lanes=off"));
  // A rectangle and a sphere among the lights, or a sky and lamps: only when asked.
  EXPECT_FALSE(uses_lanes(mixed_scene("path", "sobol"), "path"));
  EXPECT_TRUE(uses_lanes(mixed_scene("path", "sobol"), "path:lanes=on"));
  EXPECT_FALSE(uses_lanes(lamps_scene("path"), "path"));
  EXPECT_TRUE(uses_lanes(lamps_scene("path"), "path:lanes=on"));
  // Metal where the room was white: 2 plain diffuse triangles of 21.
  std::string glossy = one_light_scene("path");
  glossy.replace(glossy.find(R"("type": "diffuse", "albedo": [0.8, 0.8, 0.8])"),
                 std::string(R"("type": "diffuse", "albedo": [0.8, 0.8, 0.8])").size(),
                 R"("type": "conductor", "roughness": 0.3, "reflectance": [0.9, 0.9, 0.9])");
  EXPECT_FALSE(uses_lanes(glossy, "path"));
}

// The sky (rays that leave, weighted against its samples), delta lights (no MIS weight) and the
// sun's unbounded shadow rays: the same bits.
TEST(PathLanes, SkyAndDeltaLightsRenderTheSameBitsAsOnePathAtATime) {
  for (const char* spec : {"path", "path:strategy=nee", "path:strategy=bsdf"}) {
    const RgbImage lanes = render_json(lamps_scene(with(spec, "lanes=on")), 2);
    const RgbImage scalar = render_json(lamps_scene(with(spec, "lanes=off")), 1);
    EXPECT_GT(total(lanes), 1.0) << spec;
    EXPECT_EQ(test::differing_values(lanes, scalar), 0u) << spec;
  }
}

class PathLanesBits : public testing::TestWithParam<const char*> {};

// Every fallback (scalar interactions, emission weights, scalar light samples) and every lane
// computation give the scalar code's floats: the images are equal value for value.
TEST_P(PathLanesBits, MixedWorldRendersTheSameBitsAsOnePathAtATime) {
  const std::string spec = GetParam();
  for (const char* sampler : {"sobol", "independent"}) {
    const RgbImage lanes = render_json(mixed_scene(with(spec, "lanes=on"), sampler), 2);
    const RgbImage scalar = render_json(mixed_scene(with(spec, "lanes=off"), sampler), 1);
    EXPECT_GT(total(lanes), 1.0) << sampler;  // something was lit
    EXPECT_EQ(test::differing_values(lanes, scalar), 0u) << spec << " with " << sampler;
  }
}

INSTANTIATE_TEST_SUITE_P(Parameters, PathLanesBits,
                         testing::Values("path", "path:strategy=nee", "path:strategy=bsdf",
                                         "path:max_depth=1", "path:max_depth=0",
                                         "path:rr_exponent=1", "path:rr_exponent=0.7,rr_depth=1",
                                         "path:light_sampler=uniform"));

// One light of several units: the lanes' own pick among them, against the scalar code.
TEST(PathLanes, OneLightOfManyUnitsRendersTheSameBitsAsOnePathAtATime) {
  for (const char* spec : {"path", "path:strategy=nee"}) {
    const RgbImage lanes = render_json(one_light_scene(spec), 2);  // lanes=auto serves it
    const RgbImage scalar = render_json(one_light_scene(with(spec, "lanes=off")), 1);
    EXPECT_GT(total(lanes), 1.0);
    EXPECT_EQ(test::differing_values(lanes, scalar), 0u) << spec;
  }
}

// A camera other than the pinhole (whose rays the lanes finish themselves) and a moving
// sphere (its interaction at each ray's time): the same bits.
TEST(PathLanes, ThinLensCameraAndMotionBlurRenderTheSameBitsAsOnePathAtATime) {
  for (const char* camera :
       {R"("pinhole")", R"("thin_lens", "aperture_radius": 0.1, "focus_distance": 3.5)"}) {
    const RgbImage lanes = render_json(mixed_scene("path:lanes=on", "sobol", camera), 2);
    const RgbImage scalar = render_json(mixed_scene("path:lanes=off", "sobol", camera), 1);
    EXPECT_GT(total(lanes), 1.0) << camera;
    EXPECT_EQ(test::differing_values(lanes, scalar), 0u) << camera;
  }
}

// The Cornell box (plain triangles, one parallelogram light): the same bits, and paths far longer
// than the window of samples in flight (no roulette, 300 bounces) keep the film's order.
TEST(PathLanes, CornellBoxRendersTheSameBitsAsOnePathAtATime) {
  for (const char* spec : {"path", "path:rr_depth=1000,max_depth=300"}) {
    const RgbImage lanes = test::cornell_box(spec, 24, 8, 2);
    const RgbImage scalar = test::cornell_box(with(spec, "lanes=off"), 24, 8, 1);
    EXPECT_GT(total(lanes), 1.0);
    EXPECT_EQ(test::differing_values(lanes, scalar), 0u) << spec;
  }
}

}  // namespace
}  // namespace penumbra
