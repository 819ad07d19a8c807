/// The scene keys of motion blur: a shape's "transform_end" (its transform at time 1) and the
/// errors it can raise, each naming the file and JSON path.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

// A scene with a pinhole camera, one material "white" and one shape (JSON object text).
std::string scene_with(const std::string& shape) {
  return R"({"camera": {"type": "pinhole"}, "materials": {"white": {"type": "diffuse"}},
             "shapes": [)" +
         shape + "]}";
}

// The message of the InputError that parsing `text` throws ("" and a failure when none).
std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "test.json", PENUMBRA_SOURCE_DIR);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for: " << text;
  return "";
}

void expect_error(const std::string& shape, const std::string& place, const std::string& problem) {
  const std::string what = error_of(scene_with(shape));
  EXPECT_EQ(what.rfind("test.json:" + place + ": ", 0), 0u) << what;
  EXPECT_NE(what.find(problem), std::string::npos) << "expected '" << problem << "' in: " << what;
}

TEST(ShapeMotion, TransformEndIsTheTransformAtTimeOne) {
  const SceneDesc d = parse_scene(scene_with(R"({"type": "sphere", "center": [0, 0, 0],
      "radius": 1, "material": "white", "transform": [{"translate": [1, 0, 0]}],
      "transform_end": [{"scale": 2}, {"translate": [0, 3, 0]}]})"),
                                  "test.json", "");
  ASSERT_EQ(d.shapes.size(), 1u);
  const ShapeDesc& s = d.shapes[0];
  EXPECT_EQ(s.to_world.point({0, 0, 0}), Vec3(1, 0, 0));
  ASSERT_TRUE(s.to_world_end.has_value());
  EXPECT_EQ(s.to_world_end->point({1, 0, 0}), Vec3(2, 3, 0));
  // Without "transform": the identity at time 0; without "transform_end": a static shape.
  const SceneDesc e = parse_scene(scene_with(R"({"type": "quad", "origin": [0, 0, 0],
      "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "white",
      "transform_end": [{"translate": [0, 0, 1]}]})"),
                                  "test.json", "");
  EXPECT_TRUE(e.shapes[0].to_world.is_identity());
  EXPECT_EQ(e.shapes[0].to_world_end->point({0, 0, 0}), Vec3(0, 0, 1));
  const SceneDesc f = parse_scene(scene_with(R"({"type": "sphere", "center": [0, 0, 0],
      "radius": 1, "material": "white"})"),
                                  "test.json", "");
  EXPECT_FALSE(f.shapes[0].to_world_end.has_value());
}

TEST(ShapeMotion, EveryShapeTypeTakesTransformEnd) {
  for (const std::string shape :
       {R"({"type": "mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,2]],)"
        R"( "material": "white", "transform_end": [{"translate": [1, 0, 0]}]})",
        R"({"type": "obj", "file": "scenes/meshes/bunny.obj", "material": "white",)"
        R"( "transform_end": [{"rotate": {"angle": 5, "axis": [0, 1, 0]}}]})",
        R"({"type": "ply", "file": "tests/data/meshes/cube.ply", "material": "white",)"
        R"( "transform_end": [{"translate": [0, 1, 0]}]})"}) {
    const SceneDesc d = parse_scene(scene_with(shape), "test.json", PENUMBRA_SOURCE_DIR);
    EXPECT_TRUE(d.shapes[0].to_world_end.has_value()) << shape;
  }
}

TEST(ShapeMotion, BadTransformEndsNameTheirPlace) {
  // An error inside the operations names the operation.
  expect_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
                   "transform_end": [{"translate": [0, 0]}]})",
               "/shapes/0/transform_end/0/translate", "expected an array of 3 numbers");
  expect_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
                   "transform_end": {"translate": [0, 0, 1]}})",
               "/shapes/0/transform_end", "");
  // A sphere must stay a sphere at the end too.
  expect_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
                   "transform_end": [{"scale": [1, 2, 1]}]})",
               "/shapes/0/transform_end", "must be a similarity");
  // Moving emitters are refused: area lights sample their shapes without a time.
  expect_error(R"({"type": "quad", "origin": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
                   "material": "white", "emission": 1,
                   "transform_end": [{"translate": [0, 0, 1]}]})",
               "/shapes/0/transform_end", "a moving shape cannot be emissive");
  // Turning inside out while moving (a mirror at one end only).
  expect_error(R"({"type": "mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,2]],
                   "material": "white", "transform_end": [{"scale": [-1, 1, 1]}]})",
               "/shapes/0/transform_end", "mirrors the shape");
  // A misspelt key lists transform_end among the keys taken.
  expect_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
                   "transform_ned": []})",
               "/shapes/0/transform_ned", "transform_end");
}

// A black emission is no emission: such a shape may move.
TEST(ShapeMotion, BlackEmissionMayMove) {
  const SceneDesc d = parse_scene(scene_with(R"({"type": "sphere", "center": [0, 0, 0],
      "radius": 1, "material": "white", "emission": 0,
      "transform_end": [{"translate": [1, 0, 0]}]})"),
                                  "test.json", "");
  EXPECT_FALSE(d.shapes[0].emission.has_value());
  EXPECT_TRUE(d.shapes[0].to_world_end.has_value());
}

}  // namespace
}  // namespace penumbra
