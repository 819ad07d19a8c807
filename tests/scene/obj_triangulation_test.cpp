/// Tests of the triangulation of OBJ polygons (geometry/polygon_triangulator.h, through
/// parse_obj): convex polygons keep the fan; concave ones are tiled inside their outline with
/// their exact area, in every plane, winding and starting vertex; what is wrong with a polygon is
/// a warning naming the file and line, limited per file; and the warnings reach a scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "../image/temp_dir.h"
#include "penumbra/core/dvec3.h"
#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/geometry/polygon_triangulator.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/mesh_warnings.h"
#include "penumbra/scene/obj_reader.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

using Polygon = std::vector<Vec2d>;

/// A plane to place 2D polygons in: origin + x e1 + y e2, with e1, e2 orthonormal.
struct Plane {
  const char* name;
  DVec3 origin, e1, e2;
};

const Plane kPlanes[] = {
    {"xy", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
    {"yz", {0, 0, 0}, {0, 1, 0}, {0, 0, 1}},
    {"zx", {0, 0, 0}, {0, 0, 1}, {1, 0, 0}},
    {"tilted", {3, -2, 5}, DVec3(2, 2, 1) * (1.0 / 3), DVec3(-1, 2, -2) * (1.0 / 3)},
};

/// Twice the signed area (positive when counter-clockwise).
double area2(const Polygon& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) a += cross(p[i], p[(i + 1) % p.size()]);
  return a;
}

/// Even-odd point-in-polygon test (edges that a polygon walks twice, both ways, cancel out).
bool inside(const Polygon& p, Vec2d q) {
  bool in = false;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
    if ((p[i].y > q.y) != (p[j].y > q.y) &&
        q.x < p[j].x + (q.y - p[j].y) * (p[i].x - p[j].x) / (p[i].y - p[j].y))
      in = !in;
  }
  return in;
}

/// `p` started at vertex `start` and, when `reversed`, walked the other way.
Polygon reordered(const Polygon& p, size_t start, bool reversed) {
  Polygon out;
  for (size_t i = 0; i < p.size(); ++i) {
    const size_t k = reversed ? (start + p.size() - i) % p.size() : (start + i) % p.size();
    out.push_back(p[k]);
  }
  return out;
}

/// OBJ text: the vertices of `poly` placed in `plane`, then one face through all of them.
std::string face_obj(const Polygon& poly, const Plane& plane = kPlanes[0]) {
  std::string text, face = "f";
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3 p = (plane.origin + plane.e1 * poly[i].x + plane.e2 * poly[i].y).to_float();
    text += fmt::format("v {} {} {}\n", p.x, p.y, p.z);
    face.append(" ").append(std::to_string(i + 1));
  }
  return text + face + "\n";
}

/// The fan (0, i, i + 1) of an n-gon.
std::vector<uint32_t> fan(uint32_t n) {
  std::vector<uint32_t> out;
  for (uint32_t i = 1; i + 1 < n; ++i) out.insert(out.end(), {0, i, i + 1});
  return out;
}

/// Expects the triangles of `mesh` (the vertices of `poly` placed in `plane`, in order) to tile
/// `poly`: n - 2 triangles, facing the way the polygon winds, non-degenerate ones centred inside
/// it (as read back from the mesh, so float rounding cannot move a centroid across an edge), with
/// the polygon's area in all.
void expect_tiles(const TriangleMesh& mesh, const Polygon& poly, const Plane& plane) {
  ASSERT_EQ(mesh.triangle_count(), poly.size() - 2);
  ASSERT_EQ(mesh.positions.size(), poly.size());
  const auto in_plane = [&](const DVec3& p) {
    return Vec2d(dot(p - plane.origin, plane.e1), dot(p - plane.origin, plane.e2));
  };
  Polygon read;
  for (const Vec3& p : mesh.positions) read.push_back(in_plane(DVec3(p)));
  const double area = std::fabs(area2(poly)) / 2;
  const DVec3 facing = cross(plane.e1, plane.e2) * (area2(poly) > 0 ? 1.0 : -1.0);
  double sum = 0;
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const DVec3 a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]),
        c(mesh.positions[mesh.indices[3 * t + 2]]);
    const DVec3 n = cross(b - a, c - a);
    const double tri = length(n) / 2;
    sum += tri;
    if (tri < 1e-6 * area) continue;  // a zero-area triangle of a repeated or collinear vertex
    EXPECT_GT(dot(n, facing), 0) << "triangle " << t << " faces the wrong way";
    const Vec2d q = in_plane((a + b + c) * (1.0 / 3));
    EXPECT_TRUE(inside(read, q)) << "triangle " << t << " is centred outside at " << q.x << ", "
                                 << q.y;
  }
  EXPECT_NEAR(sum, area, 1e-5 * area);
}

