/// Tests of shape transforms in scene files: composition order, each operation, the similarity
/// check for spheres, and malformed operations.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/core/error.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/scene/transform_parser.h"

namespace penumbra {
namespace {

// The to_world of a one-triangle mesh shape with the given "transform" array.
Transform mesh_transform(const std::string& ops) {
  const std::string text =
      R"({"camera": {"type": "pinhole"}, "materials": {"m": {"type": "diffuse"}},
          "shapes": [{"type": "mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,2]],
                      "material": "m", "transform": )" +
      ops + "}]}";
  return parse_scene(text, "t.json", "").shapes.at(0).to_world;
}

// The message of the error for a sphere with the given "transform" array ("" when accepted).
std::string sphere_error(const std::string& ops) {
  const std::string text =
      R"({"camera": {"type": "pinhole"}, "materials": {"m": {"type": "diffuse"}},
          "shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m",
                      "transform": )" +
      ops + "}]}";
  try {
    parse_scene(text, "t.json", "");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_near(Vec3 a, Vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST(SceneTransform, OperationsApplyInListedOrder) {
  // Scale first, then translate: (1,0,0) -> (2,0,0) -> (3,0,0).
  expect_near(mesh_transform(R"([{"scale": 2}, {"translate": [1, 0, 0]}])").point({1, 0, 0}),
              {3, 0, 0});
  // Translate first, then scale: (1,0,0) -> (2,0,0) -> (4,0,0).
  expect_near(mesh_transform(R"([{"translate": [1, 0, 0]}, {"scale": 2}])").point({1, 0, 0}),
              {4, 0, 0});
  // (0,0,0) -> translate (1,0,0) -> rotate 90 degrees about +y (right-handed: +x to -z)
  // -> (0,0,-1) -> scale (1,2,3) -> (0,0,-3).
  const Transform t = mesh_transform(
      R"([{"translate": [1, 0, 0]}, {"rotate": {"angle": 90, "axis": [0, 2, 0]}},
          {"scale": [1, 2, 3]}])");
  expect_near(t.point({0, 0, 0}), {0, 0, -3});
  expect_near(t.point({0, 1, 0}), {0, 2, -3});
}

TEST(SceneTransform, MatrixIsRowMajorWithTranslationInTheLastColumn) {
  const Transform t =
      mesh_transform(R"([{"matrix": [1,0,0,5, 0,1,0,6, 0,0,1,7, 0,0,0,1]}, {"scale": 2}])");
  expect_near(t.point({0, 0, 0}), {10, 12, 14});
  expect_near(t.point({1, 0, 0}), {12, 12, 14});
}

TEST(SceneTransform, EmptyListIsIdentity) {
  EXPECT_TRUE(mesh_transform("[]").is_identity());
}

TEST(SceneTransform, SpheresAcceptOnlySimilarities) {
  EXPECT_EQ(sphere_error(R"([{"scale": 2}, {"rotate": {"angle": 33, "axis": [1, 2, 3]}},
                             {"translate": [1, 2, 3]}, {"scale": -0.5}])"),
            "");
  const std::string prefix = "t.json:/shapes/0/transform: ";
  EXPECT_EQ(sphere_error(R"([{"scale": [1, 2, 1]}])").rfind(prefix, 0), 0u);
  EXPECT_EQ(sphere_error(R"([{"rotate": {"angle": 30, "axis": [0, 0, 1]}},
                             {"scale": [1, 1.001, 1]}])")
                .rfind(prefix, 0),
            0u);
  // A shear that keeps every axis at unit length, but not at right angles.
  EXPECT_EQ(
      sphere_error(R"([{"matrix": [1,0.6,0,0, 0,0.8,0,0, 0,0,1,0, 0,0,0,1]}])").rfind(prefix, 0),
      0u);
  // Meshes take any invertible affine transform.
  EXPECT_NO_THROW(mesh_transform(R"([{"scale": [1, 2, 3]}])"));
}

TEST(SceneTransform, IsSimilarityTolerance) {
  EXPECT_TRUE(is_similarity(scale({3, 3, 3}) * rotate(17, {1, 1, 0})));
  EXPECT_TRUE(is_similarity(scale({1, 1, 1 + 5e-6f})));
  EXPECT_FALSE(is_similarity(scale({1, 1, 1 + 5e-5f})));
}

TEST(SceneTransform, MalformedOperationsNameTheirPath) {
  const auto expect_error = [](const std::string& ops, const std::string& place,
                               const std::string& problem) {
    const std::string what = sphere_error(ops);
    EXPECT_EQ(what.rfind("t.json:/shapes/0/transform" + place + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(problem), std::string::npos) << what;
  };
  expect_error(R"({"scale": 2})", "", "expected an array");
  expect_error(R"([{"skew": 2}])", "/0/skew", "unknown transform operation");
  expect_error(R"([{"scale": 2, "translate": [0,0,0]}])", "/0", "one key");
  expect_error(R"([{}])", "/0", "one key");
  expect_error(R"([[1]])", "/0", "one key");
  expect_error(R"([{"scale": 1}, {"scale": 0}])", "/1/scale", "must not be zero");
  expect_error(R"([{"scale": [1, 1]}])", "/0/scale", "expected an array of 3 numbers");
  expect_error(R"([{"translate": [1, "x", 0]}])", "/0/translate/1", "expected a number");
  expect_error(R"([{"rotate": {"angle": 10, "axis": [0, 0, 0]}}])", "/0/rotate/axis",
               "must not be zero");
  expect_error(R"([{"rotate": {"angle": 10}}])", "/0/rotate", "missing required key \"axis\"");
  expect_error(R"([{"rotate": {"angle": 10, "axis": [0,1,0], "deg": 1}}])", "/0/rotate/deg",
               "unknown key");
  expect_error(R"([{"rotate": 90}])", "/0/rotate", "expected an object");
  expect_error(R"([{"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0]}])", "/0/matrix", "16 numbers");
  expect_error(R"([{"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]}])", "/0/matrix", "bottom row");
  expect_error(R"([{"matrix": [1,0,0,0, 0,1,0,0, 0,0,0,0, 0,0,0,1]}])", "/0/matrix", "singular");
}

}  // namespace
}  // namespace penumbra
