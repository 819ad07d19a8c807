// The radiosity mesh: element counts, areas, twins, welding, locating points and interpolation
// weights on quads, triangles and spheres.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <tuple>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/radiosity/radiosity_mesh.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// A 2 x 1 quad (front +z, an emitter), a triangle with longest edge 1.80 (two-sided emitter), a
/// sphere of radius 1.
std::string mixed_scene() {
  return R"({
    "camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0], "vfov": 40},
    "render": {"resolution": [8, 8], "spp": 1},
    "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.6, 0.7]},
                  "shiny": {"type": "conductor", "reflectance": [0.9, 0.9, 0.9]}},
    "shapes": [
      {"type": "quad", "origin": [0, 0, 0], "edge1": [2, 0, 0], "edge2": [0, 1, 0],
       "material": "m", "emission": [1, 2, 3]},
      {"type": "mesh", "positions": [[0, 0, 3], [1.5, 0, 3], [0, 1, 3]], "indices": [[0, 1, 2]],
       "material": "m", "emission": [1, 1, 1], "two_sided": true},
      {"type": "sphere", "center": [5, 0, 0], "radius": 1, "material": "shiny"}
    ]
  })";
}

struct Built {
  World world;
  RadiosityMesh mesh;
  std::vector<std::string> warnings;
  Built(const std::string& json, float patch) : world(test::scene_from_text(json), "bvh") {
    mesh = RadiosityMesh::build(world, patch, 1000000, &warnings);
  }
};

size_t count_prim(const RadiosityMesh& mesh, uint32_t prim) {
  size_t c = 0;
  for (const RadiosityElement& e : mesh.elements()) c += e.prim == prim;
  return c;
}

// Quad 2 x 1 at patch 0.5: 4 x 2 pieces; triangle, longest edge sqrt(3.25) = 1.80: s = 4, 16
// pieces; sphere r = 1:
// n_lon = ceil(2 pi / 0.5) = 13, n_lat = ceil(pi / 0.5) = 7, 13 polar triangles per cap and
// 2 x 13 x 5 in between = 156 pieces. Each piece is two elements. At patch 10 the minimum grids:
// 1, 1 and 8 x 4 (2 x 8 x 3 = 48 pieces).
TEST(RadiosityMesh, ElementCountsFollowThePatchSize) {
  const Built b(mixed_scene(), 0.5f);
  EXPECT_EQ(count_prim(b.mesh, 0), 2u * 8);
  EXPECT_EQ(count_prim(b.mesh, 1), 2u * 16);
  EXPECT_EQ(count_prim(b.mesh, 2), 2u * 156);
  EXPECT_EQ(b.mesh.size(), 2u * (8 + 16 + 156));
  const Built coarse(mixed_scene(), 10.0f);
  EXPECT_EQ(coarse.mesh.size(), 2u * (1 + 1 + 48));
  ASSERT_EQ(b.warnings.size(), 1u);  // the conductor sphere, named once
  EXPECT_NE(b.warnings[0].find("shape 2"), std::string::npos) << b.warnings[0];
}