/// Expects the n - 2 triangles of `mesh`, a face of n vertices, to have the face's vector area
/// in sum: true of every fan and of every sequence of ears, whatever the polygon, so it checks
/// the bookkeeping (indices, the ring of vertices left) rather than the geometry.
void expect_vector_area(const TriangleMesh& mesh, size_t n) {
  ASSERT_EQ(mesh.triangle_count(), n - 2);
  DVec3 polygon, triangles;
  const DVec3 o(mesh.positions[0]);
  for (size_t i = 0; i < n; ++i)
    polygon = polygon + cross(DVec3(mesh.positions[i]) - o, DVec3(mesh.positions[(i + 1) % n]) - o);
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    for (size_t k = 0; k < 3; ++k) ASSERT_LT(mesh.indices[3 * t + k], n);
    const DVec3 a(mesh.positions[mesh.indices[3 * t]]), b(mesh.positions[mesh.indices[3 * t + 1]]),
        c(mesh.positions[mesh.indices[3 * t + 2]]);
    triangles = triangles + cross(b - a, c - a);
  }
  EXPECT_LT(length(triangles - polygon), 1e-9 * double(n)) << length(polygon);
}

/// A plane through a random point with a random orientation.
Plane random_plane(Pcg32& rng) {
  const auto random_vector = [&] {
    return DVec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5);
  };
  const DVec3 e1 = normalize(random_vector()), r = random_vector();
  return {"random", random_vector() * 10.0, e1, normalize(r - e1 * dot(r, e1))};
}

/// Parses `text` as "t.obj"; its warnings go to `warnings`.
TriangleMesh parse(const std::string& text, std::vector<std::string>& warnings) {
  warnings.clear();
  return parse_obj(text, "t.obj", &warnings);
}

/// An L-shaped hexagon of area 3, whose fan from most of its vertices leaves it.
const Polygon kL = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};

/// A five-pointed star: 10 vertices, radii 1 and 0.4.
Polygon star() {
  Polygon p;
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 ? 0.4 : 1.0, phi = i * std::numbers::pi / 5;
    p.push_back({float(r * std::cos(phi)), float(r * std::sin(phi))});
  }
  return p;
}

/// A comb of `teeth` teeth (1 wide, 9 high, 1 apart) on a base of height 1: 4 * teeth vertices,
/// counter-clockwise, area 11 * teeth - 1.
Polygon comb(int teeth) {
  const double w = 2 * teeth - 1;
  Polygon p = {{0, 0}, {w, 0}};
  for (int j = teeth - 1; j >= 0; --j) {
    p.push_back({2.0 * j + 1, 10});
    p.push_back({2.0 * j, 10});
    if (j > 0) {
      p.push_back({2.0 * j, 1});
      p.push_back({2.0 * j - 1, 1});
    }
  }
  return p;
}

TEST(ObjTriangulation, ConcavePolygonsAreTiledInEveryPlaneWindingAndStart) {
  std::vector<std::string> warnings;
  for (const Polygon& base : {kL, star()}) {
    for (const Plane& plane : kPlanes) {
      for (const bool reversed : {false, true}) {
        for (size_t start = 0; start < base.size(); ++start) {
          SCOPED_TRACE(fmt::format("{} vertices, {} plane, start {}{}", base.size(), plane.name,
                                   start, reversed ? ", reversed" : ""));
          const Polygon poly = reordered(base, start, reversed);
          expect_tiles(parse(face_obj(poly, plane), warnings), poly, plane);
          EXPECT_TRUE(warnings.empty()) << warnings.front();
        }
      }
    }
  }
}

