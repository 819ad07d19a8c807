// Shading normals and uvs of triangle meshes at ray hits (World::interaction), against the
// barycentric interpolation written out here: normals carried to world space by the inverse
// transpose, face-forwarded to the geometric normal's side; uvs interpolated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "penumbra/core/dvec3.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

// Double-precision vectors for the reference (core/dvec3.h).
using D3 = DVec3;
double max_diff(D3 a, D3 b) {
  return std::max({std::fabs(a.x - b.x), std::fabs(a.y - b.y), std::fabs(a.z - b.z)});
}

/// An affine map p -> A p + t with A given by its rows.
struct Affine {
  D3 row[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  D3 t;
  D3 point(D3 p) const { return D3{dot(row[0], p), dot(row[1], p), dot(row[2], p)} + t; }
  double det() const { return dot(row[0], cross(row[1], row[2])); }
  /// A^-T n = cof(A) n / det(A), the rows of the cofactor matrix being cross products of rows.
  D3 normal(D3 n) const {
    const D3 c0 = cross(row[1], row[2]), c1 = cross(row[2], row[0]), c2 = cross(row[0], row[1]);
    // A^-1 has columns c0, c1, c2 over det(A) (A c0 = (det, 0, 0), ...), so A^-T has them as rows.
    return D3{dot(c0, n), dot(c1, n), dot(c2, n)} * (1.0 / det());
  }
};

/// Rotation by `deg` about `axis` (Rodrigues) times the scale diag(s), then translated by t.
Affine rotate_scale(double deg, D3 axis, D3 s, D3 t) {
  const D3 k = normalize(axis);
  const double a = deg * std::numbers::pi / 180, c = std::cos(a), sn = std::sin(a);
  const double r[3][3] = {
      {c + k.x * k.x * (1 - c), k.x * k.y * (1 - c) - k.z * sn, k.x * k.z * (1 - c) + k.y * sn},
      {k.y * k.x * (1 - c) + k.z * sn, c + k.y * k.y * (1 - c), k.y * k.z * (1 - c) - k.x * sn},
      {k.z * k.x * (1 - c) - k.y * sn, k.z * k.y * (1 - c) + k.x * sn, c + k.z * k.z * (1 - c)}};
  Affine m;
  for (int i = 0; i < 3; ++i) m.row[i] = {r[i][0] * s.x, r[i][1] * s.y, r[i][2] * s.z};
  m.t = t;
  return m;
}

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
std::string vec(D3 v) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "[%.17g, %.17g, %.17g]", v.x, v.y, v.z);
  return buf;
}

/// Two triangles sharing the edge 1-2, slightly folded along it; unit vertex normals that differ
/// from each other and from the faces' normals; uvs that are not the barycentrics.
struct Mesh {
  D3 p[4] = {{0, 0, 0}, {2, 0, 0.3}, {0.2, 1.5, -0.2}, {2.1, 1.7, 0.2}};
  D3 n[4] = {normalize(D3{0.3, -0.2, 1}), normalize(D3{-0.5, 0.1, 1}), normalize(D3{0.1, 0.6, 0.8}),
             normalize(D3{0.4, 0.4, 1})};
  double uv[4][2] = {{0.1, 0.2}, {0.9, 0.05}, {0.3, 0.8}, {1.2, 1.1}};
  int tri[2][3] = {{0, 1, 2}, {1, 3, 2}};
};

