#include "penumbra/render/radiosity/radiosity_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <unordered_map>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/render/world.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// Pieces of one primitive: the grid sizes and the number of pieces they give.
struct PieceCount {
  double n1 = 0, n2 = 0;  ///< grid sizes (double so that absurd sizes are caught, not wrapped)
  double pieces = 0;
};

/// Cells along a length: at least one, about `patch` across.
double cells(double length, double patch) {
  return std::max(1.0, std::ceil(length / patch));
}

PieceCount count_pieces(const PrimitiveSet& prims, uint32_t id, double patch) {
  PieceCount c;
  switch (prims.kind(id)) {
    case PrimKind::kQuad: {
      const QuadData& q = prims.quad(id);
      c.n1 = cells(length(q.e1), patch), c.n2 = cells(length(q.e2), patch);
      c.pieces = c.n1 * c.n2;
      break;
    }
    case PrimKind::kTriangle: {
      const Vec3* p = prims.triangle(id);
      const double longest =
          std::max({length(p[1] - p[0]), length(p[2] - p[1]), length(p[0] - p[2])});
      c.n1 = cells(longest, patch);
      c.pieces = c.n1 * c.n1;
      break;
    }
    case PrimKind::kSphere: {
      const double r = prims.sphere(id).radius;
      c.n1 = std::max(8.0, std::ceil(2 * kPi * r / patch));
      c.n2 = std::max(4.0, std::ceil(kPi * r / patch));
      c.pieces = 2 * c.n1 * (c.n2 - 1);
      break;
    }
  }
  return c;
}

/// The parallelogram two triangles make when they share an edge (its diagonal) and their other
/// corners complete it (s1 + s2 = u1 + u2 within float rounding): a quad written as two
/// triangles, as the Cornell box's walls and most exported rectangles are.
std::optional<QuadData> parallelogram_of(const Vec3* a, const Vec3* b) {
  int shared_a[2], shared_b[2], count = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j] && count < 2) shared_a[count] = i, shared_b[count] = j, ++count;
  if (count != 2) return std::nullopt;
  const Vec3 s1 = a[shared_a[0]], s2 = a[shared_a[1]];
  const Vec3 u1 = a[3 - shared_a[0] - shared_a[1]], u2 = b[3 - shared_b[0] - shared_b[1]];
  const float scale = std::max({max_component(abs(s1)), max_component(abs(s2)),
                                max_component(abs(u1)), max_component(abs(u2)), 1e-30f});
  if (!(max_component(abs(s1 + s2 - u1 - u2)) <= 1e-5f * scale)) return std::nullopt;
  const QuadData q{u1, s1 - u1, s2 - u1};
  if (!(length(cross(q.e1, q.e2)) > 0)) return std::nullopt;
  return q;
}

/// True when the primitive has finite, non-degenerate geometry worth meshing.
bool meshable(const World& world, uint32_t id) {
  const PrimitiveSet& prims = world.primitives();
  if (prims.kind(id) == PrimKind::kSphere) {
    const SphereData& s = prims.sphere(id);
    return is_finite(s.center) && std::isfinite(s.radius) && s.radius > 0;
  }
  const Vec3 n = world.area_normal(id);
  return is_finite(n) && dot(n, n) > 0;
}

/// Welds vertices by quantised position: a point within `quantum` (per axis) of an existing vertex
/// reuses it. The 27 neighbouring cells are searched, so points rounding to adjacent cells meet.
class VertexWelder {
 public:
  VertexWelder(std::vector<Vec3>& vertices, float quantum) : vertices_(vertices), q_(quantum) {}

  uint32_t add(Vec3 p) {
    const int64_t k[3] = {std::llround(p.x / q_), std::llround(p.y / q_), std::llround(p.z / q_)};
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = map_.find(key(k[0] + dx, k[1] + dy, k[2] + dz));
          if (it == map_.end()) continue;
          for (const uint32_t v : it->second)
            if (max_component(abs(vertices_[v] - p)) <= q_) return v;
        }
    const auto index = static_cast<uint32_t>(vertices_.size());
    vertices_.push_back(p);
    map_[key(k[0], k[1], k[2])].push_back(index);
    return index;
  }

 private:
  /// Hash of the cell (a collision only costs distance tests: the map keeps every vertex of a
  /// key and the exact test decides; keeping only the first lost 40 % of a sphere's welds).
  static uint64_t key(int64_t x, int64_t y, int64_t z) {
    return uint64_t(x) * 0x9e3779b97f4a7c15ull ^ uint64_t(y) * 0xc2b2ae3d27d4eb4full ^
           uint64_t(z) * 0x165667b19e3779f9ull;
  }

  std::vector<Vec3>& vertices_;
  float q_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> map_;
};

