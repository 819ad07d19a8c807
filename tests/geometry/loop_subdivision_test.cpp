// Loop subdivision: counts (4^levels triangles, Euler's formula), convergence of the platonic
// solids towards smooth surfaces inside the control hull, planarity of flat meshes and their
// boundaries, the weights checked by hand, limit normals, and the errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/geometry/loop_subdivision.h"

namespace penumbra {
namespace {

/// A regular octahedron of circumradius 1, outward winding.
void octahedron(std::vector<Vec3>& p, std::vector<uint32_t>& idx) {
  p = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  idx = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
}

/// A regular tetrahedron centred at the origin, outward winding.
void tetrahedron(std::vector<Vec3>& p, std::vector<uint32_t>& idx) {
  p = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  idx = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
}

/// A flat n x n grid of unit squares in z = 0, split along one diagonal (valence 6 inside).
void grid(int n, std::vector<Vec3>& p, std::vector<uint32_t>& idx) {
  p.clear(), idx.clear();
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) p.push_back({float(x), float(y), 0});
  const auto at = [n](int x, int y) { return uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      idx.insert(idx.end(), {at(x, y), at(x + 1, y), at(x + 1, y + 1)});
      idx.insert(idx.end(), {at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    }
}

/// Number of distinct edges of a triangle list.
size_t edge_count(const std::vector<uint32_t>& idx) {
  std::set<std::pair<uint32_t, uint32_t>> e;
  for (size_t i = 0; i < idx.size(); ++i) {
    const uint32_t a = idx[i], b = idx[i - i % 3 + (i % 3 + 1) % 3];
    e.insert({std::min(a, b), std::max(a, b)});
  }
  return e.size();
}

/// The vertices on edges of one triangle, each once.
std::vector<uint32_t> boundary_vertices(const std::vector<uint32_t>& idx) {
  std::map<std::pair<uint32_t, uint32_t>, int> e;
  for (size_t i = 0; i < idx.size(); ++i) {
    const uint32_t a = idx[i], b = idx[i - i % 3 + (i % 3 + 1) % 3];
    ++e[{std::min(a, b), std::max(a, b)}];
  }
  std::set<uint32_t> v;
  for (const auto& [k, n] : e)
    if (n == 1) v.insert(k.first), v.insert(k.second);
  return {v.begin(), v.end()};
}

TEST(LoopSubdivision, CountsFollowFourToTheLevelsAndEuler) {
  std::vector<Vec3> p;
  std::vector<uint32_t> idx;
  octahedron(p, idx);
  for (int levels = 0; levels <= 4; ++levels) {
    const TriangleMesh m = loop_subdivide(p, idx, levels).mesh;
    const size_t f = 8u << (2 * levels);
    EXPECT_EQ(m.triangle_count(), f);
    // A closed genus-0 mesh: V - E + F = 2 with E = 3F / 2.
    EXPECT_EQ(m.positions.size(), 2 + f / 2) << levels;
    EXPECT_EQ(edge_count(m.indices), 3 * f / 2);
    EXPECT_EQ(m.normals.size(), m.positions.size());
  }
}

TEST(LoopSubdivision, OctahedronConvergesToASmoothSurfaceInsideItsHull) {
  std::vector<Vec3> p;
  std::vector<uint32_t> idx;
  octahedron(p, idx);
  // Convergence: the control points approach their limit positions (the distance falls by about
  // 4 per level: Loop's scheme converges quadratically in the edge length), and the surface gets
  // smoother (the largest angle between the normals of neighbouring triangles falls, by about 0.7
  // per level here: slower than the regular 1/2 near the valence-4 vertices).
  double previous_gap = 1e9, previous_kink = 1e9;
  for (int levels = 1; levels <= 5; ++levels) {
    const TriangleMesh m = loop_subdivide(p, idx, levels, false).mesh;
    const TriangleMesh lim = loop_subdivide(p, idx, levels, true).mesh;
    double gap = 0;
    for (size_t v = 0; v < m.positions.size(); ++v) {
      gap = std::max(gap, double(length(m.positions[v] - lim.positions[v])));
      // Inside the octahedron |x| + |y| + |z| <= 1 (every rule is a convex combination).
      const Vec3 q = m.positions[v];
      EXPECT_LE(std::fabs(q.x) + std::fabs(q.y) + std::fabs(q.z), 1.0 + 1e-5);
    }
    std::map<std::pair<uint32_t, uint32_t>, Vec3> first;
    double kink = 0;
    for (size_t t = 0; t < m.indices.size(); t += 3) {
      const Vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                 c = m.positions[m.indices[t + 2]];
      const Vec3 n = normalize(cross(b - a, c - a));
      for (int k = 0; k < 3; ++k) {
        const uint32_t u = m.indices[t + k], w = m.indices[t + (k + 1) % 3];
        const auto key = std::make_pair(std::min(u, w), std::max(u, w));
        const auto it = first.find(key);
        if (it == first.end())
          first[key] = n;
        else
          kink = std::max(kink, std::acos(std::clamp(double(dot(n, it->second)), -1.0, 1.0)));
      }
    }
    EXPECT_LT(gap, 0.4 * previous_gap) << levels;
    EXPECT_LT(kink, 0.8 * previous_kink) << levels;
    previous_gap = gap, previous_kink = kink;
  }
  EXPECT_LT(previous_gap, 2e-3);
  EXPECT_LT(previous_kink, 0.3);
  // The limit surface: every limit point inside the hull, limit normals nearly radial (the
  // surface is nearly round) and pointing outwards.
  const TriangleMesh m = loop_subdivide(p, idx, 4).mesh;
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const Vec3 q = m.positions[v];
    EXPECT_LE(std::fabs(q.x) + std::fabs(q.y) + std::fabs(q.z), 1.0 + 1e-5);
    EXPECT_NEAR(length(m.normals[v]), 1.0, 1e-5);
    EXPECT_GT(dot(m.normals[v], normalize(q)), 0.9) << v;
  }
}

TEST(LoopSubdivision, IcosahedronLimitIsNearlyASphereInsideTheHull) {
  // Twelve vertices (0, +-1, +-phi) and their cyclic permutations; every vertex has valence 5,
  // the closest to regular of the platonic solids, so the limit is nearly round.
  const float g = 0.5f * (1.0f + std::sqrt(5.0f));
  std::vector<Vec3> p;
  for (float a : {-1.0f, 1.0f})
    for (float b : {-g, g}) p.insert(p.end(), {{0, a, b}, {a, b, 0}, {b, 0, a}});
  for (Vec3& v : p) v = normalize(v);
  // The 20 faces: triples of mutually nearest vertices, wound outwards.
  std::vector<uint32_t> idx;
  float e = 1e9f;
  for (size_t i = 0; i < p.size(); ++i)
    for (size_t j = i + 1; j < p.size(); ++j) e = std::min(e, length(p[i] - p[j]));
  const auto near = [&](size_t i, size_t j) { return length(p[i] - p[j]) < e * 1.01f; };
  for (uint32_t i = 0; i < 12; ++i)
    for (uint32_t j = i + 1; j < 12; ++j)
      for (uint32_t k = j + 1; k < 12; ++k)
        if (near(i, j) && near(j, k) && near(i, k)) {
          const bool out = dot(cross(p[j] - p[i], p[k] - p[i]), p[i]) > 0;
          idx.insert(idx.end(), {i, out ? j : k, out ? k : j});
        }
  ASSERT_EQ(idx.size(), 60u);
  const TriangleMesh m = loop_subdivide(p, idx, 3).mesh;
  EXPECT_EQ(m.positions.size(), 2u + 20u * 64u / 2u);
  double lo = 1e9, hi = 0;
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const double r = length(m.positions[v]);
    lo = std::min(lo, r), hi = std::max(hi, r);
    EXPECT_GT(dot(m.normals[v], normalize(m.positions[v])), 0.99f) << v;
  }
  EXPECT_LT(hi, 1.0);               // inside the circumsphere, hence near the hull
  EXPECT_LT((hi - lo) / hi, 0.05);  // nearly round
}

TEST(LoopSubdivision, TetrahedronVertexMovesByLoopsWeights) {
  std::vector<Vec3> p;
  std::vector<uint32_t> idx;
  tetrahedron(p, idx);
  // Valence 3: beta = 3/16, v' = (1 - 9/16) v + 3/16 (sum of the other three) = 7/16 v - 3/16 v.
  const TriangleMesh one = loop_subdivide(p, idx, 1, false).mesh;
  for (int v = 0; v < 4; ++v) {
    const Vec3 expected =
        p[v] * (7.0f / 16.0f) + (p[0] + p[1] + p[2] + p[3] - p[v]) * (3.0f / 16.0f);
    EXPECT_NEAR(length(one.positions[v] - expected), 0.0, 1e-6) << v;
    EXPECT_NEAR(length(one.positions[v] - p[v] * 0.25f), 0.0, 1e-6);  // = v / 4 here
  }
  // The odd vertex of edge (0, 1): 3/8 (p0 + p1) + 1/8 (p2 + p3).
  const Vec3 odd = (p[0] + p[1]) * 0.375f + (p[2] + p[3]) * 0.125f;
  bool found = false;
  for (const Vec3& q : one.positions) found |= length(q - odd) < 1e-6f;
  EXPECT_TRUE(found);
  // Limit at level 0: g = 1 / (3 + 3 / (8 * 3/16)) = 1/5, v = 2/5 v + 1/5 (others) = v / 5.
  const TriangleMesh lim = loop_subdivide(p, idx, 0, true).mesh;
  for (int v = 0; v < 4; ++v) {
    EXPECT_NEAR(length(lim.positions[v] - p[v] * 0.2f), 0.0, 1e-6) << v;
    EXPECT_GT(dot(lim.normals[v], normalize(p[v])), 0.999f);  // by symmetry: radial
  }
}

TEST(LoopSubdivision, FlatGridStaysPlanarWithFixedRegularVerticesAndBoundary) {
  std::vector<Vec3> p;
  std::vector<uint32_t> idx;
  grid(4, p, idx);
  const LoopSubdivision s = loop_subdivide(p, idx, 3);
  EXPECT_EQ(s.nonmanifold_edges, 0u);
  EXPECT_EQ(s.nonmanifold_vertices, 0u);
  // An open mesh: V = V0 + E per level.
  EXPECT_EQ(s.mesh.triangle_count(), idx.size() / 3 * 64);
  for (size_t v = 0; v < s.mesh.positions.size(); ++v) {
    const Vec3 q = s.mesh.positions[v];
    EXPECT_EQ(q.z, 0.0f);                              // in the plane
    EXPECT_EQ(s.mesh.normals[v], Vec3(0, 0, 1)) << v;  // the plane's normal (the winding's)
    EXPECT_TRUE(q.x >= -1e-6f && q.x <= 4 + 1e-6f && q.y >= -1e-6f && q.y <= 4 + 1e-6f);
  }
  // Valence-6 vertices of a regular flat triangulation stay where they are (the mask reproduces
  // linear functions); interior control points here are such vertices.
  const TriangleMesh one = loop_subdivide(p, idx, 1, false).mesh;
  for (int y = 1; y < 4; ++y)
    for (int x = 1; x < 4; ++x) {
      const uint32_t v = uint32_t(y * 5 + x);
      EXPECT_NEAR(length(one.positions[v] - p[v]), 0.0, 1e-6) << x << "," << y;
    }
  // Two levels: the 16 boundary segments became 64, all in the plane and inside the square.
  const TriangleMesh two = loop_subdivide(p, idx, 2, false).mesh;
  const std::vector<uint32_t> rim = boundary_vertices(two.indices);
  EXPECT_EQ(rim.size(), 64u);
  for (uint32_t v : rim) {
    const Vec3 q = two.positions[v];
    EXPECT_TRUE(q.z == 0 && q.x >= 0 && q.x <= 4 && q.y >= 0 && q.y <= 4);
  }
}

TEST(LoopSubdivision, BoundaryDependsOnlyOnTheBoundaryPolygon) {
  // A 2 x 2 square with its centre raised: the boundary polygon is still flat (z = 0), and the
  // boundary rules use boundary points only, so every boundary vertex stays at z = 0 at every
  // level and at the limit, while the inside rises.
  std::vector<Vec3> p;
  std::vector<uint32_t> idx;
  grid(2, p, idx);
  p[4].z = 1;  // the centre (1, 1)
  for (bool limit : {false, true}) {
    const TriangleMesh m = loop_subdivide(p, idx, 3, limit).mesh;
    const std::vector<uint32_t> rim = boundary_vertices(m.indices);
    EXPECT_EQ(rim.size(), 64u);  // 8 segments x 2^3
    for (uint32_t v : rim) EXPECT_EQ(m.positions[v].z, 0.0f) << v;
    double top = 0;
    for (const Vec3& q : m.positions) top = std::max(top, double(q.z));
    EXPECT_GT(top, 0.1);
    EXPECT_LT(top, 1.0);  // inside the control hull
  }
  // The corner (0, 0, 0) has boundary neighbours (1, 0, 0) and (0, 1, 0): 3/4 v + 1/8 each.
  const TriangleMesh one = loop_subdivide(p, idx, 1, false).mesh;
  EXPECT_NEAR(length(one.positions[0] - Vec3(0.125f, 0.125f, 0)), 0.0, 1e-6);
  // Boundary edge midpoints are (a + b) / 2: the odd vertex of edge (0, 1) is (0.5, 0, 0).
  bool found = false;
  for (const Vec3& q : one.positions) found |= length(q - Vec3(0.5f, 0, 0)) < 1e-6f;
  EXPECT_TRUE(found);
}

TEST(LoopSubdivision, NonManifoldEdgesAreCreasesAndBadInputIsAnError) {
  // Three triangles on the edge (0, 1): a crease, reported; the result is still 4^l per triangle.
  const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}, {0.5f, 0, 1}};
  const std::vector<uint32_t> fins = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  const LoopSubdivision s = loop_subdivide(p, fins, 2);
  EXPECT_EQ(s.nonmanifold_edges, 1u);
  EXPECT_EQ(s.mesh.triangle_count(), 3u * 16u);
  for (const Vec3& n : s.mesh.normals) EXPECT_NEAR(length(n), 1.0, 1e-5);
  const auto error_of = [](const std::vector<Vec3>& q, const std::vector<uint32_t>& i, int l) {
    try {
      loop_subdivide(q, i, l);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::vector<uint32_t> one = {0, 1, 2};
  EXPECT_NE(error_of(p, {0, 1, 1}, 1).find("triangle 0 repeats vertex 1"), std::string::npos);
  EXPECT_NE(error_of(p, {0, 1, 2, 2, 1, 0}, 1).find("triangles 0 and 1 use the same three"),
            std::string::npos);
  EXPECT_NE(error_of(p, {0, 1, 9}, 1).find("uses vertex 9 of 5"), std::string::npos);
  EXPECT_NE(error_of(p, {0, 1}, 1).find("multiple of 3"), std::string::npos);
  EXPECT_NE(error_of(p, one, 11).find("\"levels\" 11 is outside [0, 10]"), std::string::npos);
  EXPECT_NE(error_of(p, one, -1).find("\"levels\" -1"), std::string::npos);
  EXPECT_NE(error_of({{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}}, one, 1).find("vertex 2 is not finite"),
            std::string::npos);
  {
    const ScopedMemoryLimit limit(1 << 20);  // 1 MiB: 4^8 triangles need about 6 MiB
    EXPECT_NE(error_of(p, one, 8).find("\"levels\" 8"), std::string::npos);
    EXPECT_EQ(error_of(p, one, 5), "");
  }
}

}  // namespace
}  // namespace penumbra