std::string scene_json(const Mesh& m, bool with_uvs, const Affine* to_world) {
  std::string positions, normals, uvs;
  for (int i = 0; i < 4; ++i) {
    const std::string sep = i ? ", " : "";
    positions += sep + vec(m.p[i]);
    normals += sep + vec(m.n[i]);
    uvs += sep + "[" + num(m.uv[i][0]) + ", " + num(m.uv[i][1]) + "]";
  }
  std::string shape = R"({"type": "mesh", "material": "m", "positions": [)" + positions +
                      R"(], "indices": [[0, 1, 2], [1, 3, 2]], "normals": [)" + normals + "]";
  if (with_uvs) shape += R"(, "uvs": [)" + uvs + "]";
  if (to_world) {
    std::string mat;
    for (int i = 0; i < 3; ++i) {
      const D3 r = to_world->row[i];
      const double ti = i == 0 ? to_world->t.x : (i == 1 ? to_world->t.y : to_world->t.z);
      mat += num(r.x) + ", " + num(r.y) + ", " + num(r.z) + ", " + num(ti) + ", ";
    }
    shape += R"(, "transform": [{"matrix": [)" + mat + "0, 0, 0, 1]}]";
  }
  shape += "}";
  return R"({"camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
             "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
             "shapes": [)" +
         shape + "]}";
}

/// A hit to aim at: barycentrics (b1, b2) of triangle `tri` (b0 = 1 - b1 - b2).
struct Target {
  int tri;
  double b1, b2;
};

std::vector<Target> targets() {
  std::vector<Target> t;
  for (int tri = 0; tri < 2; ++tri)
    for (const auto& [b1, b2] :
         std::vector<std::pair<double, double>>{{1.0 / 3, 1.0 / 3},
                                                {0.2, 0.7},
                                                {0.6, 0.1},  // interior
                                                {1e-3, 1e-3},
                                                {0.998, 1e-3},
                                                {1e-3, 0.998},  // near each vertex
                                                {0.45, 1e-4},
                                                {1e-4, 0.3}})  // near the outer edges
      t.push_back({tri, b1, b2});
  // On the shared edge 1-2 (b0 = 0 in triangle 0): the same normal from either triangle.
  t.push_back({0, 0.4, 0.6});
  t.push_back({0, 0.75, 0.25});
  return t;
}

/// Checks every target hit of the mesh `m` (with `flip` negating its vertex normals) placed by
/// `to_world` against the reference interpolation.
void check_mesh(Mesh m, bool flip, bool with_uvs, const Affine& to_world, const char* what) {
  if (flip)
    for (D3& n : m.n) n = -n;
  const bool identity = to_world.det() == 1 && length(to_world.t) == 0;
  const auto desc = test::scene_from_text(scene_json(m, with_uvs, identity ? nullptr : &to_world));
  const World world(desc, "bvh");
  // World-space vertices, and vertex normals by the inverse transpose, each normalised (World
  // keeps unit world-space vertex normals and interpolates those).
  D3 pw[4], nw[4];
  for (int i = 0; i < 4; ++i) {
    pw[i] = to_world.point(m.p[i]);
    nw[i] = normalize(to_world.normal(m.n[i]));
  }
  RayCounter counter;
  for (const Target& tg : targets()) {
    const int* v = m.tri[tg.tri];
    const double b0 = 1 - tg.b1 - tg.b2;
    const D3 x = pw[v[0]] * b0 + pw[v[1]] * tg.b1 + pw[v[2]] * tg.b2;
    const D3 n = normalize(nw[v[0]] * b0 + nw[v[1]] * tg.b1 + nw[v[2]] * tg.b2);
    const D3 tangent = normalize(pw[v[1]] - pw[v[0]]);
    const D3 face = normalize(cross(pw[v[1]] - pw[v[0]], pw[v[2]] - pw[v[0]]));
    // Rays from both sides, slightly oblique.
    for (const double side : {1.0, -1.0}) {
      Ray ray;
      ray.o = (x + face * (3 * side) + tangent * 0.2).to_float();
      ray.d = normalize(x - D3(ray.o)).to_float();
      SurfaceInteraction si;
      ASSERT_TRUE(world.intersect(ray, si, counter)) << what;
      const std::string at = std::string(what) + ", triangle " + std::to_string(tg.tri) +
                             ", b = (" + num(tg.b1) + ", " + num(tg.b2) + "), side " + num(side);
      // Tolerances: the hit's single-precision barycentrics and the float normals carry a few
      // ulps (~1e-7) each, and the normals vary by O(1) across the triangle, so 4e-6 is some 40
      // ulps. The intended point (either triangle on the shared edge):
      ASSERT_LT(max_diff(D3(si.p), x), 1e-5) << at;
      ASSERT_LT(si.prim, 2u) << at;
      ASSERT_TRUE(si.prim == uint32_t(tg.tri) || (b0 == 0 && tg.tri == 0)) << at;
      // The front side is the winding's, carried by the transform (flipped by a mirror); the
      // shading normal is turned to it.
      const int* w = m.tri[si.prim];
      D3 ng = normalize(cross(pw[w[1]] - pw[w[0]], pw[w[2]] - pw[w[0]]));
      if (to_world.det() < 0) ng = -ng;
      const D3 ns = dot(n, ng) < 0 ? -n : n;
      EXPECT_LT(max_diff(D3(si.ng), ng), 4e-6) << at;
      EXPECT_LT(max_diff(D3(si.ns), ns), 4e-6) << at;
      EXPECT_GT(dot(D3(si.ns), D3(si.ng)), 0.0) << at;
      // The shading frame is orthonormal around ns.
      EXPECT_NEAR(dot(D3(si.ss), D3(si.ns)), 0.0, 1e-5) << at;
      EXPECT_NEAR(dot(D3(si.ts), D3(si.ns)), 0.0, 1e-5) << at;
      EXPECT_NEAR(length(D3(si.ss)), 1.0, 1e-5) << at;
      // Interpolated uvs, or without uvs the barycentrics (b1, b2) of the triangle hit.
      if (with_uvs) {
        const double u = m.uv[v[0]][0] * b0 + m.uv[v[1]][0] * tg.b1 + m.uv[v[2]][0] * tg.b2;
        const double w = m.uv[v[0]][1] * b0 + m.uv[v[1]][1] * tg.b1 + m.uv[v[2]][1] * tg.b2;
        EXPECT_NEAR(si.uv.x, u, 4e-6) << at;
        EXPECT_NEAR(si.uv.y, w, 4e-6) << at;
      } else if (si.prim == uint32_t(tg.tri)) {
        EXPECT_NEAR(si.uv.x, tg.b1, 4e-6) << at;
        EXPECT_NEAR(si.uv.y, tg.b2, 4e-6) << at;
      }
    }
  }
}

