/// glTF meshes and nodes: vertices land where the node hierarchy puts them, TRS and matrix forms
/// agree, shared meshes become one object with several instances, strips and fans are converted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "gltf_test_util.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::load_gltf;

const TriangleMesh& mesh_of(const ShapeDesc& s) {
  return std::get<TriangleMesh>(s.geometry);
}

void expect_near(Vec3 a, Vec3 b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(GltfMesh, TranslatedTriangleLandsWhereExpected) {
  GltfBuilder b;
  const json mesh = test::triangle_mesh(b);
  const SceneDesc s = load_gltf(b.doc({{"scenes", {{{"nodes", {0}}}}},
                                       {"nodes", {{{"mesh", 0}, {"translation", {1, 2, 3}}}}},
                                       {"meshes", {mesh}}}));
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_TRUE(s.instances.empty());
  const TriangleMesh& m = mesh_of(s.shapes[0]);
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
  expect_near(s.shapes[0].to_world.point(m.positions[1]), Vec3(2, 2, 3));
  expect_near(s.shapes[0].to_world.point(m.positions[2]), Vec3(1, 3, 3));
  EXPECT_EQ(s.shapes[0].path, "/meshes/0/primitives/0");
}

TEST(GltfMesh, TrsAndColumnMajorMatrixGiveTheSameTransform) {
  // Rotation of 90 degrees about +z (quaternion xyzw), scale 2, translation (5, 0, 0).
  const double h = std::sqrt(0.5);
  const json trs = {{"translation", {5, 0, 0}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 2, 2}}};
  // The same as a column-major matrix: columns are the images of x, y, z and the translation.
  const json mat = {{"matrix", {0, 2, 0, 0, -2, 0, 0, 0, 0, 0, 2, 0, 5, 0, 0, 1}}};
  for (const json& node : {trs, mat}) {
    GltfBuilder b;
    json n = node;
    n["mesh"] = 0;
    const SceneDesc s = load_gltf(b.doc(
        {{"scenes", {{{"nodes", {0}}}}}, {"nodes", {n}}, {"meshes", {test::triangle_mesh(b)}}}));
    ASSERT_EQ(s.shapes.size(), 1u);
    const Transform& t = s.shapes[0].to_world;
    expect_near(t.point(Vec3(1, 0, 0)), Vec3(5, 2, 0));  // x -> +y, doubled
    expect_near(t.point(Vec3(0, 1, 0)), Vec3(3, 0, 0));  // y -> -x, doubled
    expect_near(t.point(Vec3(0, 0, 1)), Vec3(5, 0, 2));
  }
}

TEST(GltfMesh, ChildTransformIsParentTimesChild) {
  GltfBuilder b;
  // Parent scales by 2, child translates by (1, 0, 0): the child's origin lands at (2, 0, 0).
  const SceneDesc s = load_gltf(b.doc(
      {{"scenes", {{{"nodes", {0}}}}},
       {"nodes",
        {{{"scale", {2, 2, 2}}, {"children", {1}}}, {{"translation", {1, 0, 0}}, {"mesh", 0}}}},
       {"meshes", {test::triangle_mesh(b)}}}));
  ASSERT_EQ(s.shapes.size(), 1u);
  expect_near(s.shapes[0].to_world.point(Vec3(0, 0, 0)), Vec3(2, 0, 0));
  expect_near(s.shapes[0].to_world.point(Vec3(1, 0, 0)), Vec3(4, 0, 0));
}

TEST(GltfMesh, MeshUsedByTwoNodesIsOneObjectWithTwoInstances) {
  GltfBuilder b;
  const SceneDesc s =
      load_gltf(b.doc({{"scenes", {{{"nodes", {0, 1}}}}},
                       {"nodes",
                        {{{"mesh", 0}, {"translation", {-3, 0, 0}}, {"name", "left"}},
                         {{"mesh", 0}, {"translation", {3, 0, 0}}, {"name", "right"}}}},
                       {"meshes", {test::triangle_mesh(b)}}}));
  EXPECT_TRUE(s.shapes.empty());
  ASSERT_EQ(s.objects.size(), 1u);
  ASSERT_EQ(s.objects[0].shapes.size(), 1u);
  EXPECT_TRUE(s.objects[0].shapes[0].to_world.is_identity());
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.instances[0].object, 0u);
  EXPECT_EQ(s.instances[1].name, "right");
  expect_near(s.instances[0].to_world.point(Vec3(0, 0, 0)), Vec3(-3, 0, 0));
  expect_near(s.instances[1].to_world.point(Vec3(0, 0, 0)), Vec3(3, 0, 0));
}