TEST(ObjTriangulation, TheLShapeIsNotFannedFromAVertexThatDoesNotSeeItAll) {
  // Started next to the reflex corner (1, 1), the fan's triangle (0, 4, 5) would be centred
  // outside the L, at (4/3, 4/3).
  const Polygon poly = reordered(kL, 4, false);  // (1,2), (0,2), (0,0), (2,0), (2,1), (1,1)
  EXPECT_FALSE(inside(poly, (poly[0] + poly[4] + poly[5]) * (1.0 / 3)));
  std::vector<std::string> warnings;
  const TriangleMesh mesh = parse(face_obj(poly), warnings);
  EXPECT_NE(mesh.indices, fan(6));
  expect_tiles(mesh, poly, kPlanes[0]);
}

TEST(ObjTriangulation, ConvexPolygonsKeepTheFanExactly) {
  Polygon pentagon;
  for (int i = 0; i < 5; ++i) {
    const double phi = 0.3 + 2 * std::numbers::pi * i / 5;
    pentagon.push_back({float(std::cos(phi)), float(2 * std::sin(phi))});
  }
  const Polygon with_collinear = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {1, 1}, {0, 1}};
  const Polygon with_repeat = {{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<std::string> warnings;
  for (const Polygon& base : {pentagon, with_collinear, with_repeat}) {
    for (const Plane& plane : kPlanes) {
      for (const bool reversed : {false, true}) {
        for (size_t start = 0; start < base.size(); ++start) {
          SCOPED_TRACE(fmt::format("{} vertices, {} plane, start {}{}", base.size(), plane.name,
                                   start, reversed ? ", reversed" : ""));
          const Polygon poly = reordered(base, start, reversed);
          const TriangleMesh mesh = parse(face_obj(poly, plane), warnings);
          EXPECT_EQ(mesh.indices, fan(uint32_t(poly.size())));
          expect_tiles(mesh, poly, plane);
          EXPECT_TRUE(warnings.empty()) << warnings.front();
        }
      }
    }
  }
}

TEST(ObjTriangulation, RepeatedAndCollinearVerticesOfAConcavePolygon) {
  // The L with a vertex written twice, a collinear vertex on an edge and one on the reflex
  // corner's edge: n - 2 triangles, some of zero area, tiling the L without a warning.
  const Polygon base = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 1}, {1.5, 1},
                        {1, 1}, {1, 2}, {0, 2}, {0, 2}, {0, 1}};
  std::vector<std::string> warnings;
  for (const bool reversed : {false, true}) {
    for (size_t start = 0; start < base.size(); ++start) {
      SCOPED_TRACE(fmt::format("start {}{}", start, reversed ? ", reversed" : ""));
      const Polygon poly = reordered(base, start, reversed);
      expect_tiles(parse(face_obj(poly, kPlanes[3]), warnings), poly, kPlanes[3]);
      EXPECT_TRUE(warnings.empty()) << warnings.front();
    }
  }
}

TEST(ObjTriangulation, PolygonWithAHoleCutOpen) {
  // A 4 x 4 square with a 2 x 2 hole, joined by a cut walked both ways: the outline passes
  // through (0, 0) and (1, 1) twice. Area 12, nothing inside the hole, no warning.
  const Polygon base = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {0, 0},
                        {1, 1}, {1, 3}, {3, 3}, {3, 1}, {1, 1}};
  std::vector<std::string> warnings;
  for (const bool reversed : {false, true}) {
    for (size_t start = 0; start < base.size(); ++start) {
      SCOPED_TRACE(fmt::format("start {}{}", start, reversed ? ", reversed" : ""));
      const Polygon poly = reordered(base, start, reversed);
      expect_tiles(parse(face_obj(poly), warnings), poly, kPlanes[0]);
      EXPECT_TRUE(warnings.empty()) << warnings.front();
    }
  }
}

