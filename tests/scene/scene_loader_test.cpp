/// Tests of the JSON scene loader: the bundled scenes, every kind of input error (each naming the
/// file and the exact JSON path), syntax errors at line:column, transforms and mesh files.
#include "penumbra/scene/scene_loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/scene/mesh_reader.h"

namespace penumbra {
namespace {

const std::string kSceneDir = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/";
const std::string kDataDir = std::string(PENUMBRA_TEST_DATA) + "/scenes/";

// A scene with a pinhole camera, one material "white" and the given shapes (a JSON array);
// `extra` is inserted before "shapes" (e.g. "\"render\": {...},").
std::string scene_text(const std::string& shapes, const std::string& extra = "") {
  return R"({"camera": {"type": "pinhole"}, "materials": {"white": {"type": "diffuse"}}, )" +
         extra + R"( "shapes": )" + shapes + "}";
}

// The message of the InputError that parsing `text` throws ("" and a failure when none).
std::string error_of(const std::string& text, const std::string& base_dir = "") {
  try {
    parse_scene(text, "test.json", base_dir);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for: " << text;
  return "";
}

// Expects parsing `text` to fail with a message "test.json:PLACE: ..." containing `problem`.
void expect_error(const std::string& text, const std::string& place, const std::string& problem) {
  const std::string what = error_of(text);
  const std::string prefix = "test.json" + (place.empty() ? "" : ":" + place) + ": ";
  EXPECT_EQ(what.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "' in: " << what;
  EXPECT_NE(what.find(problem), std::string::npos) << "expected '" << problem << "' in: " << what;
}

Vec3 triangle_normal(const TriangleMesh& m, size_t t) {
  const Vec3 p0 = m.positions[m.indices[3 * t]], p1 = m.positions[m.indices[3 * t + 1]],
             p2 = m.positions[m.indices[3 * t + 2]];
  return normalize(cross(p1 - p0, p2 - p0));
}

void expect_near(Vec3 a, Vec3 b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(SceneLoader, LoadsCornellBox) {
  const SceneDesc s = load_scene(kSceneDir + "cornell-box.json");
  EXPECT_FALSE(s.description.empty());
  EXPECT_EQ(s.camera.type(), "pinhole");
  EXPECT_EQ(s.camera.require_vec3("position"), Vec3(278, 273, -800));
  EXPECT_EQ(s.camera.get_float("vfov", 0), 39.307648f);
  EXPECT_EQ(s.render.width, 256);
  EXPECT_EQ(s.render.height, 256);
  EXPECT_EQ(s.render.spp, 1024);
  EXPECT_EQ(s.render.integrator, "path");
  EXPECT_EQ(s.materials.size(), 4u);
  ASSERT_EQ(s.shapes.size(), 8u);
  size_t triangles = 0;
  int lights = 0;
  for (const ShapeDesc& shape : s.shapes) {
    ASSERT_TRUE(std::holds_alternative<TriangleMesh>(shape.geometry)) << shape.path;
    const auto& mesh = std::get<TriangleMesh>(shape.geometry);
    triangles += mesh.triangle_count();
    EXPECT_TRUE(shape.to_world.is_identity());
    if (!shape.emission) continue;
    ++lights;
    EXPECT_EQ(shape.name, "light");
    EXPECT_EQ(*shape.emission, Rgb(17, 12, 4));
    EXPECT_FALSE(shape.two_sided_emission);
    ASSERT_EQ(mesh.triangle_count(), 2u);
    // The light emits on its front side, which must face down into the box.
    for (size_t t = 0; t < 2; ++t) expect_near(triangle_normal(mesh, t), Vec3(0, -1, 0));
  }
  EXPECT_EQ(triangles, 38u);
  EXPECT_EQ(lights, 1);
}

TEST(SceneLoader, LoadsWhitted) {
  const SceneDesc s = load_scene(kSceneDir + "whitted.json");
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  EXPECT_EQ(s.render.spp, 4);
  EXPECT_GT(s.render.background.b, 0.5f);
  EXPECT_EQ(s.lights.size(), 2u);
  int spheres = 0, quads = 0;
  for (const ShapeDesc& shape : s.shapes) {
    spheres += std::holds_alternative<SphereData>(shape.geometry);
    quads += std::holds_alternative<QuadData>(shape.geometry);
  }
  EXPECT_EQ(spheres, 2);
  EXPECT_GE(quads, 64);
}

TEST(SceneLoader, LoadsBunny) {
  const SceneDesc s = load_scene(kSceneDir + "mesh-bunny.json");
  ASSERT_EQ(s.shapes.size(), 2u);
  const auto& mesh = std::get<TriangleMesh>(s.shapes[0].geometry);
  EXPECT_EQ(mesh.triangle_count(), 3674u);
  EXPECT_EQ(s.lights.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<QuadData>(s.shapes[1].geometry));
}

TEST(SceneLoader, ReadsObjAndPlyRelativeToTheSceneFile) {
  const SceneDesc s = load_scene(kDataDir + "file_meshes.json");
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[0].geometry).triangle_count(), 1u);
  expect_near(s.shapes[0].to_world.point(Vec3(0, 0, 0)), Vec3(0, 0, 1));
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[1].geometry).triangle_count(), 2u);
  EXPECT_TRUE(s.shapes[1].two_sided_emission);
  EXPECT_EQ(s.materials[0].params.get_rgb("albedo", Rgb(0)), Rgb(0.5f));
}

TEST(SceneLoader, MissingMeshFileNamesTheResolvedPath) {
  const std::string text =
      scene_text(R"([{"type": "obj", "file": "missing.obj", "material": "white"}])");
  const std::string what = error_of(text, kDataDir);
  EXPECT_EQ(what.rfind("test.json:/shapes/0/file: ", 0), 0u) << what;
  EXPECT_NE(what.find(kDataDir + "missing.obj"), std::string::npos) << what;
  expect_error(scene_text(R"([{"type": "obj", "file": "tri.ply", "material": "white"}])"),
               "/shapes/0/file", "needs a .obj file");
}

TEST(SceneLoader, MissingSceneFileIsAnInputError) {
  EXPECT_THROW(load_scene(kDataDir + "no-such-scene.json"), InputError);
}

TEST(SceneLoader, DefaultsWhenOptionalSectionsAreAbsent) {
  const SceneDesc s = parse_scene(R"({"camera": {"type": "pinhole"}, "shapes": []})", "t.json", "");
  const RenderSettings defaults;
  EXPECT_EQ(s.render.width, defaults.width);
  EXPECT_EQ(s.render.spp, defaults.spp);
  EXPECT_EQ(s.render.seed, defaults.seed);
  EXPECT_EQ(s.render.accel, defaults.accel);
  EXPECT_TRUE(s.materials.empty());
  EXPECT_TRUE(s.lights.empty());
}

TEST(SceneLoader, ReadsEveryRenderSetting) {
  const SceneDesc s = parse_scene(
      scene_text("[]", R"("render": {"resolution": [640, 360], "spp": 64, "max_depth": 0,
        "seed": 18446744073709551615, "integrator": "path", "accel": "kdtree:sah",
        "background": 0.25},)"),
      "t.json", "");
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 360);
  EXPECT_EQ(s.render.spp, 64);
  EXPECT_EQ(s.render.max_depth, std::optional<int>(0));
  EXPECT_EQ(s.render.seed, 18446744073709551615ull);
  EXPECT_EQ(s.render.integrator, "path");
  EXPECT_EQ(s.render.accel, "kdtree:sah");
  EXPECT_EQ(s.render.background, Rgb(0.25f));
}