/// Solves p = o + u e1 + v e2 in the least-squares sense (p projected onto the plane).
void plane_coordinates(Vec3 p, Vec3 o, Vec3 e1, Vec3 e2, double& u, double& v) {
  const Vec3 d = p - o;
  const double a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2);
  const double r1 = dot(d, e1), r2 = dot(d, e2);
  const double det = a * c - b * b;
  if (!(det > 0)) {
    u = v = 0;
    return;
  }
  u = (c * r1 - b * r2) / det;
  v = (a * r2 - b * r1) / det;
}

/// floor(x) clamped to [0, n - 1].
int cell_index(double x, int n) {
  const double f = std::floor(x);
  return f < 0 ? 0 : (f > n - 1 ? n - 1 : int(f));
}

}  // namespace

Vec3 RadiosityMesh::sphere_vertex(uint32_t prim, int l, int k) const {
  const PrimGrid& g = prims_[prim];
  const Vec3 c = prim_frame_[3 * size_t(prim)];
  const double r = prim_frame_[3 * size_t(prim) + 1].x;
  if (l <= 0) return c + Vec3(0, 0, float(r));
  if (l >= g.n2) return c - Vec3(0, 0, float(r));
  const double theta = kPi * l / g.n2, phi = 2 * kPi * (k % g.n1) / g.n1;
  const double s = std::sin(theta);
  return c + Vec3(float(r * s * std::cos(phi)), float(r * s * std::sin(phi)),
                  float(r * std::cos(theta)));
}

