#include "penumbra/scene/obj_reader.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/scene/mesh_reader.h"

namespace penumbra {
namespace {

const std::string kMeshes = std::string(PENUMBRA_TEST_DATA) + "/meshes/";

/// Expects parse_obj(text) to throw an InputError whose message contains every fragment.
void expect_error(const std::string& text, std::initializer_list<std::string> fragments) {
  try {
    parse_obj(text, "bad.obj");
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    for (const std::string& f : fragments) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
          << "message '" << e.what() << "' lacks '" << f << "'";
    }
  }
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(ObjReader, ReadsCubeFileWithOneVertexPerAttributeTriple) {
  const TriangleMesh mesh = read_obj(kMeshes + "cube.obj");
  EXPECT_EQ(mesh.triangle_count(), 12u);
  EXPECT_EQ(mesh.positions.size(), 24u);
  EXPECT_EQ(mesh.normals.size(), 24u);
  EXPECT_EQ(mesh.uvs.size(), 24u);
  // Every triangle is flat: its three corners share the face normal.
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Vec3 n = mesh.normals[mesh.indices[3 * t]];
    EXPECT_EQ(mesh.normals[mesh.indices[3 * t + 1]], n);
    EXPECT_EQ(mesh.normals[mesh.indices[3 * t + 2]], n);
  }
  EXPECT_EQ(mesh.normals[mesh.indices[0]], Vec3(0, 0, -1));
  EXPECT_EQ(mesh.uvs[mesh.indices[2]], Vec2(1, 1));
}

TEST(ObjReader, PositionOnlyFacesKeepFileVertices) {
  const TriangleMesh mesh = parse_obj(kTriangle + "v 5 5 5\nf 3 2 1\n", "t.obj");
  ASSERT_EQ(mesh.positions.size(), 4u);  // the unreferenced vertex stays
  EXPECT_EQ(mesh.positions[3], Vec3(5, 5, 5));
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{2, 1, 0}));
  EXPECT_TRUE(mesh.normals.empty());
  EXPECT_TRUE(mesh.uvs.empty());
}

TEST(ObjReader, AllFaceSyntaxesGiveTheirAttributes) {
  const std::string attributes = kTriangle + "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";
  const TriangleMesh uv = parse_obj(attributes + "f 1/1 2/2 3/3\n", "t.obj");
  EXPECT_EQ(uv.uvs, (std::vector<Vec2>{{0, 0}, {1, 0}, {0, 1}}));
  EXPECT_TRUE(uv.normals.empty());
  const TriangleMesh normal = parse_obj(attributes + "f 1//1 2//1 3//1\n", "t.obj");
  EXPECT_EQ(normal.normals, (std::vector<Vec3>(3, Vec3(0, 0, 1))));
  EXPECT_TRUE(normal.uvs.empty());
  const TriangleMesh both = parse_obj(attributes + "f 1/3/1 2/2/1 3/1/1\n", "t.obj");
  EXPECT_EQ(both.uvs, (std::vector<Vec2>{{0, 1}, {1, 0}, {0, 0}}));
  EXPECT_EQ(both.normals.size(), 3u);
  EXPECT_EQ(both.positions, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(both.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(ObjReader, AttributeMissingOnAnyCornerIsDroppedForTheWholeMesh) {
  const std::string text =
      kTriangle + "v 1 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n" + "f 1/1/1 2/2/1 3/1/1\nf 2//1 4//1 3//1\n";
  const TriangleMesh mesh = parse_obj(text, "t.obj");
  EXPECT_TRUE(mesh.uvs.empty());
  EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
  // Without uvs, (v, vn) triples repeat: vertices 2 and 3 are shared between the faces.
  EXPECT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
}

TEST(ObjReader, NegativeIndicesResolveRelativeToEnd) {
  const std::string text =
      kTriangle + "f -3 -2 -1\nv 0 0 1\nf -4 -1 -2\nvn 0 0 1\nf -2//-1 -1//1 1//-1\n";
  const TriangleMesh mesh = parse_obj(text, "t.obj");
  ASSERT_EQ(mesh.triangle_count(), 3u);
  // The last face has normals on every corner only; the others lack them, so normals drop.
  EXPECT_TRUE(mesh.normals.empty());
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 3, 2, 2, 3, 0}));
}

TEST(ObjReader, ConvexPolygonsAreFanTriangulatedInFaceOrder) {
  // The pentagon (0,0), (1,0), (2,1), (1,2), (0,1); concave ones: obj_triangulation_test.cpp.
  const std::string text = kTriangle + "v 2 1 0\nv 1 2 0\nf 1 2 4 5 3\nf 5 4 3\n";
  std::vector<std::string> warnings;
  const TriangleMesh mesh = parse_obj(text, "t.obj", &warnings);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 3, 0, 3, 4, 0, 4, 2, 4, 3, 2}));
  EXPECT_TRUE(warnings.empty());
}