TEST(SceneLoader, UnknownKeysNameTheirPath) {
  expect_error(scene_text(R"([{"type": "sphere", "center": [0, 0, 0], "radus": 1,
                              "material": "white"}])"),
               "/shapes/0/radus", "unknown key");
  expect_error(R"({"camera": {"type": "pinhole"}, "shapes": [], "camra": {}})", "/camra",
               "unknown key");
  expect_error(scene_text("[]", R"("render": {"sp": 4},)"), "/render/sp", "unknown key");
  expect_error(scene_text(R"([{"type": "mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]],
                              "indices": [[0,1,2]], "normal": [], "material": "white"}])"),
               "/shapes/0/normal", "unknown key");
  expect_error(scene_text(R"([{"type": "cone", "material": "white"}])"), "/shapes/0/type",
               "unknown shape type");
}

TEST(SceneLoader, WrongTypesAndLengths) {
  const auto sphere = [](const std::string& center, const std::string& radius) {
    return scene_text(R"([{"type": "sphere", "center": )" + center + R"(, "radius": )" + radius +
                      R"(, "material": "white"}])");
  };
  expect_error(sphere("[0, 0, 0]", "\"1\""), "/shapes/0/radius", "expected a number");
  expect_error(sphere("[0, 0]", "1"), "/shapes/0/center", "expected an array of 3 numbers");
  expect_error(sphere("[0, true, 0]", "1"), "/shapes/0/center/1", "expected a number");
  expect_error(sphere("{}", "1"), "/shapes/0/center", "expected an array of 3 numbers");
  expect_error(scene_text(R"([{"type": "sphere", "center": [0,0,0], "radius": 1, "material": 3}])"),
               "/shapes/0/material", "expected a string");
  expect_error(scene_text("{}"), "/shapes", "expected an array");
  expect_error(scene_text("[7]"), "/shapes/0", "expected an object");
  expect_error(R"({"camera": [], "shapes": []})", "/camera", "expected an object");
  expect_error(R"({"camera": {"type": 1}, "shapes": []})", "/camera/type", "expected a string");
  expect_error(scene_text("[]", R"("lights": {},)"), "/lights", "expected an array");
  expect_error(scene_text("[]", R"("lights": [{"type": "point"}, {"position": [0,0,0]}],)"),
               "/lights/1", "missing required key \"type\"");
  expect_error(R"({"camera": {"type": "pinhole"}, "materials": [], "shapes": []})", "/materials",
               "expected an object");
  expect_error(R"({"camera": {"type": "pinhole"}, "description": 5, "shapes": []})", "/description",
               "expected a string");
  expect_error("[]", "", "expected a JSON object at the top level");
}

