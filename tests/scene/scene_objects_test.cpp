/// Named objects and instances in JSON scenes: what is read, and every refusal naming the file
/// and JSON path.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "penumbra/core/error.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

// A scene with one material "white", the given "objects" map and "shapes" array (JSON text).
std::string scene_text(const std::string& objects, const std::string& shapes) {
  return R"({"camera": {"type": "pinhole"}, "materials": {"white": {"type": "diffuse"}}, "objects": )" +
         objects + R"(, "shapes": )" + shapes + "}";
}

const std::string kBox = R"({"box": {"shapes": [
  {"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "white"},
  {"type": "sphere", "center": [0, 0, 2], "radius": 0.5, "material": "white",
   "transform": [{"translate": [1, 0, 0]}]}]}})";

// Expects parsing `text` to fail with "test.json:PLACE: ..." containing `problem`.
void expect_error(const std::string& text, const std::string& place, const std::string& problem) {
  std::string what;
  try {
    parse_scene(text, "test.json", "");
    ADD_FAILURE() << "no InputError for: " << text;
  } catch (const InputError& e) {
    what = e.what();
  }
  const std::string prefix = "test.json:" + place + ": ";
  EXPECT_EQ(what.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "' in: " << what;
  EXPECT_NE(what.find(problem), std::string::npos) << "expected '" << problem << "' in: " << what;
}

TEST(SceneObjects, ReadsObjectsAndInstances) {
  const SceneDesc s = parse_scene(scene_text(kBox, R"([
    {"type": "instance", "object": "box", "name": "first"},
    {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white"},
    {"type": "instance", "object": "box", "transform": [{"scale": [-1, 2, 1]}, {"translate": [5, 0, 0]}]}])"),
                                  "test.json", "");
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].name, "box");
  EXPECT_EQ(s.objects[0].path, "/objects/box");
  ASSERT_EQ(s.objects[0].shapes.size(), 2u);
  EXPECT_TRUE(std::holds_alternative<QuadData>(s.objects[0].shapes[0].geometry));
  EXPECT_EQ(s.objects[0].shapes[1].path, "/objects/box/shapes/1");
  // The shape's own transform maps it into object space.
  EXPECT_EQ(s.objects[0].shapes[1].to_world.point({0, 0, 0}), Vec3(1, 0, 0));
  ASSERT_EQ(s.shapes.size(), 1u);  // instances are not shapes
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.instances[0].name, "first");
  EXPECT_EQ(s.instances[0].path, "/shapes/0");
  EXPECT_TRUE(s.instances[0].to_world.is_identity());
  EXPECT_EQ(s.instances[1].object, 0u);
  EXPECT_EQ(s.instances[1].path, "/shapes/2");
  EXPECT_EQ(s.instances[1].to_world.point({1, 1, 0}), Vec3(4, 2, 0));
  EXPECT_TRUE(s.instances[1].to_world.swaps_handedness());
}

TEST(SceneObjects, RefusesUnknownObjects) {
  expect_error(scene_text(kBox, R"([{"type": "instance", "object": "crate"}])"), "/shapes/0/object",
               "unknown object \"crate\" (defined: box)");
  expect_error(scene_text("{}", R"([{"type": "instance", "object": "crate"}])"), "/shapes/0/object",
               "no objects are defined");
  expect_error(scene_text(kBox, R"([{"type": "instance"}])"), "/shapes/0", "object");
}

TEST(SceneObjects, RefusesWhatInstancesDoNotSupport) {
  // Nested instances.
  expect_error(scene_text(R"({"a": {"shapes": [{"type": "instance", "object": "a"}]}})", "[]"),
               "/objects/a/shapes/0", "nested instancing");
  // Emissive shapes in objects (pbrt-v4 refuses area lights in instances too).
  expect_error(scene_text(R"({"lamp": {"shapes": [{"type": "sphere", "center": [0, 0, 0],
      "radius": 1, "material": "white", "emission": [1, 1, 1]}]}})",
                          "[]"),
               "/objects/lamp/shapes/0/emission", "cannot be emissive");
  // Moving shapes in objects, moving instances.
  expect_error(scene_text(R"({"m": {"shapes": [{"type": "sphere", "center": [0, 0, 0],
      "radius": 1, "material": "white", "transform_end": [{"translate": [1, 0, 0]}]}]}})",
                          "[]"),
               "/objects/m/shapes/0/transform_end", "cannot move");
  expect_error(scene_text(kBox, R"([{"type": "instance", "object": "box",
      "transform_end": [{"translate": [1, 0, 0]}]}])"),
               "/shapes/0/transform_end", "instances cannot move");
  // Keys an instance does not take; malformed objects.
  expect_error(scene_text(kBox, R"([{"type": "instance", "object": "box", "material": "white"}])"),
               "/shapes/0/material", "");
  expect_error(scene_text(R"({"e": {"shapes": []}})", "[]"), "/objects/e/shapes",
               "at least one shape");
  expect_error(scene_text(R"({"e": {"shape": []}})", "[]"), "/objects/e/shape", "");
  expect_error(scene_text(R"([])", "[]"), "/objects", "expected an object");
  // Errors inside an object's shapes name their path.
  expect_error(scene_text(R"({"b": {"shapes": [{"type": "sphere", "center": [0, 0, 0],
      "radius": -1, "material": "white"}]}})",
                          "[]"),
               "/objects/b/shapes/0/radius", "positive");
  expect_error(scene_text(R"({"b": {"shapes": [{"type": "sphere", "center": [0, 0, 0],
      "radius": 1, "material": "wood"}]}})",
                          "[]"),
               "/objects/b/shapes/0/material", "unknown material");
}

TEST(SceneObjects, TheDocumentedExampleLoads) {
  // The example of docs/scene-format.md, "Objects and instances", in a scene of its own.
  const std::string doc =
      read_file_contents(std::string(PENUMBRA_SOURCE_DIR) + "/docs/scene-format.md");
  const size_t at = doc.find("```\n\"objects\"");
  ASSERT_NE(at, std::string::npos);
  const size_t end = doc.find("```", at + 4);
  const std::string text =
      R"({"camera": {"type": "pinhole"}, "materials": {"bark": {"type": "d"}, "leaves": {"type": "d"}},)" +
      doc.substr(at + 4, end - at - 4) + "}";
  const SceneDesc s =
      parse_scene(text, "example.json", std::string(PENUMBRA_SOURCE_DIR) + "/scenes");
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].shapes.size(), 2u);
  EXPECT_EQ(s.instances.size(), 2u);
  EXPECT_TRUE(s.instances[1].to_world.swaps_handedness());
}

}  // namespace
}  // namespace penumbra