RadiosityMesh RadiosityMesh::build(const World& world, float patch_size, size_t max_elements,
                                   std::vector<std::string>* warnings) {
  if (!(patch_size > 0) || !std::isfinite(patch_size))
    throw Error(fmt::format("radiosity mesh: the patch size must be positive and finite, not {}",
                            patch_size));
  const PrimitiveSet& prims = world.primitives();
  RadiosityMesh mesh;
  mesh.prims_.resize(prims.size());
  mesh.prim_frame_.resize(3 * size_t(prims.size()));

  // Pairs of consecutive triangles of one shape that form a parallelogram are meshed as one
  // parallelogram grid (the second triangle's hits locate in it too): for the same patch size,
  // a quarter of the elements of two s^2 subdivisions and no slivers along the diagonal.
  std::vector<std::optional<QuadData>> merged(prims.size());
  std::vector<char> second_half(prims.size(), 0);
  for (uint32_t id = 0; id + 1 < prims.size(); ++id) {
    if (prims.kind(id) != PrimKind::kTriangle || prims.kind(id + 1) != PrimKind::kTriangle ||
        prims.moving(id) || prims.moving(id + 1) ||
        prims.origin(id).shape != prims.origin(id + 1).shape || !meshable(world, id) ||
        !meshable(world, id + 1) || dot(world.area_normal(id), world.area_normal(id + 1)) <= 0)
      continue;
    merged[id] = parallelogram_of(prims.triangle(id), prims.triangle(id + 1));
    if (merged[id]) second_half[++id] = 1;
  }
  const auto pieces_of = [&](uint32_t id) {
    if (!merged[id]) return count_pieces(prims, id, patch_size);
    PieceCount c;
    c.n1 = cells(length(merged[id]->e1), patch_size);
    c.n2 = cells(length(merged[id]->e2), patch_size);
    c.pieces = c.n1 * c.n2;
    return c;
  };

  // Count first: refuse an oversized mesh before allocating it.
  double total = 0;
  for (uint32_t id = 0; id < prims.size(); ++id) {
    if (!meshable(world, id) || second_half[id]) continue;
    const PieceCount c = pieces_of(id);
    if (c.n1 > 65535 || c.n2 > 65535)
      throw Error(
          fmt::format("radiosity mesh: primitive {} would be cut into a {} x {} grid, more "
                      "than 65535 cells along a side; use a larger patch size",
                      id, c.n1, c.n2));
    total += 2 * c.pieces;
  }
  if (total > double(max_elements))
    throw Error(
        fmt::format("radiosity mesh: patch size {} gives {} elements, more than the budget "
                    "of {}; use a larger patch size",
                    patch_size, total, max_elements));
  mesh.elements_.reserve(size_t(total));

  const Bounds3& b = world.bounds();
  const float extent = b.empty() ? 1.0f : max_component(b.diagonal());
  VertexWelder welder(mesh.vertices_, 1e-6f * std::max(extent, 1e-20f));
  std::vector<char> warned(world.shape_count(), 0);

  for (uint32_t id = 0; id < prims.size(); ++id) {
    if (!meshable(world, id)) continue;
    if (second_half[id]) {  // meshed with the triangle before it
      mesh.prims_[id] = mesh.prims_[id - 1];
      for (int k = 0; k < 3; ++k)
        mesh.prim_frame_[3 * size_t(id) + k] = mesh.prim_frame_[3 * size_t(id - 1) + k];
      continue;
    }
    const uint32_t shape = prims.origin(id).shape;
    const Material& material = world.shape_material(shape);
    if ((material.flags() & (kBsdfGlossy | kBsdfSpecular | kBsdfTransmission)) != 0 &&
        !warned[shape]) {
      warned[shape] = 1;
      if (warnings)
        warnings->push_back(
            fmt::format("radiosity: shape {} has a material that is not purely "
                        "diffuse; it is treated as diffuse with its albedo",
                        shape));
    }
    Rgb rho = material.albedo();
    rho = {std::clamp(rho.r, 0.0f, 0.999f), std::clamp(rho.g, 0.0f, 0.999f),
           std::clamp(rho.b, 0.0f, 0.999f)};
    const std::optional<Rgb>& le = world.shape_emission(shape);
    const Rgb front_emission = le ? *le * float(kPi) : Rgb{};
    const Rgb back_emission = le && world.shape_emits_both_sides(shape) ? front_emission : Rgb{};

    const PieceCount c = pieces_of(id);
    PrimGrid& g = mesh.prims_[id];
    g.first = static_cast<uint32_t>(mesh.elements_.size());
    g.n1 = uint16_t(c.n1), g.n2 = uint16_t(c.n2);
    g.kind = uint8_t(merged[id] ? PrimKind::kQuad : prims.kind(id));
    Vec3* frame = &mesh.prim_frame_[3 * size_t(id)];

    // One piece: its front element (corners ordered counter-clockwise about `front`) and twin.
    auto add_piece = [&](Vec3 p0, Vec3 p1, Vec3 p2, const Vec3* p3, Vec3 front) {
      RadiosityElement e;
      e.corners = p3 ? 4 : 3;
      Vec3 q[4] = {p0, p1, p2, p3 ? *p3 : Vec3()};
      Vec3 n = p3 ? cross(p1 - p0, *p3 - p0) : cross(p1 - p0, p2 - p0);
      if (dot(n, front) < 0) {
        std::swap(q[1], q[e.corners - 1]);  // (a, b, c) -> (a, c, b); (a, b, c, d) -> (a, d, c, b)
        n = -n;
      }
      const float len = length(n);
      e.area = p3 ? len : 0.5f * len;
      e.normal = n / len;
      e.centroid = p3 ? (q[0] + q[1] + q[2] + q[3]) * 0.25f : (q[0] + q[1] + q[2]) / 3.0f;
      for (int k = 0; k < e.corners; ++k) e.v[k] = welder.add(q[k]);
      e.rho = rho;
      e.emission = front_emission;
      e.prim = id;
      const auto index = static_cast<uint32_t>(mesh.elements_.size());
      e.twin = index + 1;
      RadiosityElement back = e;
      back.normal = -e.normal;
      std::swap(back.v[1], back.v[e.corners - 1]);
      back.emission = back_emission;
      back.twin = index;
      mesh.elements_.push_back(e);
      mesh.elements_.push_back(back);
    };

    switch (PrimKind(g.kind)) {
      case PrimKind::kQuad: {
        const QuadData& q = merged[id] ? *merged[id] : prims.quad(id);
        frame[0] = q.p, frame[1] = q.e1, frame[2] = q.e2;
        const Vec3 front = world.area_normal(id);
        const int n1 = g.n1, n2 = g.n2;
        auto at = [&](int i, int j) {
          return q.p + q.e1 * (float(i) / n1) + q.e2 * (float(j) / n2);
        };
        for (int j = 0; j < n2; ++j)
          for (int i = 0; i < n1; ++i) {
            const Vec3 p3 = at(i, j + 1);
            add_piece(at(i, j), at(i + 1, j), at(i + 1, j + 1), &p3, front);
          }
        break;
      }
      case PrimKind::kTriangle: {
        const Vec3* p = prims.triangle(id);
        frame[0] = p[0], frame[1] = p[1] - p[0], frame[2] = p[2] - p[0];
        const Vec3 front = world.area_normal(id);
        const int s = g.n1;
        // Grid point (i, j): barycentric coordinates i / s, j / s of vertices 1 and 2.
        auto at = [&](int i, int j) {
          if (i == s) return p[1];
          if (j == s) return p[2];
          return p[0] + frame[1] * (float(i) / s) + frame[2] * (float(j) / s);
        };
        // Row j: up-pointing triangle i at 2 i, down-pointing triangle i at 2 i + 1 (see locate).
        for (int j = 0; j < s; ++j)
          for (int i = 0; i < s - j; ++i) {
            add_piece(at(i, j), at(i + 1, j), at(i, j + 1), nullptr, front);
            if (i < s - 1 - j)
              add_piece(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), nullptr, front);
          }
        break;
      }
      case PrimKind::kSphere: {
        const SphereData& sd = prims.sphere(id);
        frame[0] = sd.center, frame[1] = {sd.radius, 0, 0};
        // The front side is the outside unless the shape's transform flips it: ask the world for
        // the geometric normal of a hit on the top of the sphere.
        Ray ray;
        ray.o = sd.center + Vec3(0, 0, 2 * sd.radius);
        ray.d = {0, 0, -1};
        SurfaceInteraction si;
        world.interaction(ray, Hit{sd.radius, 0, 0, id}, si);
        const float side = si.ng.z >= 0 ? 1.0f : -1.0f;
        const int n_lon = g.n1, n_lat = g.n2;
        for (int l = 0; l < n_lat; ++l)
          for (int k = 0; k < n_lon; ++k) {
            const Vec3 a = mesh.sphere_vertex(id, l, k), b2 = mesh.sphere_vertex(id, l, k + 1);
            const Vec3 c2 = mesh.sphere_vertex(id, l + 1, k + 1),
                       d = mesh.sphere_vertex(id, l + 1, k);
            if (l == 0) {
              add_piece(a, d, c2, nullptr, ((a + d + c2) / 3.0f - sd.center) * side);
            } else if (l == n_lat - 1) {
              add_piece(a, b2, c2, nullptr, ((a + b2 + c2) / 3.0f - sd.center) * side);
            } else {
              add_piece(a, b2, c2, nullptr, ((a + b2 + c2) / 3.0f - sd.center) * side);
              add_piece(a, c2, d, nullptr, ((a + c2 + d) / 3.0f - sd.center) * side);
            }
          }
        break;
      }
    }
  }
  return mesh;
}

