#include "penumbra/scene/ply_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/scene/mesh_reader.h"
#include "ply_test_writer.h"

namespace penumbra {
namespace {

using test::Format;
using test::PlyWriter;

const std::string kMeshes = std::string(PENUMBRA_TEST_DATA) + "/meshes/";

const std::vector<Vec3> kCube = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},    {0, 1, 0},
                                 {0, 0, 1}, {1, 0, 1}, {1, 1, 1.25}, {-0.5, 1, 1}};
const std::vector<std::vector<double>> kQuads = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                 {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};

/// The cube with normals, uvs, and extra properties and elements of many types to skip.
std::string rich_cube(Format format, const std::string& count_type = "uchar",
                      const std::string& index_type = "int") {
  PlyWriter w(format);
  w.header(
      "comment extras of every type to skip\nelement vertex 8\nproperty double x\n"
      "property float y\nproperty float z\nproperty uchar red\n"
      "property list uchar short extra\nproperty float nx\nproperty float ny\n"
      "property float nz\nproperty ushort id\nproperty float u\nproperty double v\n"
      "element edge 2\nproperty int vertex1\nproperty list uint char tags\n"
      "element face 6\nproperty char flags\nproperty list " +
      count_type + " " + index_type +
      " vertex_indices\nproperty list ushort float weights\n"
      "property uint material\n");
  for (size_t i = 0; i < kCube.size(); ++i) {
    const Vec3 p = kCube[i];
    w.put("double", p.x), w.put("float", p.y), w.put("float", p.z), w.put("uchar", 200);
    w.list("uchar", "short", std::vector<double>(i % 3, -7));
    w.put("float", 0), w.put("float", 0), w.put("float", i % 2 ? 1 : -1);
    w.put("ushort", 60000), w.put("float", p.x * 0.5), w.put("double", 1 - p.y);
    w.end_item();
  }
  for (int e = 0; e < 2; ++e) {
    w.put("int", e), w.list("uint", "char", {-1, 2, 3}), w.end_item();
  }
  for (const std::vector<double>& quad : kQuads) {
    w.put("char", -3), w.list(count_type, index_type, quad), w.list("ushort", "float", {0.25});
    w.put("uint", 4000000000.0), w.end_item();
  }
  return w.data();
}

/// The triangles of kQuads after fan triangulation.
std::vector<uint32_t> cube_triangles() {
  std::vector<uint32_t> indices;
  for (const std::vector<double>& q : kQuads) {
    for (double v : {q[0], q[1], q[2], q[0], q[2], q[3]}) indices.push_back(uint32_t(v));
  }
  return indices;
}

/// A small binary little-endian file: 3 float vertices and the given faces (list uchar int).
std::string small_binary(const std::vector<std::vector<double>>& faces) {
  PlyWriter w(Format::kLittle);
  w.header(
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face " +
      std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\n");
  for (double v : {0, 0, 0, 1, 0, 0, 0, 1, 0}) w.put("float", v);
  for (const std::vector<double>& f : faces) w.list("uchar", "int", f);
  return w.data();
}

/// Expects parse_ply(data) to throw an InputError whose message contains every fragment.
void expect_error(const std::string& data, std::initializer_list<std::string> fragments) {
  try {
    parse_ply(data, "bad.ply");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    for (const std::string& f : fragments) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
          << "message '" << e.what() << "' lacks '" << f << "'";
    }
  }
}

const std::string kAsciiHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(PlyReader, ReadsAsciiCubeFile) {
  const TriangleMesh mesh = read_ply(kMeshes + "cube.ply");
  EXPECT_EQ(mesh.positions.size(), 8u);
  EXPECT_EQ(mesh.positions[6], Vec3(1, 1, 1));
  EXPECT_TRUE(mesh.normals.empty());
  EXPECT_TRUE(mesh.uvs.empty());
  EXPECT_EQ(mesh.triangle_count(), 12u);
  EXPECT_EQ(std::vector<uint32_t>(mesh.indices.begin(), mesh.indices.begin() + 6),
            (std::vector<uint32_t>{0, 3, 2, 0, 2, 1}));
}

