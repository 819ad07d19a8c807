/// glTF cameras, KHR_lights_punctual lights and materials as penumbra records, and the defaults
/// of a file that has no camera or no light.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gltf_test_util.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::has_warning;
using test::load_gltf;

void expect_vec(const SceneParams& p, const char* key, Vec3 want) {
  const Vec3 v = p.get_vec3(key, Vec3(-99.0f));
  EXPECT_NEAR(v.x, want.x, 1e-5) << key;
  EXPECT_NEAR(v.y, want.y, 1e-5) << key;
  EXPECT_NEAR(v.z, want.z, 1e-5) << key;
}

TEST(GltfView, CameraLooksDownItsLocalMinusZ) {
  GltfBuilder b;
  // A camera at (0, 1, 5) turned 90 degrees about +y: local -z becomes world -x.
  const double h = std::sqrt(0.5);
  const SceneDesc s = load_gltf(b.doc(
      {{"scenes", {{{"nodes", {0, 1}}}}},
       {"nodes",
        {{{"mesh", 0}}, {{"camera", 0}, {"translation", {0, 1, 5}}, {"rotation", {0, h, 0, h}}}}},
       {"cameras",
        {{{"type", "perspective"},
          {"perspective", {{"yfov", 0.5}, {"aspectRatio", 2.0}, {"znear", 0.1}}}}}},
       {"meshes", {test::triangle_mesh(b)}}}));
  EXPECT_EQ(s.camera.type(), "pinhole");
  expect_vec(s.camera, "position", Vec3(0, 1, 5));
  expect_vec(s.camera, "look_at", Vec3(-1, 1, 5));
  expect_vec(s.camera, "up", Vec3(0, 1, 0));
  EXPECT_NEAR(s.camera.get_float("vfov", 0), 0.5 * 180 / 3.14159265358979, 1e-4);
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 320);
  EXPECT_FALSE(has_warning(s, "default camera"));
}

TEST(GltfView, OrthographicCameraFallsBackToTheDefaultWithAWarning) {
  GltfBuilder b;
  const SceneDesc s = load_gltf(
      b.doc({{"scenes", {{{"nodes", {0, 1}}}}},
             {"nodes", {{{"mesh", 0}}, {{"camera", 0}}}},
             {"cameras",
              {{{"type", "orthographic"},
                {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 9}}}}}},
             {"meshes", {test::triangle_mesh(b)}}}));
  EXPECT_TRUE(has_warning(s, "model.gltf:/cameras/0: camera type \"orthographic\" not supported"));
  EXPECT_TRUE(has_warning(s, "default camera"));
}

TEST(GltfView, DefaultCameraAndEnvironmentFrameAnUnlitScene) {
  GltfBuilder b;
  const SceneDesc s = load_gltf(b.doc({{"scenes", {{{"nodes", {0}}}}},
                                       {"nodes", {{{"mesh", 0}, {"translation", {10, 0, 0}}}}},
                                       {"meshes", {test::triangle_mesh(b)}}}));
  // Bounds (10, 0, 0)-(11, 1, 0): centre (10.5, 0.5, 0), radius sqrt(0.5).
  expect_vec(s.camera, "look_at", Vec3(10.5f, 0.5f, 0));
  const Vec3 eye = s.camera.get_vec3("position", Vec3(0.0f));
  const double dist =
      std::sqrt(std::pow(eye.x - 10.5, 2) + std::pow(eye.y - 0.5, 2) + eye.z * eye.z);
  EXPECT_NEAR(dist, std::sqrt(0.5) / std::sin(20 * 3.14159265358979 / 180), 1e-4);
  EXPECT_GT(eye.z, 0.0f);
  EXPECT_GT(eye.y, 0.5f);
  EXPECT_EQ(s.camera.get_float("vfov", 0), 40.0f);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type(), "environment");
  EXPECT_EQ(s.lights[0].get_float("radiance", 0), 1.0f);
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  EXPECT_EQ(s.render.integrator, "path");
}