TEST(ObjTriangulation, RandomStarShapedAndSkylinePolygonsAreTiled) {
  Pcg32 rng(18);
  std::vector<std::string> warnings;
  for (int trial = 0; trial < 400; ++trial) {
    Polygon poly;
    if (trial % 2 == 0) {
      // Star-shaped about the origin: increasing angles, radii from 0.2 to 1.
      std::vector<double> angles(4 + rng.next_bounded(60));
      for (double& a : angles) a = 2 * std::numbers::pi * rng.next_double();
      std::sort(angles.begin(), angles.end());
      for (const double a : angles) {
        const double r = 0.2 + 0.8 * rng.next_double();
        poly.push_back({r * std::cos(a), r * std::sin(a)});
      }
    } else {
      // A skyline of columns of heights 1 to 4: equal neighbours give collinear and repeated
      // vertices.
      const int columns = 1 + int(rng.next_bounded(30));
      poly = {{0, 0}, {double(columns), 0}};
      for (int x = columns - 1; x >= 0; --x) {
        const double h = 1 + rng.next_bounded(4);
        poly.push_back({x + 1.0, h});
        poly.push_back({double(x), h});
      }
    }
    const Plane plane = trial % 3 == 0 ? kPlanes[trial % 4] : random_plane(rng);
    const Polygon p = reordered(poly, rng.next_bounded(uint32_t(poly.size())), trial % 5 < 2);
    SCOPED_TRACE(fmt::format("trial {}: {} vertices", trial, p.size()));
    expect_tiles(parse(face_obj(p, plane), warnings), p, plane);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }
}

/// True when the open segments ab and cd cross (exact enough for random doubles).
bool proper_cross(Vec2d a, Vec2d b, Vec2d c, Vec2d d) {
  const auto side = [](Vec2d p, Vec2d q, Vec2d r) { return cross(q - p, r - p); };
  return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
}

/// A random simple polygon: random points, joined in random order, then untangled by reversing
/// the path between two crossing edges (2-opt) until no edges cross; each reversal shortens it.
Polygon random_simple_polygon(Pcg32& rng, size_t n) {
  Polygon p(n);
  for (Vec2d& v : p) v = {rng.next_double(), rng.next_double()};
  for (bool crossed = true; crossed;) {
    crossed = false;
    for (size_t i = 0; i < n && !crossed; ++i) {
      for (size_t j = i + 2; j < n && !crossed; ++j) {
        if (i == 0 && j == n - 1) continue;
        if (proper_cross(p[i], p[i + 1], p[j], p[(j + 1) % n])) {
          std::reverse(p.begin() + long(i) + 1, p.begin() + long(j) + 1);
          crossed = true;
        }
      }
    }
  }
  return p;
}

TEST(ObjTriangulation, RandomSimplePolygonsAreTiled) {
  Pcg32 rng(2024);
  std::vector<std::string> warnings;
  for (int trial = 0; trial < 300; ++trial) {
    const Polygon p = random_simple_polygon(rng, 4 + rng.next_bounded(40));
    const Plane plane = trial % 2 ? kPlanes[trial % 4] : random_plane(rng);
    SCOPED_TRACE(fmt::format("trial {}: {} vertices", trial, p.size()));
    expect_tiles(parse(face_obj(p, plane), warnings), p, plane);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
  }
}

TEST(ObjTriangulation, RandomPolygonsAlwaysGiveTheirTriangles) {
  // Random vertices, often on a small grid: crossing, touching, repeated and collinear.
  Pcg32 rng(7);
  std::vector<std::string> warnings;
  for (int trial = 0; trial < 1000; ++trial) {
    const size_t n = 4 + rng.next_bounded(40);
    const bool grid = trial % 2 == 0;
    Polygon poly;
    for (size_t i = 0; i < n; ++i) {
      poly.push_back(grid ? Vec2d(rng.next_bounded(4), rng.next_bounded(4))
                          : Vec2d(rng.next_double(), rng.next_double()));
    }
    SCOPED_TRACE(fmt::format("trial {}: {} vertices", trial, n));
    expect_vector_area(parse(face_obj(poly, kPlanes[trial % 4]), warnings), n);
  }
}

TEST(ObjTriangulation, NonPlanarPolygonWarnsWithFileAndLine) {
  std::vector<std::string> warnings;
  const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0.2\nv 0 1 0\n";
  const TriangleMesh mesh = parse(quad + "f 1 2 3 4\n", warnings);
  EXPECT_EQ(mesh.indices, fan(4));  // convex seen along its normal: the fan
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "t.obj:line 5: face of 4 vertices is not planar (a vertex is 0.035 of its size from "
            "its plane); triangulated anyway");
  // Within the tolerance (1e-3 of the size): no warning.
  parse("v 0 0 0\nv 1 0 0\nv 1 1 0.0005\nv 0 1 0\nf 1 2 3 4\n", warnings);
  EXPECT_TRUE(warnings.empty());
  // Without a list the warnings are dropped, and the mesh is the same.
  EXPECT_EQ(parse_obj(quad + "f 1 2 3 4\n", "t.obj").indices, mesh.indices);
}