TEST(SceneLoader, OutOfRangeValues) {
  const auto sphere = [](const std::string& radius) {
    return scene_text(R"([{"type": "sphere", "center": [0, 0, 0], "radius": )" + radius +
                      R"(, "material": "white"}])");
  };
  expect_error(sphere("-1"), "/shapes/0/radius", "radius must be positive");
  expect_error(sphere("0"), "/shapes/0/radius", "radius must be positive");
  expect_error(sphere("1e39"), "/shapes/0/radius", "out of single-precision range");
  // A number beyond double range is a parse-time error, placed by line and column.
  const std::string huge = sphere("1e999");
  expect_error(huge, "1:" + std::to_string(huge.find("1e999") + 1), "number overflow");
  expect_error(scene_text(R"([{"type": "quad", "origin": [0,0,0], "edge1": [1,0,0],
                              "edge2": [2,0,0], "material": "white"}])"),
               "/shapes/0", "no area");
  expect_error(scene_text(R"([{"type": "quad", "origin": [0,0,0], "edge1": [1,0,0],
                              "edge2": [0,1,0], "material": "white", "emission": [1,-1,1]}])"),
               "/shapes/0/emission", "must not be negative");
}

TEST(SceneLoader, RenderSettingsAreValidated) {
  const auto render = [](const std::string& body) {
    return scene_text("[]", R"("render": {)" + body + "},");
  };
  expect_error(render(R"("resolution": [0, 10])"), "/render/resolution/0", "[1, 65536], got 0");
  expect_error(render(R"("resolution": [10, 65537])"), "/render/resolution/1", "[1, 65536]");
  expect_error(render(R"("resolution": [10])"), "/render/resolution", "array of 2 integers");
  expect_error(render(R"("resolution": [10.5, 10])"), "/render/resolution/0", "integer");
  expect_error(render(R"("spp": 0)"), "/render/spp", "expected an integer in [1,");
  expect_error(render(R"("max_depth": -1)"), "/render/max_depth", "expected an integer in [0,");
  expect_error(render(R"("seed": -1)"), "/render/seed", "expected an integer in [0,");
  expect_error(render(R"("seed": 18446744073709551616)"), "/render/seed", "expected an integer");
  expect_error(render(R"("seed": 0.5)"), "/render/seed", "expected an integer");
  expect_error(render(R"("integrator": "")"), "/render/integrator", "must not be empty");
  expect_error(render(R"("accel": 3)"), "/render/accel", "expected a string");
  expect_error(render(R"("background": [0, -1, 0])"), "/render/background", "must not be negative");
  expect_error(scene_text("[]", R"("render": [],)"), "/render", "expected an object");
}