TEST(GltfView, PunctualLightsMapToPointAndDirectional) {
  GltfBuilder b;
  const double h = std::sqrt(0.5);
  const json lights = {
      {"lights",
       {{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 4}},
        {{"type", "directional"}, {"intensity", 3}},
        {{"type", "spot"}, {"intensity", 2}, {"range", 10}, {"spot", {{"outerConeAngle", 0.5}}}},
        {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.2}}}}}}};
  const auto node = [](int light, json extra) {
    extra["extensions"] = {{"KHR_lights_punctual", {{"light", light}}}};
    return extra;
  };
  const SceneDesc s = load_gltf(b.doc(
      {{"extensionsUsed", {"KHR_lights_punctual"}},
       {"extensions", {{"KHR_lights_punctual", lights}}},
       {"scenes", {{{"nodes", {0, 1, 2, 3, 4}}}}},
       {"nodes",
        {{{"mesh", 0}},
         node(0, {{"translation", {1, 2, 3}}}),
         node(1, {{"rotation", {-h, 0, 0, h}}}),  // -90 degrees about x: -z -> -y (straight down)
         node(2, {{"translation", {0, 5, 0}}}),
         node(3, {{"rotation", {-h, 0, 0, h}}})}},
       {"meshes", {test::triangle_mesh(b)}}}));
  ASSERT_EQ(s.lights.size(), 4u);
  EXPECT_EQ(s.lights[0].type(), "point");
  expect_vec(s.lights[0], "position", Vec3(1, 2, 3));
  const Rgb i = s.lights[0].get_rgb("intensity", Rgb(0.0f));
  EXPECT_FLOAT_EQ(i.r, 4.0f);
  EXPECT_FLOAT_EQ(i.g, 2.0f);
  EXPECT_FLOAT_EQ(i.b, 1.0f);
  EXPECT_EQ(s.lights[1].type(), "directional");
  expect_vec(s.lights[1], "direction", Vec3(0, -1, 0));
  EXPECT_FLOAT_EQ(s.lights[1].get_rgb("irradiance", Rgb(0.0f)).g, 3.0f);
  // Spot: a cone about the node's -z, outerConeAngle 0.5 rad and innerConeAngle 0 (defaults:
  // pi/4 and 0).
  EXPECT_EQ(s.lights[2].type(), "spot");
  expect_vec(s.lights[2], "position", Vec3(0, 5, 0));
  expect_vec(s.lights[2], "direction", Vec3(0, 0, -1));
  EXPECT_NEAR(s.lights[2].get_float("cone_angle", 0), 0.5 * 180 / std::numbers::pi, 1e-4);
  EXPECT_NEAR(s.lights[2].get_float("cone_delta", 0), 0.5 * 180 / std::numbers::pi, 1e-4);
  EXPECT_FLOAT_EQ(s.lights[2].get_rgb("intensity", Rgb(0.0f)).r, 2.0f);
  expect_vec(s.lights[3], "direction", Vec3(0, -1, 0));
  EXPECT_NEAR(s.lights[3].get_float("cone_angle", 0), 45.0, 1e-4);
  EXPECT_NEAR(s.lights[3].get_float("cone_delta", 0), 45.0 - 0.2 * 180 / std::numbers::pi, 1e-4);
  EXPECT_FALSE(has_warning(s, "mapped to a point light"));
  EXPECT_TRUE(has_warning(s, "lights/2/range: range ignored"));
  EXPECT_FALSE(has_warning(s, "not supported"));
}