TEST(ObjTriangulation, SelfIntersectingPolygonsWarnAndTerminate) {
  std::vector<std::string> warnings;
  // A pentagram: every turn is a left turn, but it winds twice.
  Polygon pentagram;
  for (int i = 0; i < 5; ++i) {
    const double phi = 4 * std::numbers::pi * i / 5;
    pentagram.push_back({float(std::cos(phi)), float(std::sin(phi))});
  }
  EXPECT_EQ(parse(face_obj(pentagram), warnings).triangle_count(), 3u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("t.obj:line 6: face of 5 vertices intersects itself (its edges", 0),
            0u)
      << warnings[0];
  // A bow-tie with lobes of different sizes: only its edges 1-2 and 3-4 cross.
  const Polygon bow_tie = {{0, 0}, {2, 2}, {2, 0}, {0, 1}};
  EXPECT_EQ(parse(face_obj(bow_tie), warnings).triangle_count(), 2u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "t.obj:line 5: face of 4 vertices intersects itself (its edges from corner 1 to 2 and "
            "from 3 to 4 cross); triangulated anyway, its triangles may overlap");
  // A comb whose last tooth is bent across its neighbour: still n - 2 triangles.
  Polygon crossed = comb(6);
  crossed[2].x = 7;
  EXPECT_EQ(parse(face_obj(crossed), warnings).triangle_count(), crossed.size() - 2);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("intersects itself"), std::string::npos) << warnings[0];
}

TEST(ObjTriangulation, PolygonsWithNoAreaWarn) {
  std::vector<std::string> warnings;
  const Polygon symmetric_bow_tie = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  const Polygon collinear = {{0, 0}, {1, 1}, {3, 3}, {2, 2}, {0.5, 0.5}};
  const Polygon one_point = {{1, 1}, {1, 1}, {1, 1}, {1, 1}};
  for (const Polygon& poly : {symmetric_bow_tie, collinear, one_point}) {
    EXPECT_EQ(parse(face_obj(poly), warnings).indices, fan(uint32_t(poly.size())));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(fmt::format("t.obj:line {}: face of {} vertices encloses no area",
                                           poly.size() + 1, poly.size())),
              std::string::npos)
        << warnings[0];
  }
}

TEST(ObjTriangulation, LargeConcaveCombIsTiled) {
  std::vector<std::string> warnings;
  const Polygon poly = comb(1250);  // 5000 vertices
  ASSERT_EQ(poly.size(), 5000u);
  const TriangleMesh mesh = parse(face_obj(poly, kPlanes[1]), warnings);
  expect_tiles(mesh, poly, kPlanes[1]);
  EXPECT_NEAR(std::fabs(area2(poly)) / 2, 11 * 1250 - 1, 1e-9);
  EXPECT_TRUE(warnings.empty());
}

TEST(ObjTriangulation, ConcavePolygonsAboveTheLimitGetTheFanWithAWarning) {
  std::vector<std::string> warnings;
  // At the limit: ear-clipped.
  const Polygon at_limit = comb(int(kMaxEarClipVertices / 4));
  ASSERT_EQ(at_limit.size(), kMaxEarClipVertices);
  expect_tiles(parse(face_obj(at_limit), warnings), at_limit, kPlanes[0]);
  EXPECT_TRUE(warnings.empty());
  // A million vertices: the fan, at once.
  const Polygon huge = comb(250000);
  const TriangleMesh mesh = parse(face_obj(huge), warnings);
  EXPECT_EQ(mesh.indices, fan(uint32_t(huge.size())));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0],
            "t.obj:line 1000001: face of 1000000 vertices is concave and has more than 10000 "
            "vertices, the most that are ear-clipped; fan-triangulated, so its triangles may "
            "cover area outside it");
}

