/// Tests of the texture syntax of scene files: colours or texture objects in material parameters,
/// and errors that name the file and JSON path of the bad value.
#include "penumbra/render/texture/texture_params.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "penumbra/core/error.h"
#include "penumbra/render/material/material_registry.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

// The material {"type": "diffuse", "albedo": ALBEDO} at /materials/floor of scene.json.
std::unique_ptr<Material> diffuse_with(const std::string& albedo) {
  return make_material(
      SceneParams(nlohmann::json::parse(R"({"type": "diffuse", "albedo": )" + albedo + "}"),
                  "scene.json", "/materials/floor"));
}

// The message of the InputError that making that material throws ("" and a failure when none).
std::string error_of(const std::string& albedo) {
  try {
    diffuse_with(albedo);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << albedo;
  return "";
}

TEST(TextureParams, ColoursAndTextureObjects) {
  SurfaceInteraction si;
  MaterialScratch scratch;
  si.uv = {0.1f, 0.1f};
  EXPECT_EQ(diffuse_with("0.25")->albedo(), Rgb(0.25f));
  EXPECT_EQ(diffuse_with("[0.1, 0.2, 0.3]")->albedo(), Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(diffuse_with(R"({"type": "constant", "color": 0.5})")->albedo(), Rgb(0.5f));
  // Checkerboard: default colours black and white, scale as one number or [su, sv].
  auto m = diffuse_with(R"({"type": "checkerboard", "scale": [10, 1]})");
  si.uv = {0.05f, 0.1f};
  EXPECT_EQ(m->at(si, scratch).albedo(), Rgb(0.0f));  // cell (0, 0): even
  si.uv = {0.15f, 0.1f};
  EXPECT_EQ(m->at(si, scratch).albedo(), Rgb(1.0f));  // cell (1, 0): odd
  // World-space (solid) checkerboard.
  m = diffuse_with(
      R"({"type": "checkerboard", "scale": 1, "space": "world", "colors": [0.2, 0.4]})");
  si.p = {1.5f, 0.5f, 0.5f};
  EXPECT_EQ(m->at(si, scratch).albedo(), Rgb(0.4f));
  // Zone plate: default centre (0.5, 0.5) and colours black, white.
  m = diffuse_with(R"({"type": "zone_plate", "k": 1000})");
  si.uv = {0.5f, 0.5f};
  EXPECT_EQ(m->at(si, scratch).albedo(), Rgb(1.0f));
  m = diffuse_with(R"({"type": "zone_plate", "k": 1000, "center": [0, 0], "colors": [0.3, 0.6]})");
  si.uv = {0.0f, 0.0f};
  EXPECT_EQ(m->at(si, scratch).albedo(), Rgb(0.6f));
}

TEST(TextureParams, ErrorsNameTheJsonPath) {
  const std::string at = "scene.json:/materials/floor/albedo";
  EXPECT_EQ(error_of(R"({"type": "zoneplate", "k": 1})"),
            at + "/type: unknown texture type 'zoneplate' (valid: constant, checkerboard, "
                 "zone_plate, image)");
  EXPECT_EQ(error_of(R"({"k": 1})"), at + ": missing required key \"type\"");
  EXPECT_EQ(error_of(R"({"type": "zone_plate"})"), at + ": missing required key \"k\"");
  EXPECT_EQ(error_of(R"({"type": "checkerboard"})"), at + ": missing required key \"scale\"");
  EXPECT_EQ(error_of(R"({"type": "constant"})"), at + ": missing required key \"color\"");
  EXPECT_EQ(error_of(R"({"type": "checkerboard", "scale": 4, "colors": [[0, 0, 0], [1, 1]]})"),
            at + "/colors/1: expected a number or an array of 3 numbers");
  EXPECT_EQ(error_of(R"({"type": "checkerboard", "scale": 4, "colors": [[0, 0, 1.5], 1]})"),
            at + "/colors/0: must lie in [0, 1]");
  EXPECT_EQ(error_of(R"({"type": "checkerboard", "scale": 4, "colors": [0, 1, 0]})"),
            at + "/colors: expected an array of 2 colours, got 3");
  EXPECT_EQ(error_of(R"({"type": "checkerboard", "scale": 4, "colors": "red"})"),
            at + "/colors: expected an array");
  EXPECT_EQ(error_of(R"({"type": "checkerboard", "scale": [4, 0]})"),
            at + "/scale: must be a positive number");
  EXPECT_EQ(error_of(R"({"type": "checkerboard", "scale": [4, 4], "space": "world"})"),
            at + "/scale: expected a number");
  EXPECT_EQ(error_of(R"({"type": "checkerboard", "scale": 4, "space": "xyz"})"),
            at + "/space: unknown space 'xyz' (valid: uv, world)");
  EXPECT_EQ(error_of(R"({"type": "zone_plate", "k": -1})"), at + "/k: must be a positive number");
  EXPECT_EQ(error_of(R"({"type": "zone_plate", "k": 1, "center": [0.5]})"),
            at + "/center: expected an array of 2 numbers");
  EXPECT_EQ(error_of(R"({"type": "constant", "color": -0.5})"), at + "/color: must lie in [0, 1]");
  EXPECT_EQ(error_of("1.5"), at + ": must lie in [0, 1]");
  EXPECT_EQ(error_of("[1, 2]"), at + ": expected a number or an array of 3 numbers");
  // A misspelt key of the texture is reported at its own path.
  const std::string unknown = error_of(R"({"type": "zone_plate", "k": 1, "centre": [0, 0]})");
  EXPECT_EQ(unknown.rfind(at + "/centre: unknown key", 0), 0u) << unknown;
}

// Through the whole scene loader: the error names the scene file and the material's JSON path;
// a mirror's reflectance takes textures as well.
TEST(TextureParams, SceneFilesReportTextureErrors) {
  const std::string scene = R"({
    "camera": {"type": "pinhole", "position": [0, 0, -1], "look_at": [0, 0, 0]},
    "materials": {"plate": {"type": "MATERIAL"}},
    "shapes": [{"type": "quad", "origin": [1, 1, 0], "edge1": [-2, 0, 0], "edge2": [0, -2, 0],
                "material": "plate"}]})";
  auto world_error = [&](const std::string& material) {
    std::string s = scene;
    s.replace(s.find(R"("type": "MATERIAL")"), 18, material);
    try {
      World(test::scene_from_text(s), "bvh");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(
      world_error(
          R"("type": "diffuse", "albedo": {"type": "zone_plate", "k": 100, "colors": [0, 2]})"),
      "test.json:/materials/plate/albedo/colors/1: must lie in [0, 1]");
  EXPECT_EQ(world_error(R"("type": "mirror", "reflectance": {"type": "checker", "scale": 2})"),
            "test.json:/materials/plate/reflectance/type: unknown texture type 'checker' (valid: "
            "constant, checkerboard, zone_plate, image)");
  EXPECT_EQ(world_error(R"("type": "mirror", "reflectance": {"type": "checkerboard", "scale": 2})"),
            "no error");
}

// The texture examples of docs/scene-format.md (the block after "### Textures") make materials.
TEST(TextureParams, DocumentedExamplesLoad) {
  std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/docs/scene-format.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t section = doc.find("### Textures");
  ASSERT_NE(section, std::string::npos);
  const size_t begin = doc.find("```text\n", section) + 8, end = doc.find("```", begin);
  const auto materials = nlohmann::json::parse("{" + doc.substr(begin, end - begin) + "}");
  ASSERT_EQ(materials.size(), 3u);
  for (const auto& [name, object] : materials.items())
    EXPECT_NO_THROW(make_material(SceneParams(object, "doc.json", "/materials/" + name))) << name;
}

}  // namespace
}  // namespace penumbra