// A rectangle written as two triangles (as the Cornell box's walls are) is meshed as one
// parallelogram grid: 2 x 1 at patch 0.5 gives 4 x 2 pieces, not 2 x s^2 = 2 x 9 triangles, and
// hits on either triangle locate in it. Two triangles that do not complete a parallelogram (a
// kite) keep their own subdivisions.
TEST(RadiosityMesh, TrianglePairsFormingAParallelogramAreOneGrid) {
  const auto scene = [](const char* positions) {
    return fmt::format(R"({{
      "camera": {{"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0], "vfov": 40}},
      "render": {{"resolution": [8, 8], "spp": 1}},
      "materials": {{"m": {{"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}}}},
      "shapes": [{{"type": "mesh", "positions": {}, "indices": [[0, 1, 2], [0, 2, 3]],
                   "material": "m"}}]
    }})",
                       positions);
  };
  const Built rect(scene("[[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]]"), 0.5f);
  EXPECT_EQ(rect.mesh.size(), 2u * 4 * 2);
  Pcg32 rng(4);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p{2 * rng.next_float(), rng.next_float(), 0};
    const uint32_t prim = p.y < 0.5f * p.x ? 0 : 1;  // the triangle (0,1,2) lies below the diagonal
    const uint32_t e = rect.mesh.locate(prim, p, {0, 0, 1});
    ASSERT_LT(e, rect.mesh.size());
    float w[4];
    rect.mesh.corner_weights(e, p, w);
    for (int k = 0; k < 4; ++k) EXPECT_GE(w[k], -1e-4f) << "the element does not contain p";
  }
  const Built kite(scene("[[0, 0, 0], [2, 0, 0], [2.5, 1.5, 0], [0, 1, 0]]"), 0.5f);
  EXPECT_GT(kite.mesh.size(), 2u * 4 * 2);
  for (const RadiosityElement& e : kite.mesh.elements()) EXPECT_EQ(e.corners, 3);
}

TEST(RadiosityMesh, RefusesMoreElementsThanTheBudget) {
  const World world(test::scene_from_text(mixed_scene()), "bvh");
  EXPECT_THROW(RadiosityMesh::build(world, 0.5f, 359), Error);
  EXPECT_NO_THROW(RadiosityMesh::build(world, 0.5f, 360));
  EXPECT_THROW(RadiosityMesh::build(world, 0.0f, 1000), Error);
}

// Planar elements tile their primitive exactly: the areas add up to twice (both sides) the quad's
// 2 and the triangle's 0.75. The sphere's chord triangles inscribe it: their area is below 4 pi
// and approaches it as O(h^2): a flat triangle of circumradius R_c lies at least 1 - R_c^2/2 from
// the centre, and radial projection onto the unit sphere magnifies areas by at most 1/d^3, so
// the relative deficit is at most about 1.5 R_c^2. At patch 0.1 (cells of 0.098 x <= 0.0997
// rad, cut along their diagonal) R_c <= 0.071, a deficit under 0.76%.
TEST(RadiosityMesh, AreasAddUpToTheSurfaces) {
  const Built b(mixed_scene(), 0.1f);
  double area[3] = {0, 0, 0};
  for (const RadiosityElement& e : b.mesh.elements()) area[e.prim] += e.area;
  EXPECT_NEAR(area[0], 2 * 2.0, 1e-4);
  EXPECT_NEAR(area[1], 2 * 0.75, 1e-4);
  EXPECT_LT(area[2], 2 * 4 * kPi);
  EXPECT_GT(area[2], 2 * 4 * kPi * (1 - 0.0076));
}

// Every element has a twin on the same corners with the opposite normal; emission is pi L on the
// front (+z for the quad) only, on both sides of the two-sided triangle; rho is the albedo.
TEST(RadiosityMesh, TwinsShareGeometryWithOppositeNormals) {
  const Built b(mixed_scene(), 0.5f);
  const auto& els = b.mesh.elements();
  for (uint32_t i = 0; i < els.size(); ++i) {
    const RadiosityElement& e = els[i];
    ASSERT_LT(e.twin, els.size());
    const RadiosityElement& t = els[e.twin];
    EXPECT_EQ(t.twin, i);
    EXPECT_EQ(t.prim, e.prim);
    EXPECT_EQ(t.corners, e.corners);
    EXPECT_NEAR(dot(e.normal, t.normal), -1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(e.area, t.area);
    // The same corners in the opposite order: (a, b, c) -> (a, c, b), (a, b, c, d) -> (a, d, c, b).
    for (int k = 0; k < e.corners; ++k) EXPECT_EQ(t.v[k], e.v[(e.corners - k) % e.corners]);
    // The corners wind counter-clockwise about the normal.
    const auto& v = b.mesh.vertices();
    const Vec3 n = cross(v[e.v[1]] - v[e.v[0]], v[e.v[2]] - v[e.v[0]]);
    EXPECT_GT(dot(n, e.normal), 0.0f);
    if (e.prim == 0) {
      const bool front = e.normal.z > 0;
      EXPECT_NEAR(e.emission.b, front ? 3 * kPi : 0.0, 1e-5);
    } else if (e.prim == 1) {
      EXPECT_NEAR(e.emission.g, kPi, 1e-5);
    } else {
      EXPECT_EQ(e.emission.r, 0.0f);
      EXPECT_GT(dot(e.normal, e.centroid - Vec3(5, 0, 0)) * (i % 2 == 0 ? 1.0f : -1.0f), 0.0f)
          << "the sphere's front elements face outwards";
    }
    if (e.prim != 2) {
      EXPECT_FLOAT_EQ(e.rho.g, 0.6f);
    }
  }
}

// The Cornell box's walls are separate meshes that meet at the corners: each corner position is
// one vertex, shared by the elements of every wall that touches it.
TEST(RadiosityMesh, WeldsTheCornellBoxCorners) {
  const World world(test::bundled_scene("cornell-box.json"), "bvh");
  const RadiosityMesh mesh = RadiosityMesh::build(world, 100.0f, 100000);
  // The back corners join three surfaces; the front ones (the box is open at z = 0) two.
  const struct {
    Vec3 p;
    size_t shapes;
  } corners[] = {{{0, 0, 559.2f}, 3},        {{549.6f, 0, 559.2f}, 3}, {{0, 548.8f, 559.2f}, 3},
                 {{556, 548.8f, 559.2f}, 3}, {{0, 0, 0}, 2},           {{0, 548.8f, 0}, 2}};
  for (const auto& [c, expected] : corners) {
    SCOPED_TRACE(fmt::format("corner {} {} {}", c.x, c.y, c.z));
    std::vector<uint32_t> found;
    for (uint32_t v = 0; v < mesh.vertices().size(); ++v)
      if (max_component(abs(mesh.vertices()[v] - c)) < 1e-2f) found.push_back(v);
    ASSERT_EQ(found.size(), 1u);
    std::set<uint32_t> shapes;
    for (const RadiosityElement& e : mesh.elements())
      for (int k = 0; k < e.corners; ++k)
        if (e.v[k] == found[0]) shapes.insert(world.primitives().origin(e.prim).shape);
    EXPECT_EQ(shapes.size(), expected);
  }
}

/// A uniform point of element e with every barycentric / edge coordinate at least `margin`.
Vec3 point_in(const RadiosityMesh& mesh, const RadiosityElement& e, Pcg32& rng, float margin) {
  const auto& v = mesh.vertices();
  const Vec3 v0 = v[e.v[0]], v1 = v[e.v[1]], v2 = v[e.v[2]];
  if (e.corners == 4) {
    const float s = margin + (1 - 2 * margin) * rng.next_float();
    const float t = margin + (1 - 2 * margin) * rng.next_float();
    return v0 + (v1 - v0) * s + (v[e.v[3]] - v0) * t;
  }
  float b1, b2;
  do {
    b1 = rng.next_float(), b2 = rng.next_float();
  } while (b1 < margin || b2 < margin || 1 - b1 - b2 < margin);
  return v0 * (1 - b1 - b2) + v1 * b1 + v2 * b2;
}

// A point inside an element (away from its edges by 15% of its size: on a sphere, the chord of a
// cell's top and bottom edge bows away from the latitude circle by a few percent of the cell)
// is located in that element, or in its twin seen from the other side. Sphere points are the
// element's points projected radially onto the sphere (where hits lie).
TEST(RadiosityMesh, LocateFindsTheElementContainingAPoint) {
  const Built b(mixed_scene(), 0.3f);
  const auto& els = b.mesh.elements();
  Pcg32 rng(7);
  for (int trial = 0; trial < 3000; ++trial) {
    const uint32_t i = rng.next_bounded(uint32_t(els.size()));
    const RadiosityElement& e = els[i];
    Vec3 p = point_in(b.mesh, e, rng, 0.15f);
    if (e.prim == 2) p = Vec3(5, 0, 0) + normalize(p - Vec3(5, 0, 0));
    ASSERT_EQ(b.mesh.locate(e.prim, p, e.normal), i) << "trial " << trial;
    ASSERT_EQ(b.mesh.locate(e.prim, p, -e.normal), e.twin) << "trial " << trial;
  }
  EXPECT_EQ(b.mesh.locate(99, Vec3(0, 0, 0), Vec3(0, 0, 1)), UINT32_MAX);
}

// Points anywhere on a primitive, edges and corners included, land in an element of it whose
// cell contains them: the clamping never leaves the primitive's elements.
TEST(RadiosityMesh, LocateClampsPointsOnTheBoundary) {
  const Built b(mixed_scene(), 0.3f);
  const Vec3 points[] = {{0, 0, 0}, {2, 1, 0}, {2, 0, 0}, {1, 1, 0}};
  for (const Vec3 p : points) {
    const uint32_t e = b.mesh.locate(0, p, Vec3(0, 0, 1));
    ASSERT_LT(e, b.mesh.size());
    EXPECT_EQ(b.mesh.elements()[e].prim, 0u);
    EXPECT_GT(b.mesh.elements()[e].normal.z, 0.0f);
    // The corners of the found element lie within one cell of p.
    for (int k = 0; k < 4; ++k)
      EXPECT_LT(length(b.mesh.vertices()[b.mesh.elements()[e].v[k]] - p), 0.5f);
  }
  for (const Vec3 p :
       {Vec3(0, 0, 3), Vec3(1.5f, 0, 3), Vec3(0, 1, 3), Vec3(5, 0, 1), Vec3(5, 0, -1)}) {
    const uint32_t prim = p.x > 4 ? 2 : 1;
    const uint32_t e = b.mesh.locate(prim, p, Vec3(0, 0, 1));
    ASSERT_LT(e, b.mesh.size());
    EXPECT_EQ(b.mesh.elements()[e].prim, prim);
  }
}

// Adaptive subdivision, twice (a child split again): every split piece becomes four of a
// quarter area each, areas still add up, twins still mirror their fronts, midpoints shared by two
// split neighbours are one vertex, and locate finds every leaf (quads, triangles, sphere chords)
// from points inside it. Splitting the same lists again from the same build gives the same mesh.
TEST(RadiosityMesh, SubdivisionSplitsPiecesIntoFourAndLocateFindsTheLeaves) {
  Built b(mixed_scene(), 0.3f);
  const double area_before = [&] {
    double a = 0;
    for (const RadiosityElement& e : b.mesh.elements()) a += e.area;
    return a;
  }();
  const size_t n0 = b.mesh.size();
  // No two vertices at the same place, before and after: shared midpoints are welded.
  const auto duplicates = [](const RadiosityMesh& m) {
    std::set<std::tuple<float, float, float>> seen;
    size_t d = 0;
    for (const Vec3& v : m.vertices()) d += !seen.insert({v.x, v.y, v.z}).second;
    return d;
  };
  EXPECT_EQ(duplicates(b.mesh), 0u);
  std::vector<uint32_t> first;
  for (uint32_t f = 0; f < n0; f += 6) first.push_back(f);  // every third piece, all kinds
  b.mesh.subdivide(first);
  ASSERT_EQ(b.mesh.size(), n0 + 6 * first.size());
  std::vector<uint32_t> second;
  for (uint32_t f = 0; f < b.mesh.size(); f += 10) second.push_back(f);
  b.mesh.subdivide(second);
  ASSERT_EQ(b.mesh.size(), n0 + 6 * (first.size() + second.size()));
  ASSERT_EQ(b.mesh.refinements().size(), 2u);

  const auto& els = b.mesh.elements();
  double area = 0;
  for (uint32_t i = 0; i < els.size(); ++i) {
    const RadiosityElement& e = els[i];
    area += e.area;
    ASSERT_EQ(els[e.twin].twin, i);
    EXPECT_EQ(e.twin, i % 2 == 0 ? i + 1 : i - 1);
    EXPECT_NEAR(dot(e.normal, els[e.twin].normal), -1.0f, 1e-6f);
  }
  EXPECT_NEAR(area, area_before, 1e-4 * area_before);
  EXPECT_EQ(duplicates(b.mesh), 0u);

  Pcg32 rng(11);
  for (int trial = 0; trial < 4000; ++trial) {
    const uint32_t i = rng.next_bounded(uint32_t(els.size()));
    const RadiosityElement& e = els[i];
    Vec3 p = point_in(b.mesh, e, rng, 0.15f);
    if (e.prim == 2) {
      // Children of a chord triangle are planar; their hits come radially from the sphere.
      p = Vec3(5, 0, 0) + normalize(p - Vec3(5, 0, 0));
      if (b.mesh.locate(e.prim, p, e.normal) != i) continue;  // the bow of the chord
    }
    ASSERT_EQ(b.mesh.locate(e.prim, p, e.normal), i) << "trial " << trial;
    ASSERT_EQ(b.mesh.locate(e.prim, p, -e.normal), e.twin) << "trial " << trial;
  }

  Built again(mixed_scene(), 0.3f);
  again.mesh.subdivide(first);
  again.mesh.subdivide(second);
  ASSERT_EQ(again.mesh.size(), b.mesh.size());
  for (uint32_t i = 0; i < els.size(); ++i)
    for (int k = 0; k < els[i].corners; ++k)
      ASSERT_EQ(again.mesh.vertices()[again.mesh.elements()[i].v[k]],
                b.mesh.vertices()[els[i].v[k]]);
  EXPECT_THROW(again.mesh.subdivide({1}), Error);   // a back element
  EXPECT_THROW(again.mesh.subdivide({0, 0}), Error);  // twice
  EXPECT_THROW(again.mesh.subdivide({uint32_t(again.mesh.size())}), Error);
}

// Corner weights sum to 1 and interpolate the corners back to the point, on all element kinds.
TEST(RadiosityMesh, CornerWeightsReproduceThePoint) {
  const Built b(mixed_scene(), 0.3f);
  const auto& els = b.mesh.elements();
  Pcg32 rng(11);
  for (int trial = 0; trial < 2000; ++trial) {
    const uint32_t i = rng.next_bounded(uint32_t(els.size()));
    const RadiosityElement& e = els[i];
    const Vec3 p = point_in(b.mesh, e, rng, 0.0f);
    float w[4];
    b.mesh.corner_weights(i, p, w);
    Vec3 q;
    float sum = 0;
    for (int k = 0; k < e.corners; ++k) q += b.mesh.vertices()[e.v[k]] * w[k], sum += w[k];
    EXPECT_NEAR(sum, 1.0f, 1e-5f);
    EXPECT_LT(length(q - p), 1e-5f) << "trial " << trial;
    for (int k = 0; k < e.corners; ++k) EXPECT_GE(w[k], -1e-5f);
  }
}

}  // namespace
}  // namespace penumbra
