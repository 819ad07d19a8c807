/// `penumbra convert`'s scene writer: a scene read from pbrt-v4 or JSON, written as JSON with PLY
/// meshes and read back, has the same meshes bit for bit and renders the same bits.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../image/temp_dir.h"
#include "penumbra/scene/pbrt_parser.h"
#include "penumbra/scene/scene_writer.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

using test::differing_values;
using test::render_desc;

// Every file of write_scene_json written under `dir`; returns the scene file's path.
std::string write_all(const test::TempDir& dir, const SceneDesc& scene) {
  const std::vector<SceneFile> files = write_scene_json(scene, "scene.json", "scene-meshes");
  for (const SceneFile& f : files) {
    const std::filesystem::path p = dir.path() / f.path;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << f.bytes;
  }
  return dir.file("scene.json");
}

// A pbrt scene with a textured mesh with normals and uvs, a sphere, an area light, a
// checkerboard, a point light, two instances of an object, a moving sphere (so the camera has a
// shutter) and an off-centre screen window.
const char* const kPbrt = R"(
LookAt 0 1 -4  0 1 0  0 1 0
Camera "perspective" "float fov" 45 "float screenwindow" [-1.2 1.4 -1 1.1]
Film "rgb" "integer xresolution" 40 "integer yresolution" 30
Sampler "independent" "integer pixelsamples" 4
Integrator "path" "integer maxdepth" 4
WorldBegin
LightSource "point" "point3 from" [1 3 -1] "rgb I" [4 4 4]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [6 6 6]
  Shape "trianglemesh" "point3 P" [-0.5 2.5 -0.5  0.5 2.5 -0.5  0.5 2.5 0.5  -0.5 2.5 0.5]
    "integer indices" [0 1 2  0 2 3]
AttributeEnd
Texture "checks" "spectrum" "checkerboard" "float uscale" 4 "float vscale" 4
  "rgb tex1" [0.8 0.8 0.8] "rgb tex2" [0.2 0.3 0.4]
Material "diffuse" "texture reflectance" "checks"
Shape "trianglemesh" "point3 P" [-2 0 -2  2 0 -2  2 0 2  -2 0 2] "integer indices" [0 2 1  0 3 2]
  "point2 uv" [0 0 1 0 1 1 0 1] "normal N" [0 1 0  0 1 0  0 1 0  0 1 0]
ObjectBegin "pyramid"
  Material "conductor" "float roughness" 0.1
  Shape "trianglemesh" "point3 P" [0 0 0  0.3 0 0  0 0 0.3  0 0.4 0]
    "integer indices" [0 2 1  0 1 3  0 3 2  1 2 3]
ObjectEnd
AttributeBegin
  Translate -0.8 0 0
  ObjectInstance "pyramid"
AttributeEnd
AttributeBegin
  Translate -0.3 0 0.5
  Rotate 30 0 1 0
  ObjectInstance "pyramid"
AttributeEnd
Material "dielectric" "float eta" 1.5
AttributeBegin
  Translate 0.7 0.5 0
  ActiveTransform EndTime
  Translate 0 0.3 0
  ActiveTransform All
  Shape "sphere" "float radius" 0.5
AttributeEnd
)";

TEST(ConvertRoundTrip, PbrtSceneWrittenAsJsonRendersTheSameBits) {
  const SceneDesc pbrt = parse_pbrt_scene(kPbrt, "test.pbrt", "");
  ASSERT_EQ(pbrt.instances.size(), 2u);
  EXPECT_TRUE(pbrt.warnings.empty()) << pbrt.warnings.front();
  ASSERT_TRUE(pbrt.camera.json().contains("shutter"));
  ASSERT_TRUE(pbrt.camera.json().contains("screen_window"));
  const test::TempDir dir;
  const SceneDesc json = load_scene(write_all(dir, pbrt));
  ASSERT_EQ(json.shapes.size(), pbrt.shapes.size());
  ASSERT_EQ(json.objects.size(), 1u);
  ASSERT_EQ(json.instances.size(), 2u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "scene-meshes" / "shape-1.ply"));
  // Meshes bit for bit, and transforms number for number.
  for (size_t i = 0; i < pbrt.shapes.size(); ++i) {
    EXPECT_EQ(json.shapes[i].to_world.matrix().m, pbrt.shapes[i].to_world.matrix().m) << i;
    ASSERT_EQ(json.shapes[i].to_world_end.has_value(), pbrt.shapes[i].to_world_end.has_value());
    if (pbrt.shapes[i].to_world_end) {
      EXPECT_EQ(json.shapes[i].to_world_end->matrix().m, pbrt.shapes[i].to_world_end->matrix().m);
    }
    EXPECT_EQ(json.shapes[i].material, pbrt.shapes[i].material);
    EXPECT_EQ(json.shapes[i].emission.has_value(), pbrt.shapes[i].emission.has_value());
    const auto* a = std::get_if<TriangleMesh>(&pbrt.shapes[i].geometry);
    const auto* b = std::get_if<TriangleMesh>(&json.shapes[i].geometry);
    ASSERT_EQ(a == nullptr, b == nullptr) << i;
    if (!a) continue;
    EXPECT_EQ(a->positions, b->positions);
    EXPECT_EQ(a->normals, b->normals);
    EXPECT_EQ(a->uvs, b->uvs);
    EXPECT_EQ(a->indices, b->indices);
  }
  const RgbImage before = render_desc(pbrt, 2), after = render_desc(json, 2);
  EXPECT_EQ(differing_values(before, after), 0u);
  EXPECT_GT(test::region_mean(before, 0, 0, 40, 30).r, 0.05f);  // not trivially equal
  EXPECT_EQ(json.camera.json().at("shutter"), pbrt.camera.json().at("shutter"));
  EXPECT_EQ(json.camera.json().at("screen_window"), pbrt.camera.json().at("screen_window"));
}

// A bundled JSON scene survives the round trip too (inline meshes become PLY files).
TEST(ConvertRoundTrip, BundledJsonSceneRendersTheSameBits) {
  SceneDesc original = test::bundled_scene("cornell-box.json");
  original.render.width = 32, original.render.height = 32, original.render.spp = 2;
  const test::TempDir dir;
  const SceneDesc copy = load_scene(write_all(dir, original));
  EXPECT_EQ(copy.render.integrator, original.render.integrator);
  EXPECT_EQ(copy.render.seed, original.render.seed);
  EXPECT_EQ(copy.materials.size(), original.materials.size());
  EXPECT_EQ(differing_values(render_desc(original, 2), render_desc(copy, 2)), 0u);
}

}  // namespace
}  // namespace penumbra