TEST(ObjReader, DedupesAttributeTriples) {
  const std::string text = kTriangle + "v 1 1 0\nvn 0 0 1\nvn 0 0 -1\n" +
                           "f 1//1 2//1 3//1\nf 2//1 4//1 3//1\nf 1//2 3//2 2//2\n";
  const TriangleMesh mesh = parse_obj(text, "t.obj");
  // Faces 1 and 2 share (2,1) and (3,1); face 3 uses positions 1-3 with another normal.
  EXPECT_EQ(mesh.positions.size(), 7u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 4, 5, 6}));
  EXPECT_EQ(mesh.positions[5], Vec3(0, 1, 0));
  EXPECT_EQ(mesh.normals[5], Vec3(0, 0, -1));
}

TEST(ObjReader, AcceptsCommentsBlankLinesAndIgnoredStatements) {
  const std::string text =
      "# header\r\n\r\nmtllib a.mtl\no thing\ng group\ns 1\nusemtl red\n"
      "v 0 0 0 1\t# with w\nv +1 0 0 1 0 0\nv 0 1e0 0\nvp 0.5\n  \n"
      "l 1 2\np 1\nvt 0.5\r\nf 1 2 3 # trailing comment\r\n";
  const TriangleMesh mesh = parse_obj(text, "t.obj");
  EXPECT_EQ(mesh.positions, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(mesh.triangle_count(), 1u);
}

TEST(ObjReader, DegenerateTrianglesAreKept) {
  const TriangleMesh mesh = parse_obj(kTriangle + "f 1 1 2\nf 1 2 2 3\n", "t.obj");
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 0, 1, 0, 1, 1, 0, 1, 2}));
}

TEST(ObjReader, EmptyInputGivesEmptyMesh) {
  const TriangleMesh mesh = parse_obj("# nothing\n", "t.obj");
  EXPECT_EQ(mesh.triangle_count(), 0u);
}

TEST(ObjReader, IndexZeroNamesLine) {
  expect_error(kTriangle + "f 0 1 2\n", {"bad.obj:line 4", "index 0"});
}

TEST(ObjReader, IndexOutOfRangeNamesLine) {
  expect_error(kTriangle + "f 1 2 4\n", {"bad.obj:line 4", "index 4 out of range"});
  expect_error(kTriangle + "\nf -4 1 2\n", {"bad.obj:line 5", "out of range"});
  expect_error(kTriangle + "f 1/1 2/1 3/1\n", {"line 4", "uv index 1 out of range"});
  expect_error(kTriangle + "vn 0 0 1\nf 1//2 2//1 3//1\n", {"line 5", "normal index 2"});
}

TEST(ObjReader, BadNumberNamesLine) {
  expect_error("v 0 0 0\nv 1 x 0\n", {"bad.obj:line 2", "bad number 'x'"});
  expect_error("v 0 0 0\nv 1 0.5.1 0\n", {"line 2", "bad number"});
  expect_error(kTriangle + "f 1 2 3x\n", {"line 4", "bad index '3x'"});
  expect_error(kTriangle + "f 1 2/1/1/1 3\n", {"line 4", "bad face vertex"});
}

TEST(ObjReader, MissingCoordinateNamesLine) {
  expect_error("v 0 0\n", {"bad.obj:line 1", "needs 3 numbers, found 2"});
  expect_error("vn 0 1\n", {"line 1", "'vn' needs 3"});
}

TEST(ObjReader, NonFiniteCoordinateNamesLine) {
  expect_error("v 0 0 0\n\nv nan 0 0\n", {"bad.obj:line 3", "non-finite"});
  expect_error("v inf 0 0\n", {"line 1", "non-finite"});
  expect_error("v 1e39 0 0\n", {"line 1", "non-finite"});
}

TEST(ObjReader, UnknownStatementNamesKeywordAndLine) {
  expect_error(kTriangle + "curv 0 1 1 2\n", {"bad.obj:line 4", "unknown statement 'curv'"});
}

TEST(ObjReader, FaceWithTwoVerticesNamesLine) {
  expect_error(kTriangle + "f 1 2\n", {"bad.obj:line 4", "face with 2 vertices"});
}

TEST(ObjReader, ReadMeshDispatchesOnExtensionAndNamesMissingFiles) {
  EXPECT_EQ(read_mesh(kMeshes + "cube.obj").triangle_count(), 12u);
  EXPECT_THROW(read_mesh(kMeshes + "cube.stl"), InputError);
  try {
    read_obj(kMeshes + "missing.obj");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.obj: cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace penumbra
