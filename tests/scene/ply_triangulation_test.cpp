/// PLY polygons are triangulated as OBJ polygons are (geometry/polygon_triangulator.h): the same
/// triangles from the same polygon in every PLY format, also when the faces come before the
/// vertices; convex faces keep the fan; what is wrong with a polygon is a warning naming the
/// file and the line (ascii) or byte (binary), at most 10 per file.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "penumbra/scene/obj_reader.h"
#include "penumbra/scene/ply_reader.h"
#include "ply_test_writer.h"

namespace penumbra {
namespace {

using test::Format;
using test::PlyWriter;

using Polygon = std::vector<Vec3>;

// An L-shaped hexagon (concave at (1, 1, 0)), started where the fan would leave it.
const Polygon kL = {{1, 2, 0}, {0, 2, 0}, {0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}};

// A five-pointed star in a tilted plane: 10 vertices, 5 of them reflex.
Polygon star() {
  Polygon p;
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 ? 0.4 : 1.0, phi = i * std::numbers::pi / 5;
    const float x = float(r * std::cos(phi)), y = float(r * std::sin(phi));
    p.push_back({x, y, 0.5f * x + 3.0f});
  }
  return p;
}

// One file with the given polygons over their own vertices, faces first when `faces_first`.
std::string ply_of(const std::vector<Polygon>& polys, Format format, bool faces_first = false) {
  size_t vertices = 0;
  for (const Polygon& p : polys) vertices += p.size();
  const std::string vertex_decl = "element vertex " + std::to_string(vertices) +
                                  "\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string face_decl =
      "element face " + std::to_string(polys.size()) + "\nproperty list uchar int vertex_indices\n";
  PlyWriter w(format);
  w.header(faces_first ? face_decl + vertex_decl : vertex_decl + face_decl);
  const auto put_vertices = [&] {
    for (const Polygon& p : polys)
      for (const Vec3& v : p)
        w.put("float", v.x), w.put("float", v.y), w.put("float", v.z), w.end_item();
  };
  const auto put_faces = [&] {
    double first = 0;
    for (const Polygon& p : polys) {
      std::vector<double> ids;
      for (size_t i = 0; i < p.size(); ++i) ids.push_back(first + double(i));
      first += double(p.size());
      w.list("uchar", "int", ids), w.end_item();
    }
  };
  if (faces_first)
    put_faces(), put_vertices();
  else
    put_vertices(), put_faces();
  return w.data();
}

// The same polygons as an OBJ file.
std::string obj_of(const std::vector<Polygon>& polys) {
  std::string s, f;
  size_t first = 1;
  for (const Polygon& p : polys) {
    f += "f";
    for (const Vec3& v : p) {
      char line[96];
      std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", v.x, v.y, v.z);
      s += line;
      f += ' ';  // (" " + std::string trips GCC 12's -Wrestrict)
      f += std::to_string(first++);
    }
    f += "\n";
  }
  return s + f;
}

TEST(PlyTriangulation, ConcavePolygonsGetTheObjReadersTrianglesInEveryFormat) {
  const std::vector<Polygon> polys = {kL, star(), {{0, 0, 5}, {1, 0, 5}, {1, 1, 5}, {0, 1, 5}}};
  const TriangleMesh obj = parse_obj(obj_of(polys), "t.obj");
  ASSERT_EQ(obj.triangle_count(), 4u + 8u + 2u);
  for (const Format f : {Format::kAscii, Format::kLittle, Format::kBig})
    for (const bool faces_first : {false, true}) {
      SCOPED_TRACE(std::to_string(int(f)) + (faces_first ? " faces first" : ""));
      std::vector<std::string> warnings;
      const TriangleMesh ply = parse_ply(ply_of(polys, f, faces_first), "t.ply", &warnings);
      EXPECT_EQ(ply.positions, obj.positions);
      EXPECT_EQ(ply.indices, obj.indices);
      EXPECT_TRUE(warnings.empty()) << warnings.front();
    }
  // Not the fan: the L's fan from its first vertex has the triangle (0, 4, 5), outside the L.
  const TriangleMesh ply = parse_ply(ply_of({kL}, Format::kAscii), "t.ply");
  const std::vector<uint32_t> fan = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5};
  EXPECT_NE(ply.indices, fan);
  // The L's area (3) is tiled exactly.
  double area = 0;
  for (size_t t = 0; t < ply.indices.size(); t += 3) {
    const Vec3 a = ply.positions[ply.indices[t]], b = ply.positions[ply.indices[t + 1]],
               c = ply.positions[ply.indices[t + 2]];
    area += 0.5 * double(cross(b - a, c - a).z);
  }
  EXPECT_NEAR(area, 3.0, 1e-6);
}

TEST(PlyTriangulation, ConvexFacesKeepTheFan) {
  const Polygon hexagon = {{2, 0, 0},  {1, 1.7f, 0},   {-1, 1.7f, 0},
                           {-2, 0, 0}, {-1, -1.7f, 0}, {1, -1.7f, 0}};
  const TriangleMesh ply = parse_ply(ply_of({hexagon}, Format::kLittle), "t.ply");
  EXPECT_EQ(ply.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5}));
}

TEST(PlyTriangulation, BadPolygonsAreWarnedAboutAtTheirLineOrByte) {
  const Polygon bowtie = {{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 1, 0}};  // edges 1 and 3 cross
  const Polygon bent = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5f}, {0, 1, 0}};
  std::vector<std::string> w;
  parse_ply(ply_of({bent, bowtie}, Format::kAscii), "t.ply", &w);
  ASSERT_EQ(w.size(), 2u);
  // Header: 9 lines; vertices on lines 10-17; the faces on 18 and 19.
  EXPECT_NE(w[0].find("t.ply:line 18: face of 4 vertices is not planar"), std::string::npos)
      << w[0];
  EXPECT_NE(w[1].find("t.ply:line 19: face of 4 vertices intersects itself"), std::string::npos)
      << w[1];
  w.clear();
  parse_ply(ply_of({bent}, Format::kLittle), "t.ply", &w);
  ASSERT_EQ(w.size(), 1u);
  // The face's list starts after the header and 4 vertices of 12 bytes.
  const size_t header = ply_of({bent}, Format::kLittle).size() - 48 - 17;
  EXPECT_NE(w[0].find("t.ply:byte " + std::to_string(header + 48) + ": face of 4 vertices"),
            std::string::npos)
      << w[0];
  // At most 10 listed, then one line for the rest.
  w.clear();
  parse_ply(ply_of(std::vector<Polygon>(15, bowtie), Format::kAscii), "t.ply", &w);
  ASSERT_EQ(w.size(), 11u);
  EXPECT_EQ(w.back(), "t.ply: 5 more warnings like these (the first 10 are listed)");
}

}  // namespace
}  // namespace penumbra