TEST(PlyReader, QuadsAreFanTriangulatedAndExtraPropertiesSkipped) {
  const TriangleMesh mesh = parse_ply(rich_cube(Format::kLittle), "cube.ply");
  EXPECT_EQ(mesh.positions, kCube);
  EXPECT_EQ(mesh.indices, cube_triangles());
  ASSERT_EQ(mesh.normals.size(), 8u);
  EXPECT_EQ(mesh.normals[1], Vec3(0, 0, 1));
  EXPECT_EQ(mesh.normals[2], Vec3(0, 0, -1));
  ASSERT_EQ(mesh.uvs.size(), 8u);
  EXPECT_EQ(mesh.uvs[7], Vec2(-0.25f, 0));
}

TEST(PlyReader, BigEndianMatchesLittleEndian) {
  const TriangleMesh little = parse_ply(rich_cube(Format::kLittle), "le.ply");
  const TriangleMesh big = parse_ply(rich_cube(Format::kBig), "be.ply");
  EXPECT_EQ(big.positions, little.positions);
  EXPECT_EQ(big.normals, little.normals);
  EXPECT_EQ(big.uvs, little.uvs);
  EXPECT_EQ(big.indices, little.indices);
}

TEST(PlyReader, AsciiMatchesBinary) {
  const TriangleMesh binary = parse_ply(rich_cube(Format::kLittle), "le.ply");
  const TriangleMesh ascii = parse_ply(rich_cube(Format::kAscii), "ascii.ply");
  EXPECT_EQ(ascii.positions, binary.positions);
  EXPECT_EQ(ascii.normals, binary.normals);
  EXPECT_EQ(ascii.uvs, binary.uvs);
  EXPECT_EQ(ascii.indices, binary.indices);
}

TEST(PlyReader, AcceptsEveryIntegerListType) {
  for (const char* count : {"char", "uchar", "short", "ushort", "int", "uint", "int8", "uint32"}) {
    for (const char* index : {"uchar", "short", "ushort", "int", "uint", "uint8", "int32"}) {
      for (Format format : {Format::kAscii, Format::kLittle, Format::kBig}) {
        EXPECT_EQ(parse_ply(rich_cube(format, count, index), "t.ply").indices, cube_triangles())
            << count << " " << index;
      }
    }
  }
}

TEST(PlyReader, DegenerateTrianglesAreKept) {
  const TriangleMesh mesh = parse_ply(small_binary({{0, 0, 1}, {0, 1, 1, 2}}), "t.ply");
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 0, 1, 0, 1, 1, 0, 1, 2}));
}

TEST(PlyReader, ReadMeshDispatchesBinaryFile) {
  const std::string path = ::testing::TempDir() + "penumbra_ply_reader_test.PLY";
  std::ofstream(path, std::ios::binary) << rich_cube(Format::kBig);
  EXPECT_EQ(read_mesh(path).indices, cube_triangles());
  std::remove(path.c_str());
}

TEST(PlyReader, TruncatedBinaryNamesByteOffset) {
  const std::string data = small_binary({{0, 1, 2, 0, 1, 2}, {2, 1, 0}});
  // The last index starts 4 bytes before the end; cut it in half.
  const size_t offset = data.size() - 4;
  expect_error(data.substr(0, data.size() - 2),
               {"bad.ply:byte " + std::to_string(offset), "unexpected end of file", "item 1"});
}