TEST(SceneLoader, MaterialsAreCheckedByName) {
  expect_error(scene_text(R"([{"type": "sphere", "center": [0,0,0], "radius": 1,
                              "material": "whte"}])"),
               "/shapes/0/material", "unknown material \"whte\" (defined: white)");
  expect_error(R"({"camera": {"type": "pinhole"},
                  "materials": {"white": {"type": "diffuse"}, "white": {"type": "mirror"}},
                  "shapes": []})",
               "/materials/white", "duplicate key");
  expect_error(
      R"({"camera": {"type": "pinhole"}, "materials": {"m": {"albedo": 1}}, "shapes": []})",
      "/materials/m", "missing required key \"type\"");
  // Material parameters are the material's business: the loader accepts any key.
  const SceneDesc s = parse_scene(
      R"({"camera": {"type": "pinhole", "fancy": 1}, "materials": {"m": {"type": "x", "y": [1]}},
          "shapes": []})",
      "t.json", "");
  EXPECT_EQ(s.materials.at(0).params.type(), "x");
  EXPECT_THROW(s.materials.at(0).params.check_all_used(), InputError);
}

TEST(SceneLoader, MissingRequiredKeys) {
  expect_error(R"({"shapes": []})", "", "missing required key \"camera\"");
  expect_error(R"({"camera": {"type": "pinhole"}})", "", "missing required key \"shapes\"");
  expect_error(scene_text(R"([{"type": "sphere", "center": [0,0,0], "material": "white"}])"),
               "/shapes/0", "missing required key \"radius\"");
  expect_error(scene_text(R"([{"type": "sphere", "center": [0,0,0], "radius": 1}])"), "/shapes/0",
               "missing required key \"material\"");
  expect_error(scene_text(R"([{"center": [0,0,0]}])"), "/shapes/0",
               "missing required key \"type\"");
  expect_error(scene_text(R"([{"type": "obj", "material": "white"}])"), "/shapes/0",
               "missing required key \"file\"");
}

TEST(SceneLoader, InlineMeshesAreValidated) {
  const auto mesh = [](const std::string& body) {
    return scene_text(R"([{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "white"},
                          {"type": "mesh", "material": "white", )" +
                      body + "}]");
  };
  const std::string tri = R"("positions": [[0,0,0], [1,0,0], [0,1,0]], )";
  expect_error(mesh(tri + R"("indices": [[0, 1, 3]])"), "/shapes/1/indices/0/2",
               "vertex index 3 out of range (the mesh has 3 positions)");
  expect_error(mesh(tri + R"("indices": [[0, -1, 2]])"), "/shapes/1/indices/0/1",
               "expected an integer");
  expect_error(mesh(tri + R"("indices": [])"), "/shapes/1/indices", "at least one triangle");
  expect_error(mesh(tri + R"("indices": [[0, 1]])"), "/shapes/1/indices/0", "3 vertex indices");
  expect_error(mesh(tri + R"("indices": [[0,1,2]], "normals": [[0,0,1], [0,0,1]])"),
               "/shapes/1/normals", "expected 3 normals (one per position), got 2");
  expect_error(mesh(tri + R"("indices": [[0,1,2]], "uvs": [[0,0], [1,0], [0]])"), "/shapes/1/uvs/2",
               "expected an array of 2 numbers");
  expect_error(mesh(tri + R"("indices": [[0,1,2]], "uvs": [[0,0]])"), "/shapes/1/uvs",
               "expected 3 uvs");
  expect_error(mesh(R"("positions": [[0,0,0], [1,0]], "indices": [[0,1,1]])"),
               "/shapes/1/positions/1", "expected an array of 3 numbers");
  // A well-formed mesh keeps everything, in order.
  const SceneDesc s =
      parse_scene(mesh(tri + R"("indices": [[0,2,1]], "normals": [[0,0,1],[0,0,1],[0,0,1]],
                    "uvs": [[0,0],[1,0],[0,1]])"),
                  "t.json", "");
  const auto& m = std::get<TriangleMesh>(s.shapes[1].geometry);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 2, 1}));
  EXPECT_EQ(m.uvs[2], Vec2(0, 1));
  EXPECT_EQ(m.normals.size(), 3u);
}