TEST(GapShadingNormal, IsTheNormalisedBarycentricInterpolation) {
  check_mesh(Mesh{}, false, true, Affine{}, "identity");
}

// Vertex normals on the back side of the winding are turned to the geometric normal's side.
TEST(GapShadingNormal, IsFaceForwardedToTheGeometricNormal) {
  check_mesh(Mesh{}, true, true, Affine{}, "flipped normals");
}

// Under a rotation with a non-uniform scale, normals go by the inverse transpose (not the matrix
// itself: the scale diag(2, 0.5, 1.5) would tilt them off the surface by tens of degrees).
TEST(GapShadingNormal, TransformsByTheInverseTranspose) {
  const Affine m = rotate_scale(40, {1, 1, 0.5}, {2, 0.5, 1.5}, {0.3, -1, 2});
  check_mesh(Mesh{}, false, true, m, "rotated and scaled");
  check_mesh(Mesh{}, true, false, m, "rotated and scaled, flipped normals, no uvs");
}

// A mirroring transform flips the front side; shading normals carried by the inverse transpose
// stay on it.
TEST(GapShadingNormal, MirroredMeshKeepsNormalsOnTheFrontSide) {
  const Affine m = rotate_scale(-65, {0.2, -1, 0.4}, {-1.5, 1, 0.7}, {-1, 0.5, 0.25});
  ASSERT_LT(m.det(), 0);
  check_mesh(Mesh{}, false, true, m, "mirrored");
}

// Without uvs a triangle's uv is its barycentrics (b1, b2) (docs/scene-format.md).
TEST(GapShadingNormal, MeshWithoutUvsUsesTheBarycentrics) {
  check_mesh(Mesh{}, false, false, Affine{}, "no uvs");
}

}  // namespace
}  // namespace penumbra