TEST(ObjTriangulation, ConcavePolygonsBeyondTheFilesBudgetGetTheFanWithAWarning) {
  const Polygon poly = comb(250);  // 1000 vertices: 10^6 units of ear-clipping work
  std::vector<Vec3> points;
  for (const Vec2d& q : poly) points.push_back(Vec3(float(q.x), float(q.y), 0.0f));
  const std::vector<Vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  PolygonTriangulator triangulator(2.5e6);  // room for two
  std::vector<uint32_t> out;
  for (int i = 0; i < 3; ++i) {
    out.clear();
    const PolygonReport r = triangulator.triangulate(points, out);
    EXPECT_EQ(r.budget_spent, i == 2) << "polygon " << i;
    EXPECT_EQ(r.any(), i == 2) << "polygon " << i;
    EXPECT_EQ(out.size(), 3 * 998u);
    if (i < 2)
      EXPECT_NE(out, fan(1000)) << "polygon " << i;
    else
      EXPECT_EQ(out, fan(1000));
    // Convex polygons take the fan in O(n) and do not draw on the budget.
    out.clear();
    EXPECT_FALSE(triangulator.triangulate(square, out).any());
  }
  PolygonReport spent;
  spent.budget_spent = true;
  const std::vector<std::string> problems = polygon_problems(spent, 1000);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0],
            "face of 1000 vertices is concave, and this file's concave faces have used up the "
            "ear-clipping budget (the work of 20 faces of 10000 vertices); fan-triangulated, so "
            "its triangles may cover area outside it");
  // A new triangulator (a new file) has its budget again.
  PolygonTriangulator fresh(2.5e6);
  out.clear();
  EXPECT_FALSE(fresh.triangulate(points, out).budget_spent);
}

TEST(ObjTriangulation, WarningsAreLimitedPerFile) {
  std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 1\nv 0 1 0\n";
  for (int i = 0; i < 25; ++i) text += "f 1 2 3 4\n";
  std::vector<std::string> warnings;
  EXPECT_EQ(parse(text, warnings).triangle_count(), 50u);
  ASSERT_EQ(warnings.size(), 11u);
  EXPECT_EQ(warnings[0].rfind("t.obj:line 5: face of 4 vertices is not planar", 0), 0u);
  EXPECT_EQ(warnings[9].rfind("t.obj:line 14: ", 0), 0u);
  EXPECT_EQ(warnings[10], "t.obj: 15 more warnings like these (the first 10 are listed)");
}

TEST(ObjWarnings, ReachTheSceneThroughTheLoaderAndReadMesh) {
  const test::TempDir dir;
  test::write_bytes(dir.file("bent.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0.2\nv 0 1 0\nf 1 2 3 4\n");
  test::write_bytes(dir.file("scene.json"),
                    R"({"camera": {"type": "pinhole"}, "materials": {"m": {"type": "diffuse"}},
                        "shapes": [{"type": "obj", "file": "bent.obj", "material": "m"}]})");
  const SceneDesc scene = load_scene(dir.file("scene.json"));
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0].rfind(dir.file("bent.obj") + ":line 5: face of 4 vertices is not "
                                                           "planar",
                                    0),
            0u)
      << scene.warnings[0];
  std::vector<std::string> warnings;
  EXPECT_EQ(read_mesh(dir.file("bent.obj"), &warnings).triangle_count(), 2u);
  EXPECT_EQ(warnings, scene.warnings);
}

TEST(ObjWarnings, MeshFilesWithoutTrianglesAreRefusedAsSceneShapes) {
  const test::TempDir dir;
  test::write_bytes(dir.file("points.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  test::write_bytes(dir.file("points.ply"),
                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                    "end_header\n0 0 0\n1 0 0\n0 1 0\n");
  for (const char* type : {"obj", "ply"}) {
    const std::string file = dir.file(std::string("points.") + type);
    test::write_bytes(dir.file("scene.json"), fmt::format(R"({{"camera": {{"type": "pinhole"}},
                          "materials": {{"m": {{"type": "diffuse"}}}},
                          "shapes": [{{"type": "{}", "file": "points.{}", "material": "m"}}]}})",
                                                          type, type));
    try {
      load_scene(dir.file("scene.json"));
      ADD_FAILURE() << "no error for " << file;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                dir.file("scene.json") + ":/shapes/0/file: mesh file has no triangles: " + file);
    }
  }
}

}  // namespace
}  // namespace penumbra
