/// End-to-end test of the glTF importer: a scene written as glTF (a camera node, a box mesh placed
/// by two nodes, an emissive lamp, a floor) and by hand in penumbra's JSON renders the same bits.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../scene/gltf_test_util.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

using nlohmann::json;
using test::region_mean;
using test::render_desc;
using test::scene_from_text;

// A unit cube centred at the origin: 8 corners, 12 triangles.
const std::vector<float> kCube = {-0.5f, -0.5f, -0.5f, 0.5f,  -0.5f, -0.5f, 0.5f, 0.5f,
                                  -0.5f, -0.5f, 0.5f,  -0.5f, -0.5f, -0.5f, 0.5f, 0.5f,
                                  -0.5f, 0.5f,  0.5f,  0.5f,  0.5f,  -0.5f, 0.5f, 0.5f};
const std::vector<uint32_t> kCubeIdx = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                        3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
const std::vector<float> kLamp = {-0.5f, 2.5f, -0.5f, 0.5f,  2.5f, -0.5f,
                                  0.5f,  2.5f, 0.5f,  -0.5f, 2.5f, 0.5f};
const std::vector<float> kFloor = {-3, 0, -3, 3, 0, -3, 3, 0, 3, -3, 0, 3};
const std::vector<uint32_t> kQuadIdx = {0, 1, 2, 0, 2, 3};

json prim(test::GltfBuilder& b, const std::vector<float>& p, const std::vector<uint32_t>& i,
          int material) {
  return {{"attributes", {{"POSITION", b.floats(p, "VEC3", 3)}}},
          {"indices", b.indices(i)},
          {"material", material}};
}

// Translations are exact in float: the JSON loader reads "translate" as float, the glTF importer
// keeps glTF's doubles, so 0.8 would differ in the last bits of a few pixels (14 values of 2304).
SceneDesc gltf_scene() {
  test::GltfBuilder b;
  const json doc =
      b.doc({{"scenes", {{{"nodes", {0, 1, 2, 3, 4}}}}},
             {"nodes",
              {{{"camera", 0}, {"translation", {0, 1, 5}}},
               {{"mesh", 0}, {"translation", {-0.75, 0.5, 0}}},
               {{"mesh", 0}, {"translation", {0.75, 0.5, 0}}},
               {{"mesh", 1}},
               {{"mesh", 2}}}},
             {"cameras",
              {{{"type", "perspective"},
                {"perspective",
                 {{"yfov", 0.6981317007977318}, {"aspectRatio", 4.0 / 3}, {"znear", 0.1}}}}}},
             {"materials",
              {{{"pbrMetallicRoughness",
                 {{"baseColorFactor", {0.8, 0.1, 0.1, 1}}, {"metallicFactor", 0}}}},
               {{"pbrMetallicRoughness",
                 {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0}}},
                {"emissiveFactor", {1, 1, 1}},
                {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 8}}}}}},
               {{"pbrMetallicRoughness",
                 {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0}}}}}},
             {"meshes",
              {{{"primitives", {prim(b, kCube, kCubeIdx, 0)}}},
               {{"primitives", {prim(b, kLamp, kQuadIdx, 1)}}},
               {{"primitives", {prim(b, kFloor, kQuadIdx, 2)}}}}}});
  return parse_gltf_scene(doc.dump(), "box.gltf", "");
}

json points(const std::vector<float>& p) {
  json out = json::array();
  for (size_t i = 0; i < p.size(); i += 3) out.push_back({p[i], p[i + 1], p[i + 2]});
  return out;
}

json triangles(const std::vector<uint32_t>& idx) {
  json out = json::array();
  for (size_t i = 0; i < idx.size(); i += 3) out.push_back({idx[i], idx[i + 1], idx[i + 2]});
  return out;
}

// The same scene in penumbra's JSON.
SceneDesc json_scene() {
  const json box = {{"type", "mesh"},
                    {"material", "red"},
                    {"positions", points(kCube)},
                    {"indices", triangles(kCubeIdx)}};
  const json doc = {
      {"camera",
       {{"type", "pinhole"},
        {"position", {0, 1, 5}},
        {"look_at", {0, 1, 4}},
        {"up", {0, 1, 0}},
        {"vfov", 40}}},
      {"render", {{"resolution", {32, 24}}, {"spp", 4}, {"integrator", "path"}, {"max_depth", 3}}},
      {"materials",
       {{"red", {{"type", "diffuse"}, {"albedo", {0.8, 0.1, 0.1}}}},
        {"grey", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}}},
        {"white", {{"type", "diffuse"}, {"albedo", {0.8, 0.8, 0.8}}}}}},
      {"objects", {{"box", {{"shapes", {box}}}}}},
      {"shapes",
       {{{"type", "instance"},
         {"object", "box"},
         {"transform", {{{"translate", {-0.75, 0.5, 0}}}}}},
        {{"type", "instance"}, {"object", "box"}, {"transform", {{{"translate", {0.75, 0.5, 0}}}}}},
        {{"type", "mesh"},
         {"material", "grey"},
         {"emission", {8, 8, 8}},
         {"positions", points(kLamp)},
         {"indices", triangles(kQuadIdx)}},
        {{"type", "mesh"},
         {"material", "white"},
         {"positions", points(kFloor)},
         {"indices", triangles(kQuadIdx)}}}}};
  return scene_from_text(doc.dump());
}

TEST(GltfRender, SameSceneInJsonAndGltfRendersTheSameBits) {
  SceneDesc g = gltf_scene();
  EXPECT_TRUE(g.warnings.empty()) << g.warnings.front();
  EXPECT_EQ(g.instances.size(), 2u);
  const SceneDesc j = json_scene();
  g.render = j.render;  // the glTF file has no render settings; compare the same ones
  const RgbImage a = render_desc(g, 2);
  const RgbImage b = render_desc(j, 2);
  ASSERT_EQ(a.width(), 32);
  ASSERT_EQ(a.height(), 24);
  EXPECT_EQ(test::differing_values(a, b), 0u);
  // Not trivially equal: the lit boxes are in the picture, red on both sides of the centre.
  const Rgb left = region_mean(a, 4, 8, 14, 20), right = region_mean(a, 18, 8, 28, 20);
  EXPECT_GT(left.r, 2 * left.g);
  EXPECT_GT(right.r, 2 * right.g);
}

}  // namespace
}  // namespace penumbra