uint32_t RadiosityMesh::locate(uint32_t prim, Vec3 p, Vec3 towards) const {
  if (prim >= prims_.size() || prims_[prim].first == UINT32_MAX) return UINT32_MAX;
  const PrimGrid& g = prims_[prim];
  const Vec3* frame = &prim_frame_[3 * size_t(prim)];
  uint32_t piece = 0;
  switch (PrimKind(g.kind)) {
    case PrimKind::kQuad: {
      double u, v;
      plane_coordinates(p, frame[0], frame[1], frame[2], u, v);
      piece = uint32_t(cell_index(v * g.n2, g.n2)) * g.n1 + uint32_t(cell_index(u * g.n1, g.n1));
      break;
    }
    case PrimKind::kTriangle: {
      // Sub-triangle of the s^2 subdivision: row j, column i, up or down pointing.
      double u, v;
      plane_coordinates(p, frame[0], frame[1], frame[2], u, v);
      const int s = g.n1;
      const double a = u * s, b = v * s;
      const int j = cell_index(b, s);
      const int i = cell_index(a, s - j);
      const bool down = i < s - 1 - j && (a - i) + (b - j) > 1.0;
      piece = uint32_t(j * (2 * s - j) + 2 * i + (down ? 1 : 0));
      break;
    }
    case PrimKind::kSphere: {
      const Vec3 d = p - frame[0];
      const float len = length(d);
      if (!(len > 0)) return UINT32_MAX;
      const double theta = std::acos(std::clamp(double(d.z) / len, -1.0, 1.0));
      double phi = std::atan2(double(d.y), double(d.x));
      if (phi < 0) phi += 2 * kPi;
      const int n_lon = g.n1, n_lat = g.n2;
      const int l = cell_index(theta / kPi * n_lat, n_lat);
      const int k = cell_index(phi / (2 * kPi) * n_lon, n_lon);
      if (l == 0) {
        piece = uint32_t(k);
      } else if (l == n_lat - 1) {
        piece = uint32_t(n_lon + (n_lat - 2) * 2 * n_lon + k);
      } else {
        // Which side of the plane through the centre and the cut diagonal (l, k)-(l + 1, k + 1).
        const Vec3 a = sphere_vertex(prim, l, k) - frame[0];
        const Vec3 c = sphere_vertex(prim, l + 1, k + 1) - frame[0];
        const Vec3 b = sphere_vertex(prim, l, k + 1) - frame[0];
        const Vec3 m = cross(a, c);
        const bool second = (dot(d, m) > 0) != (dot(b, m) > 0);
        piece = uint32_t(n_lon + (l - 1) * 2 * n_lon + 2 * k + (second ? 1 : 0));
      }
      break;
    }
  }
  const uint32_t e = pieces_.empty() ? g.first + 2 * piece
                                     : pieces_[descend(g.first / 2 + piece, p)].element;
  // The side: for a sphere by its true normal at p, not the chord element's, which points the
  // other way for grazing directions (0.1 % of the hits inside a closed sphere went to the
  // outer twins).
  const Vec3 n = PrimKind(g.kind) == PrimKind::kSphere
                     ? (p - frame[0]) * (dot(elements_[e].normal, p - frame[0]) >= 0 ? 1.0f : -1.0f)
                     : elements_[e].normal;
  return dot(n, towards) >= 0 ? e : e + 1;
}