TEST(PlyReader, TruncatedAsciiNamesLine) {
  expect_error(kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", {"bad.ply:line 14", "end of file"});
}

TEST(PlyReader, HeaderCountLargerThanFileFailsBeforeAllocating) {
  std::string data = small_binary({{0, 1, 2}});
  data.replace(data.find("vertex 3"), 8, "vertex 1099511627776");
  expect_error(data, {"bad.ply:line 3", "1099511627776", "more than 32-bit indices"});
  data = small_binary({{0, 1, 2}});
  data.replace(data.find("vertex 3"), 8, "vertex 4000000000");
  expect_error(data, {"bad.ply:line 3", "4000000000", "bytes follow the header"});
  data = small_binary({{0, 1, 2}});
  data.replace(data.find("face 1"), 6, "face 4000000000");
  expect_error(data, {"bad.ply:line 7", "4000000000"});
  expect_error(kAsciiHead + "0 0 0\n", {"bad.ply:line 3", "declares 3 items"});
}

TEST(PlyReader, BadTypeNameNamesHeaderLine) {
  std::string data = kAsciiHead;
  data.replace(data.find("float y"), 5, "flaot");
  expect_error(data, {"bad.ply:line 5", "unknown type 'flaot'"});
}

TEST(PlyReader, MissingVertexIndicesNamesFaceElement) {
  std::string data = kAsciiHead;
  data.replace(data.find("vertex_indices"), 14, "corner_indices");
  expect_error(data + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", {"bad.ply:line 7", "vertex_indices"});
}

TEST(PlyReader, IndexOutOfRangeNamesPlace) {
  const std::string data = small_binary({{0, 1, 2}, {0, 3, 1}});
  const size_t offset = data.size() - 8;  // the second index of the second face
  expect_error(data, {"bad.ply:byte " + std::to_string(offset), "index 3 out of range"});
  expect_error(small_binary({{0, -1, 2}}), {"index -1 out of range"});
  expect_error(kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n\n3 0 1 7\n", {"bad.ply:line 14", "index 7"});
}

TEST(PlyReader, NonNumberInAsciiNamesLine) {
  expect_error(kAsciiHead + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n",
               {"bad.ply:line 11", "expected a number, found 'zero'"});
  expect_error(kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", {"line 13", "expected an integer"});
}

TEST(PlyReader, NegativeCountsAreErrors) {
  expect_error(kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", {"line 13", "negative list count"});
  std::string data = kAsciiHead;
  data.replace(data.find("face 1"), 6, "face -1");
  expect_error(data, {"bad.ply:line 7", "negative count"});
}

TEST(PlyReader, NonFiniteCoordinatesNamePlace) {
  expect_error(kAsciiHead + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", {"bad.ply:line 11", "non-finite"});
  PlyWriter w(Format::kLittle);
  w.header(
      "element vertex 1\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 0\nproperty list uchar int vertex_indices\n");
  w.put("double", 0), w.put("double", 1e300), w.put("double", 0);
  expect_error(w.data(), {"bad.ply:byte " + std::to_string(w.data().size() - 24), "non-finite"});
}

TEST(PlyReader, FaceWithTwoVerticesIsAnError) {
  const std::string data = small_binary({{0, 1, 2, 0, 1, 2}, {0, 1}});
  expect_error(data, {"bad.ply:byte " + std::to_string(data.size() - 9), "face with 2 vertices"});
  std::string ascii = kAsciiHead;
  ascii.replace(ascii.find("face 1"), 6, "face 2");
  expect_error(ascii + "0 0 0\n1 0 0\n0 1 0\n4 0 1 2 0\n2 0 1\n", {"line 14", "face with 2"});
}

TEST(PlyReader, HeaderProblemsNameLine) {
  expect_error("PLY\nformat ascii 1.0\n", {"bad.ply:line 1", "bad magic"});
  expect_error("solid cube\n", {"bad.ply:line 1", "bad magic"});
  expect_error("ply\nformat ascii 1.0\nelement vertex 0\n", {"bad.ply:line 4", "end_header"});
  expect_error("ply\nformat text 1.0\nend_header\n", {"bad.ply:line 2", "unknown format"});
  expect_error("ply\nelement vertex 0\nend_header\n", {"bad.ply:line 3", "missing 'format'"});
  expect_error("ply\nformat ascii 1.0\nproperty float x\nend_header\n",
               {"line 3", "property before any element"});
  expect_error(
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nelement face 0\n"
      "property list uchar int vertex_indices\nend_header\n",
      {"bad.ply:line 3", "has no property 'y'"});
  std::string data = kAsciiHead;
  data.replace(data.find("element face 1"), 14, "element face 1\nbogus line");
  expect_error(data, {"bad.ply:line 8", "unknown header keyword 'bogus'"});
  data = kAsciiHead;
  const std::string face = "element face 1\nproperty list uchar int vertex_indices\n";
  data.replace(data.find(face), face.size(), "");
  expect_error(data, {"bad.ply:line 7", "no 'face' element"});
}

}  // namespace
}  // namespace penumbra