TEST(GltfMesh, EmissiveMeshUsedTwiceIsCopiedWithAWarning) {
  GltfBuilder b;
  json mesh = test::triangle_mesh(b);
  mesh["primitives"][0]["material"] = 0;
  const SceneDesc s = load_gltf(b.doc({{"scenes", {{{"nodes", {0, 1}}}}},
                                       {"nodes", {{{"mesh", 0}}, {{"mesh", 0}}}},
                                       {"materials", {{{"emissiveFactor", {1, 1, 1}}}}},
                                       {"meshes", {mesh}}}));
  EXPECT_EQ(s.shapes.size(), 2u);
  EXPECT_TRUE(s.objects.empty());
  EXPECT_TRUE(test::has_warning(s, "model.gltf:/meshes/0: emissive mesh used by 2 nodes"));
}

TEST(GltfMesh, NonIndexedStripAndFanBecomeTriangles) {
  GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, "VEC3", 3);
  const json strip = {{"attributes", {{"POSITION", pos}}}, {"mode", 5}};
  const json fan = {{"attributes", {{"POSITION", pos}}}, {"mode", 6}};
  const json points = {{"attributes", {{"POSITION", pos}}}, {"mode", 0}};
  const SceneDesc s = load_gltf(b.doc({{"scenes", {{{"nodes", {0}}}}},
                                       {"nodes", {{{"mesh", 0}}}},
                                       {"meshes", {{{"primitives", {strip, fan, points}}}}}}));
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(mesh_of(s.shapes[0]).indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(mesh_of(s.shapes[1]).indices, (std::vector<uint32_t>{1, 2, 0, 2, 3, 0}));
  EXPECT_TRUE(test::has_warning(s, "/meshes/0/primitives/2/mode: POINTS primitive skipped"));
}

TEST(GltfMesh, NormalsAndNormalizedByteUvsAreRead) {
  GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int nrm = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
  const uint8_t uv_bytes[8] = {0, 0, 255, 0, 0, 255, 0, 0};  // 3 VEC2, stride 2
  const int uv = b.add(uv_bytes, 6, 5121, "VEC2", 3);
  b.accessors()[size_t(uv)]["normalized"] = true;
  const json prim = {{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}}};
  const SceneDesc s = load_gltf(b.doc({{"scenes", {{{"nodes", {0}}}}},
                                       {"nodes", {{{"mesh", 0}}}},
                                       {"meshes", {{{"primitives", {prim}}}}}}));
  ASSERT_EQ(s.shapes.size(), 1u);
  const TriangleMesh& m = mesh_of(s.shapes[0]);
  ASSERT_EQ(m.normals.size(), 3u);
  expect_near(m.normals[2], Vec3(0, 0, 1));
  ASSERT_EQ(m.uvs.size(), 3u);
  EXPECT_FLOAT_EQ(m.uvs[1].x, 1.0f);
  EXPECT_FLOAT_EQ(m.uvs[1].y, 1.0f);  // v flipped: glTF v = 0 is the top row
  EXPECT_FLOAT_EQ(m.uvs[2].y, 0.0f);
}

TEST(GltfMesh, LoadSceneChoosesTheGltfReaderByExtension) {
  GltfBuilder b;
  const json doc = b.doc({{"scenes", {{{"nodes", {0}}}}},
                          {"nodes", {{{"mesh", 0}}}},
                          {"meshes", {test::triangle_mesh(b)}}});
  const std::string path = ::testing::TempDir() + "/penumbra_gltf_ext.GLTF";
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    const std::string text = doc.dump();
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
  }
  const SceneDesc s = load_scene(path);
  EXPECT_EQ(s.shapes.size(), 1u);
  EXPECT_EQ(s.render.integrator, "path");
  std::remove(path.c_str());
}

}  // namespace
}  // namespace penumbra
