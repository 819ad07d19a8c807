#include "penumbra/geometry/loop_subdivision.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "penumbra/core/dvec3.h"
#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"

namespace penumbra {

namespace {

constexpr uint32_t kNone = ~0u;

/// The connectivity of one level: edges sorted by vertex pair, each triangle's edges, and per
/// vertex its edges and triangles (compressed rows).
struct Topology {
  std::vector<uint32_t> edge_v;      ///< 2 per edge, smaller index first
  std::vector<uint32_t> edge_faces;  ///< triangles on each edge
  std::vector<uint32_t> edge_opp;    ///< 2 per edge: vertices opposite its first two triangles
  std::vector<uint32_t> face_edge;   ///< 3 per triangle: the edge (v[j], v[j+1])
  std::vector<uint32_t> ve_start, ve, vf_start, vf;
};

/// Compressed rows of (vertex, item) pairs.
void compress(size_t nv, const std::vector<std::pair<uint32_t, uint32_t>>& pairs,
              std::vector<uint32_t>& start, std::vector<uint32_t>& items) {
  start.assign(nv + 1, 0);
  for (const auto& [v, _] : pairs) ++start[v + 1];
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  items.resize(pairs.size());
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (const auto& [v, item] : pairs) items[fill[v]++] = item;
}

Topology build_topology(size_t nv, const std::vector<uint32_t>& idx) {
  // Each triangle side keyed by its vertex pair; sorting groups the sides of one edge.
  std::vector<std::pair<uint64_t, uint32_t>> sides(idx.size());
  for (uint32_t h = 0; h < idx.size(); ++h) {
    const uint32_t a = idx[h], b = idx[h - h % 3 + (h % 3 + 1) % 3];
    sides[h] = {(uint64_t(std::min(a, b)) << 32) | std::max(a, b), h};
  }
  std::sort(sides.begin(), sides.end());
  Topology t;
  t.face_edge.resize(idx.size());
  std::vector<std::pair<uint32_t, uint32_t>> ve, vf;
  for (size_t i = 0; i < sides.size();) {
    const uint64_t key = sides[i].first;
    const uint32_t e = uint32_t(t.edge_faces.size());
    t.edge_v.insert(t.edge_v.end(), {uint32_t(key >> 32), uint32_t(key)});
    t.edge_opp.insert(t.edge_opp.end(), {kNone, kNone});
    uint32_t count = 0;
    for (; i < sides.size() && sides[i].first == key; ++i, ++count) {
      const uint32_t h = sides[i].second;
      t.face_edge[h] = e;
      if (count < 2) t.edge_opp[2 * e + count] = idx[h - h % 3 + (h % 3 + 2) % 3];
    }
    t.edge_faces.push_back(count);
    ve.push_back({uint32_t(key >> 32), e});
    ve.push_back({uint32_t(key), e});
  }
  for (uint32_t h = 0; h < idx.size(); ++h) vf.push_back({idx[h], h / 3});
  compress(nv, ve, t.ve_start, t.ve);
  compress(nv, vf, t.vf_start, t.vf);
  return t;
}

/// How a vertex moves: by the interior rule, the crease rule (neighbours c0, c1) or not at all.
struct VertexRule {
  enum Kind : uint8_t { kInterior, kCrease, kCorner } kind = kCorner;
  uint32_t c0 = kNone, c1 = kNone;
  bool ring_ok = false;        ///< `ring` is v's one-ring in order around it (one fan)
  std::vector<uint32_t> ring;  ///< the neighbours (ordered when ring_ok)
};

/// Orders v's neighbours around it by walking the link (each triangle joins the two neighbours it
/// holds): true when the triangles form one fan, closed or open (then the ring runs from one end
/// to the other).
bool order_ring(const Topology& t, const std::vector<uint32_t>& idx, uint32_t v,
                std::vector<uint32_t>& ring, std::vector<std::pair<uint32_t, uint32_t>>& link) {
  const size_t n = t.ve_start[v + 1] - t.ve_start[v];
  if (n == 0) return false;
  link.clear();
  for (uint32_t k = t.vf_start[v]; k < t.vf_start[v + 1]; ++k) {
    const uint32_t f = t.vf[k];
    const int j = idx[3 * f] == v ? 0 : idx[3 * f + 1] == v ? 1 : 2;
    const uint32_t a = idx[3 * f + (j + 1) % 3], b = idx[3 * f + (j + 2) % 3];
    link.push_back({a, b});
    link.push_back({b, a});
  }
  std::sort(link.begin(), link.end());
  // Every neighbour joined to one or two others; zero or two ends.
  size_t nodes = 0, ends = 0;
  uint32_t start = link.front().first;
  for (size_t i = 0; i < link.size();) {
    size_t k = i;
    while (k < link.size() && link[k].first == link[i].first) ++k;
    ++nodes;
    if (k - i == 1 && ends++ == 0) start = link[i].first;
    if (k - i > 2) return false;
    i = k;
  }
  if (nodes != n || (ends != 0 && ends != 2)) return false;
  ring.clear();
  uint32_t prev = kNone, cur = start;
  while (ring.size() < n) {
    ring.push_back(cur);
    auto it = std::lower_bound(link.begin(), link.end(), std::pair<uint32_t, uint32_t>{cur, 0});
    uint32_t next = kNone;
    for (; it != link.end() && it->first == cur; ++it)
      if (it->second != prev) {
        next = it->second;
        break;
      }
    prev = cur, cur = next;
    if (cur == kNone || cur == start) break;
  }
  return ring.size() == n && (ends == 2 ? cur == kNone : cur == start);
}

/// The rule of vertex v (Loop's interior rule, Hoppe et al.'s crease and corner rules).
void classify(const Topology& t, const std::vector<uint32_t>& idx, uint32_t v, VertexRule& r,
              std::vector<std::pair<uint32_t, uint32_t>>& link) {
  uint32_t creases = 0;
  r.c0 = r.c1 = kNone;
  for (uint32_t k = t.ve_start[v]; k < t.ve_start[v + 1]; ++k) {
    const uint32_t e = t.ve[k];
    if (t.edge_faces[e] == 2) continue;
    const uint32_t other = t.edge_v[2 * e] == v ? t.edge_v[2 * e + 1] : t.edge_v[2 * e];
    (creases++ == 0 ? r.c0 : r.c1) = other;
  }
  r.ring_ok = order_ring(t, idx, v, r.ring, link);
  if (!r.ring_ok) {
    r.ring.clear();
    for (uint32_t k = t.ve_start[v]; k < t.ve_start[v + 1]; ++k) {
      const uint32_t e = t.ve[k];
      r.ring.push_back(t.edge_v[2 * e] == v ? t.edge_v[2 * e + 1] : t.edge_v[2 * e]);
    }
  }
  if (creases == 0 && r.ring_ok)
    r.kind = VertexRule::kInterior;
  else if (creases == 2)
    r.kind = VertexRule::kCrease;
  else
    r.kind = VertexRule::kCorner;
}

/// Loop's (Warren's) even-vertex weight for valence n.
double loop_beta(size_t n) {
  return n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * double(n));
}

/// (1 - n w) p_v + w sum of the ring.
Vec3 weigh_ring(const std::vector<Vec3>& p, uint32_t v, const std::vector<uint32_t>& ring,
                double w) {
  DVec3 sum;
  for (uint32_t u : ring) sum = sum + DVec3(p[u]);
  return (DVec3(p[v]) * (1.0 - double(ring.size()) * w) + sum * w).to_float();
}

/// One level: even vertices by their rules, one odd vertex per edge, four triangles per triangle
/// (corners first, then the middle one; each keeps its parent's winding).
void subdivide_once(std::vector<Vec3>& p, std::vector<uint32_t>& idx) {
  const Topology t = build_topology(p.size(), idx);
  const size_t nv = p.size(), ne = t.edge_faces.size();
  std::vector<Vec3> q(nv + ne);
  VertexRule r;
  std::vector<std::pair<uint32_t, uint32_t>> link;
  for (uint32_t v = 0; v < nv; ++v) {
    classify(t, idx, v, r, link);
    if (r.kind == VertexRule::kInterior)
      q[v] = weigh_ring(p, v, r.ring, loop_beta(r.ring.size()));
    else if (r.kind == VertexRule::kCrease)
      q[v] = (DVec3(p[v]) * 0.75 + (DVec3(p[r.c0]) + DVec3(p[r.c1])) * 0.125).to_float();
    else
      q[v] = p[v];
  }
  for (size_t e = 0; e < ne; ++e) {
    const DVec3 a(p[t.edge_v[2 * e]]), b(p[t.edge_v[2 * e + 1]]);
    if (t.edge_faces[e] == 2)
      q[nv + e] = ((a + b) * 0.375 +
                   (DVec3(p[t.edge_opp[2 * e]]) + DVec3(p[t.edge_opp[2 * e + 1]])) * 0.125)
                      .to_float();
    else
      q[nv + e] = ((a + b) * 0.5).to_float();  // boundary or non-manifold: a crease
  }
  std::vector<uint32_t> out(idx.size() * 4);
  for (size_t f = 0; f < idx.size() / 3; ++f) {
    const uint32_t v0 = idx[3 * f], v1 = idx[3 * f + 1], v2 = idx[3 * f + 2];
    const uint32_t m0 = uint32_t(nv + t.face_edge[3 * f]),
                   m1 = uint32_t(nv + t.face_edge[3 * f + 1]),
                   m2 = uint32_t(nv + t.face_edge[3 * f + 2]);
    const uint32_t tri[12] = {v0, m0, m2, m0, v1, m1, m2, m1, v2, m0, m1, m2};
    std::copy(tri, tri + 12, out.begin() + 12 * f);
  }
  p = std::move(q);
  idx = std::move(out);
}

/// Tangent masks of a boundary vertex with its ring ordered from one crease neighbour to the
/// other (as pbrt's loopsubdiv, after Hoppe et al. 1994): the normal cross(S, T).
DVec3 boundary_normal(const std::vector<Vec3>& p, uint32_t v, const std::vector<uint32_t>& ring) {
  const size_t n = ring.size();
  const auto at = [&](size_t i) { return DVec3(p[ring[i]]); };
  const DVec3 pv(p[v]);
  const DVec3 s = at(n - 1) - at(0);
  DVec3 t;
  if (n == 2) {
    t = at(0) + at(1) - pv * 2.0;
  } else if (n == 3) {
    t = at(1) - pv;
  } else if (n == 4) {
    t = at(0) * -1.0 + at(1) * 2.0 + at(2) * 2.0 - at(3) - pv * 2.0;
  } else {
    const double theta = std::numbers::pi / double(n - 1);
    t = (at(0) + at(n - 1)) * std::sin(theta);
    for (size_t k = 1; k + 1 < n; ++k)
      t = t + at(k) * ((2.0 * std::cos(theta) - 2.0) * std::sin(double(k) * theta));
    t = -t;
  }
  return cross(s, t);
}

/// Moves the vertices to their limit positions and gives them limit normals, turned to the side
/// of the area-weighted normal of their triangles (which the winding defines).
void push_to_limit(TriangleMesh& m) {
  std::vector<Vec3>& p = m.positions;
  const Topology t = build_topology(p.size(), m.indices);
  std::vector<Vec3> lim(p.size());
  std::vector<DVec3> mask(p.size());
  VertexRule r;
  std::vector<std::pair<uint32_t, uint32_t>> link;
  for (uint32_t v = 0; v < p.size(); ++v) {
    classify(t, m.indices, v, r, link);
    if (r.kind == VertexRule::kInterior) {
      const size_t n = r.ring.size();
      lim[v] = weigh_ring(p, v, r.ring, 1.0 / (double(n) + 3.0 / (8.0 * loop_beta(n))));
      DVec3 s, tt;
      for (size_t j = 0; j < n; ++j) {
        const double a = 2.0 * std::numbers::pi * double(j) / double(n);
        s = s + DVec3(p[r.ring[j]]) * std::cos(a);
        tt = tt + DVec3(p[r.ring[j]]) * std::sin(a);
      }
      mask[v] = cross(s, tt);
    } else if (r.kind == VertexRule::kCrease) {
      lim[v] = (DVec3(p[v]) * 0.6 + (DVec3(p[r.c0]) + DVec3(p[r.c1])) * 0.2).to_float();
      const bool ends_on_creases =
          r.ring_ok && ((r.ring.front() == r.c0 && r.ring.back() == r.c1) ||
                        (r.ring.front() == r.c1 && r.ring.back() == r.c0));
      if (ends_on_creases) mask[v] = boundary_normal(p, v, r.ring);
    } else {
      lim[v] = p[v];
    }
  }
  p = std::move(lim);
  // Area-weighted triangle normals at the limit positions: the side and the fallback.
  std::vector<DVec3> area(p.size());
  for (size_t f = 0; f < m.indices.size(); f += 3) {
    const uint32_t a = m.indices[f], b = m.indices[f + 1], c = m.indices[f + 2];
    const DVec3 n = cross(DVec3(p[b]) - DVec3(p[a]), DVec3(p[c]) - DVec3(p[a]));
    area[a] = area[a] + n, area[b] = area[b] + n, area[c] = area[c] + n;
  }
  m.normals.resize(p.size());
  for (size_t v = 0; v < p.size(); ++v) {
    DVec3 n = mask[v];
    if (dot(n, area[v]) < 0.0) n = -n;
    double len = std::sqrt(dot(n, n));
    if (!(len > 0.0 && std::isfinite(len)) || !(dot(n, area[v]) > 0.0)) {
      n = area[v];
      len = std::sqrt(dot(n, n));
    }
    m.normals[v] = len > 0.0 && std::isfinite(len) ? (n * (1.0 / len)).to_float() : Vec3(0, 0, 1);
  }
}

/// Refuses what the subdivision cannot take, naming the triangle or vertex.
void validate(const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices,
              int levels) {
  if (levels < 0 || levels > kMaxLoopLevels)
    throw Error(
        fmt::format("loop subdivision: \"levels\" {} is outside [0, {}]", levels, kMaxLoopLevels));
  if (indices.empty() || indices.size() % 3 != 0)
    throw Error(fmt::format("loop subdivision: {} indices are not a non-zero multiple of 3",
                            indices.size()));
  for (size_t v = 0; v < positions.size(); ++v)
    if (!is_finite(positions[v]))
      throw Error(fmt::format("loop subdivision: vertex {} is not finite", v));
  std::vector<std::pair<std::array<uint32_t, 3>, size_t>> sorted;
  sorted.reserve(indices.size() / 3);
  for (size_t f = 0; f < indices.size() / 3; ++f) {
    std::array<uint32_t, 3> tri = {indices[3 * f], indices[3 * f + 1], indices[3 * f + 2]};
    for (uint32_t i : tri)
      if (i >= positions.size())
        throw Error(fmt::format("loop subdivision: triangle {} uses vertex {} of {}", f, i,
                                positions.size()));
    std::sort(tri.begin(), tri.end());
    if (tri[0] == tri[1] || tri[1] == tri[2])
      throw Error(fmt::format("loop subdivision: triangle {} repeats vertex {}", f, tri[1]));
    sorted.push_back({tri, f});
  }
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i].first == sorted[i - 1].first)
      throw Error(fmt::format("loop subdivision: triangles {} and {} use the same three vertices",
                              sorted[i - 1].second, sorted[i].second));
  // The result: 4^levels triangles per triangle, about 100 bytes each while it is built (the
  // sorted sides of the last level, positions, normals and indices).
  const double faces = double(indices.size() / 3) * std::pow(4.0, levels);
  const std::string what =
      fmt::format("loop subdivision \"levels\" {}: {} triangles x 4^{} = {:.0f} triangles", levels,
                  indices.size() / 3, levels, faces);
  if (faces > double(1u << 31)) throw Error(what + ", more than 2^31");
  check_memory(faces * 100.0, what, "lower \"levels\"");
}

}  // namespace

LoopSubdivision loop_subdivide(const std::vector<Vec3>& positions,
                               const std::vector<uint32_t>& indices, int levels, bool limit) {
  validate(positions, indices, levels);
  LoopSubdivision out;
  {
    // What the control mesh holds that the rules treat specially (reported by the caller).
    const Topology t = build_topology(positions.size(), indices);
    for (uint32_t c : t.edge_faces) out.nonmanifold_edges += c > 2;
    VertexRule r;
    std::vector<std::pair<uint32_t, uint32_t>> link;
    for (uint32_t v = 0; v < positions.size(); ++v) {
      if (t.ve_start[v + 1] == t.ve_start[v]) continue;  // unused vertex
      classify(t, indices, v, r, link);
      out.nonmanifold_vertices += r.kind == VertexRule::kCorner;
    }
  }
  out.mesh.positions = positions;
  out.mesh.indices = indices;
  for (int l = 0; l < levels; ++l) subdivide_once(out.mesh.positions, out.mesh.indices);
  if (limit) push_to_limit(out.mesh);
  return out;
}

}  // namespace penumbra