uint32_t RadiosityMesh::descend(uint32_t piece, Vec3 p) const {
  // The children's order of subdivide: parallelograms by (s >= 1/2) + 2 (t >= 1/2); triangles
  // the corners at o, o + e1 / 2, o + e2 / 2, then the inverted middle one.
  while (pieces_[piece].child != UINT32_MAX) {
    const Piece& n = pieces_[piece];
    double s, t;
    plane_coordinates(p, n.o, n.e1, n.e2, s, t);
    uint32_t i;
    if (n.corners == 4)
      i = (s >= 0.5 ? 1u : 0u) + (t >= 0.5 ? 2u : 0u);
    else if (s >= 0.5)
      i = 1;
    else if (t >= 0.5)
      i = 2;
    else
      i = s + t < 0.5 ? 0u : 3u;
    piece = n.child + i;
  }
  return piece;
}

void RadiosityMesh::corner_weights(uint32_t e, Vec3 p, float w[4]) const {
  const RadiosityElement& el = elements_[e];
  const Vec3 v0 = vertices_[el.v[0]], v1 = vertices_[el.v[1]];
  double s, t;
  if (el.corners == 3) {
    plane_coordinates(p, v0, v1 - v0, vertices_[el.v[2]] - v0, s, t);
    w[0] = float(1 - s - t), w[1] = float(s), w[2] = float(t), w[3] = 0;
  } else {
    plane_coordinates(p, v0, v1 - v0, vertices_[el.v[3]] - v0, s, t);
    w[0] = float((1 - s) * (1 - t)), w[1] = float(s * (1 - t)), w[2] = float(s * t);
    w[3] = float((1 - s) * t);
  }
}

}  // namespace penumbra