TEST(GltfView, MaterialsMapToDiffuseConductorDielectricAndEmission) {
  GltfBuilder b;
  const json tri = test::triangle_mesh(b);
  json meshes = json::array();
  for (int m = 0; m < 5; ++m) {
    json mesh = tri;
    mesh["primitives"][0]["material"] = m;
    meshes.push_back(mesh);
  }
  json none = tri;  // no material: the glTF default material
  meshes.push_back(none);
  const json materials = {
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.2, 0.1, 1}}, {"metallicFactor", 0}}}},
      {{"pbrMetallicRoughness",
        {{"baseColorFactor", {0.9, 0.8, 0.5, 1}},
         {"metallicFactor", 0.7},
         {"roughnessFactor", 0.4}}}},
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0}}},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
         {"KHR_materials_ior", {{"ior", 1.33}}}}}},
      {{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0.5}}},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}}}},
      {{"emissiveFactor", {1, 0.5, 0}},
       {"doubleSided", true},
       {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}}}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}}};
  json nodes = json::array(), roots = json::array();
  for (int m = 0; m < 6; ++m) nodes.push_back({{"mesh", m}}), roots.push_back(m);
  const SceneDesc s = load_gltf(b.doc({{"scenes", {{{"nodes", roots}}}},
                                       {"nodes", nodes},
                                       {"materials", materials},
                                       {"meshes", meshes}}));
  ASSERT_EQ(s.materials.size(), 6u);
  const auto params = [&](size_t i) { return s.materials[i].params; };
  EXPECT_EQ(params(0).type(), "diffuse");
  EXPECT_FLOAT_EQ(params(0).get_rgb("albedo", Rgb(0.0f)).g, 0.2f);
  EXPECT_EQ(params(1).type(), "conductor");
  EXPECT_FLOAT_EQ(params(1).get_rgb("reflectance", Rgb(0.0f)).b, 0.5f);
  EXPECT_FLOAT_EQ(params(1).get_float("roughness", 0), 0.4f);
  EXPECT_TRUE(has_warning(s, "/materials/1/pbrMetallicRoughness/metallicFactor: metallic"));
  EXPECT_EQ(params(2).type(), "dielectric");
  EXPECT_FLOAT_EQ(params(2).get_float("ior", 0), 1.33f);
  EXPECT_EQ(params(3).type(), "rough_dielectric");
  EXPECT_FLOAT_EQ(params(3).get_float("ior", 0), 1.5f);
  EXPECT_FLOAT_EQ(params(3).get_float("roughness", 0), 0.5f);
  EXPECT_EQ(params(5).type(), "conductor");  // the spec's default: white, metallic 1, rough 1
  EXPECT_EQ(s.materials[5].name, "gltf/default");
  EXPECT_FLOAT_EQ(params(5).get_float("roughness", 0), 1.0f);
  ASSERT_EQ(s.shapes.size(), 6u);
  EXPECT_EQ(s.shapes[4].material, "gltf/4");
  ASSERT_TRUE(s.shapes[4].emission.has_value());
  EXPECT_FLOAT_EQ(s.shapes[4].emission->r, 4.0f);
  EXPECT_FLOAT_EQ(s.shapes[4].emission->g, 2.0f);
  EXPECT_TRUE(s.shapes[4].two_sided_emission);
  EXPECT_FALSE(s.shapes[0].emission.has_value());
  EXPECT_EQ(s.shapes[5].material, "gltf/default");
  EXPECT_TRUE(has_warning(s, "/materials/4: textures are not read (metallicRoughnessTexture)"));
  // Emission lights the scene: no default environment.
  EXPECT_TRUE(s.lights.empty());
}

TEST(GltfView, UnsupportedExtensionsAreNamed) {
  GltfBuilder b;
  const SceneDesc s = load_gltf(b.doc({{"extensionsUsed", {"KHR_texture_transform", "EXT_foo"}},
                                       {"extensionsRequired", {"EXT_foo"}},
                                       {"scenes", {{{"nodes", {0}}}}},
                                       {"nodes", {{{"mesh", 0}}}},
                                       {"meshes", {test::triangle_mesh(b)}}}));
  EXPECT_TRUE(has_warning(s, "/extensionsUsed/0: extension KHR_texture_transform not supported"));
  EXPECT_TRUE(has_warning(s, "/extensionsRequired/0: required extension EXT_foo not supported"));
  EXPECT_EQ(s.shapes.size(), 1u);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

TEST(GltfView, CommittedGltfAndGlbOfTheSameSceneAgree) {
  const std::string dir = std::string(PENUMBRA_TEST_DATA) + "/gltf/";
  const SceneDesc a = load_scene(dir + "boxes.gltf");
  const SceneDesc b = load_scene(dir + "boxes.glb");
  EXPECT_TRUE(a.warnings.empty()) << a.warnings.front();
  ASSERT_EQ(a.shapes.size(), 3u);
  ASSERT_EQ(b.shapes.size(), 3u);
  for (size_t i = 0; i < 3; ++i)
    EXPECT_EQ(std::get<TriangleMesh>(a.shapes[i].geometry).positions,
              std::get<TriangleMesh>(b.shapes[i].geometry).positions);
  EXPECT_EQ(a.shapes[1].name, "gold box");
  EXPECT_EQ(a.materials[1].params.type(), "conductor");
  ASSERT_EQ(a.lights.size(), 1u);
  EXPECT_EQ(a.lights[0].type(), "point");
  EXPECT_EQ(a.render.width, 640);
  EXPECT_EQ(a.render.height, 427);
  EXPECT_EQ(a.camera.get_vec3("position", Vec3(0.0f)).z, 6.0f);
}

}  // namespace
}  // namespace penumbra