TEST(SceneLoader, EmissionAndTwoSided) {
  const std::string quad = R"({"type": "quad", "origin": [0,0,0], "edge1": [1,0,0],
                               "edge2": [0,1,0], "material": "white")";
  const SceneDesc s =
      parse_scene(scene_text("[" + quad + R"(, "emission": 2, "two_sided": true}, )" + quad +
                             "}, " + quad + R"(, "emission": [0, 0, 0]}])"),
                  "t.json", "");
  EXPECT_EQ(*s.shapes[0].emission, Rgb(2));
  EXPECT_TRUE(s.shapes[0].two_sided_emission);
  EXPECT_FALSE(s.shapes[1].emission);
  EXPECT_FALSE(s.shapes[2].emission);  // black emission is no emission
  expect_error(scene_text("[" + quad + R"(, "two_sided": true}])"), "/shapes/0/two_sided",
               "no \"emission\"");
  expect_error(scene_text("[" + quad + R"(, "emission": [1, 1, 1], "two_sided": 1}])"),
               "/shapes/0/two_sided", "expected true or false");
}

// The JSON examples of docs/scene-format.md: the first is a whole scene, the others are shapes.
TEST(SceneLoader, DocumentedExamplesLoad) {
  const std::string doc =
      read_file_contents(std::string(PENUMBRA_SOURCE_DIR) + "/docs/scene-format.md");
  std::vector<std::string> blocks;
  for (size_t at = doc.find("```json\n"); at != std::string::npos; at = doc.find("```json\n", at)) {
    at += 8;
    const size_t end = doc.find("```", at);
    blocks.push_back(doc.substr(at, end - at));
  }
  ASSERT_GE(blocks.size(), 5u);
  const SceneDesc s = parse_scene(blocks[0], "example.json", kSceneDir);
  EXPECT_EQ(s.shapes.size(), 4u);
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[2].geometry).triangle_count(), 3674u);
  const auto& lamp = std::get<TriangleMesh>(s.shapes[3].geometry);
  expect_near(triangle_normal(lamp, 0), Vec3(0, -1, 0));
  for (size_t i = 1; i < blocks.size(); ++i) {
    const std::string text =
        R"({"camera": {"type": "pinhole"}, "materials": {"white": {"type": "d"},
        "glass": {"type": "d"}, "clay": {"type": "d"}}, "shapes": [)" +
        blocks[i] + "]}";
    EXPECT_NO_THROW(parse_scene(text, "example.json", kSceneDir)) << blocks[i];
  }
}

TEST(SceneLoader, SyntaxErrorsReportLineAndColumn) {
  const std::string text = "{\n  \"camera\": {\"type\": \"pinhole\"},\n  \"shapes\": [1,]\n}\n";
  expect_error(text, "3:16", "syntax error");
  expect_error("{\"camera\": {\"type\": \"pinhole\"}", "1:31", "unexpected end of input");
  expect_error("", "1:1", "unexpected end of input");
  expect_error("{\n\n  \"camera\": tru }", "3:16", "invalid literal");
}

TEST(SceneLoader, DuplicateKeysAnywhereNameTheirPath) {
  expect_error(
      scene_text(R"([{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "white"},
                              {"type": "mesh", "material": "white", "positions": [[0,0,0],[1,0,0],[0,1,0]],
                               "indices": [[0,1,2]]},
                              {"type": "sphere", "center": [0,0,0], "radius": 1, "radius": 2,
                               "material": "white"}])"),
      "/shapes/2/radius", "duplicate key");
  expect_error(R"({"camera": {"type": "pinhole"}, "shapes": [], "shapes": []})", "/shapes",
               "duplicate key");
  expect_error(scene_text("[]", R"("lights": [{"type": "point", "a/b~": 1, "a/b~": 2}],)"),
               "/lights/0/a~1b~0", "duplicate key");
}

}  // namespace
}  // namespace penumbra
