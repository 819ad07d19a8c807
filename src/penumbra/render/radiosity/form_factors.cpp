#include "penumbra/render/radiosity/form_factors.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "penumbra/core/dvec3.h"
#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/timer.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/render/radiosity/radiosity_mesh.h"
#include "penumbra/render/sampling.h"
#include "penumbra/render/world.h"

namespace penumbra {
namespace {

constexpr double kPi = std::numbers::pi;

/// An n x n zero matrix, refused beyond the memory limit.
FormFactors allocate(size_t n) {
  check_memory(double(n) * double(n) * sizeof(float),
               fmt::format("radiosity: the dense form-factor matrix of {} elements", n),
               "use a larger patch size, fewer max_elements, or hierarchy=true");
  FormFactors ff;
  ff.n = n;
  ff.f.assign(n * n, 0.0f);
  return ff;
}

// ---- Ray casting ---------------------------------------------------------------------------

/// The point where `hit` lies on its primitive (time 0 geometry, as the mesh).
Vec3 hit_point(const PrimitiveSet& prims, const Ray& ray, const Hit& hit) {
  switch (prims.kind(hit.prim)) {
    case PrimKind::kTriangle: {
      const Vec3* p = prims.triangle(hit.prim);
      return p[0] * (1.0f - hit.u - hit.v) + p[1] * hit.u + p[2] * hit.v;
    }
    case PrimKind::kQuad: {
      const QuadData& q = prims.quad(hit.prim);
      return q.p + q.e1 * hit.u + q.e2 * hit.v;
    }
    case PrimKind::kSphere:
      break;
  }
  return ray.at(hit.t);
}

/// Row i of the ray-cast matrix: hit counts per element, written as count / rays.
void raycast_row(const World& world, const RadiosityMesh& mesh, size_t i, int rays, uint64_t seed,
                 float* row, std::vector<uint32_t>& hits) {
  const PrimitiveSet& prims = world.primitives();
  const RadiosityElement& e = mesh.elements()[i];
  const Vec3* vs = mesh.vertices().data();
  const Vec3 v0 = vs[e.v[0]], v1 = vs[e.v[1]], v2 = vs[e.v[2]];
  const Vec3 v3 = e.corners == 4 ? vs[e.v[3]] : v2;
  const bool sphere = prims.kind(e.prim) == PrimKind::kSphere;
  const SphereData sd = sphere ? prims.sphere(e.prim) : SphereData{};
  // Error bound of a point interpolated from the corners (each itself a few roundings from the
  // primitive), or of a point projected onto the sphere.
  const Vec3 p_error = sphere ? (abs(sd.center) + Vec3(sd.radius)) * gamma(8)
                              : (abs(v0) + abs(v1) + abs(v2) + abs(v3)) * gamma(16);
  Vec3 t, b;
  orthonormal_basis(e.normal, t, b);
  Pcg32 rng(hash_combine(seed, i));
  hits.clear();
  for (int k = 0; k < rays; ++k) {
    // A uniform point of the element.
    const float u1 = rng.next_float(), u2 = rng.next_float();
    Vec3 p, n = e.normal, nt = t, nb = b;
    if (e.corners == 4) {
      p = v0 + (v1 - v0) * u1 + (v3 - v0) * u2;
    } else {
      const float su = std::sqrt(u1);
      p = v0 * (1.0f - su) + v1 * (su * (1.0f - u2)) + v2 * (su * u2);
    }
    if (sphere) {
      // Leave from the true sphere, radially above the element's point, with its true normal.
      const Vec3 d = p - sd.center;
      p = sd.center + d * (sd.radius / length(d));
      n = normalize(d);
      if (dot(n, e.normal) < 0) n = -n;
      orthonormal_basis(n, nt, nb);
    }
    // A cosine-distributed direction about the normal.
    const Vec3 l = sample_cosine_hemisphere({rng.next_float(), rng.next_float()});
    Ray ray;
    ray.d = nt * l.x + nb * l.y + n * l.z;
    ray.o = offset_ray_origin(p, p_error, n, ray.d);
    Hit hit;
    if (!world.accelerator().intersect(ray, hit)) continue;
    const uint32_t j = mesh.locate(hit.prim, hit_point(prims, ray, hit), -ray.d);
    if (j != UINT32_MAX) hits.push_back(j);
  }
  // Counts per element, exact before the one division.
  std::sort(hits.begin(), hits.end());
  for (size_t a = 0; a < hits.size();) {
    size_t c = a;
    while (c < hits.size() && hits[c] == hits[a]) ++c;
    row[hits[a]] = float(double(c - a) / rays);
    a = c;
  }
}

// ---- Hemicube ------------------------------------------------------------------------------

/// Form factor from the origin (normal +z) to a polygon, by Lambert's contour formula:
/// F = 1/(2 pi) sum over edges of the edge's angle times the z component of its unit normal.
double polygon_form_factor(const DVec3* v, int count) {
  double sum = 0;
  for (int k = 0; k < count; ++k) {
    const DVec3 a = normalize(v[k]), c = normalize(v[(k + 1) % count]);
    const DVec3 g = cross(a, c);
    const double len = length(g);
    if (len > 0) sum += std::atan2(len, dot(a, c)) * g.z / len;
  }
  return std::fabs(sum) / (2 * kPi);
}

/// The hemicube's cells: the top face (z = 1, resolution^2 cells over [-1, 1]^2) then four side
/// faces (resolution x resolution / 2 over [-1, 1] x [0, 1]), all of side h = 2 / resolution.
struct Hemicube {
  int res = 0, half = 0;
  float h = 0;
  std::vector<float> top, side;  ///< exact delta form factors, row-major (row = v, column = u)

  explicit Hemicube(int resolution) : res(resolution), half(resolution / 2), h(2.0f / resolution) {
    top.resize(size_t(res) * res);
    side.resize(size_t(res) * half);
    const double hd = 2.0 / res;
    for (int b = 0; b < res; ++b)
      for (int a = 0; a < res; ++a) {
        const double u0 = -1 + a * hd, u1 = u0 + hd, w0 = -1 + b * hd, w1 = w0 + hd;
        const DVec3 cell[4] = {{u0, w0, 1}, {u1, w0, 1}, {u1, w1, 1}, {u0, w1, 1}};
        top[size_t(b) * res + a] = float(polygon_form_factor(cell, 4));
      }
    for (int b = 0; b < half; ++b)
      for (int a = 0; a < res; ++a) {
        const double u0 = -1 + a * hd, u1 = u0 + hd, z0 = b * hd, z1 = z0 + hd;
        const DVec3 cell[4] = {{1, u0, z0}, {1, u1, z0}, {1, u1, z1}, {1, u0, z1}};
        side[size_t(b) * res + a] = float(polygon_form_factor(cell, 4));
      }
  }
  /// Cells in all five faces.
  size_t cells() const { return top.size() + 4 * side.size(); }
};

/// A convex polygon of at most 4 + 6 clipped corners.
struct Polygon {
  Vec3 p[12];
  int n = 0;
};

/// Sutherland-Hodgman: keeps the part of `in` where dot(plane, p) + d >= 0.
void clip(const Polygon& in, Vec3 plane, float d, Polygon& out) {
  out.n = 0;
  for (int k = 0; k < in.n; ++k) {
    const Vec3 a = in.p[k], c = in.p[(k + 1) % in.n];
    const float fa = dot(plane, a) + d, fc = dot(plane, c) + d;
    if (fa >= 0) out.p[out.n++] = a;
    if ((fa >= 0) != (fc >= 0)) out.p[out.n++] = a + (c - a) * (fa / (fa - fc));
  }
}

/// Local (x, y, z) to face (u, v, w) coordinates (w: depth along the face's axis).
Vec3 to_face(int face, Vec3 q) {
  switch (face) {
    case 0:
      return q;
    case 1:
      return {q.y, q.z, q.x};
    case 2:
      return {q.y, q.z, -q.x};
    case 3:
      return {q.x, q.z, q.y};
    default:
      return {q.x, q.z, -q.y};
  }
}

/// Per-thread z-buffer over all cells of the hemicube.
struct ZBuffer {
  std::vector<float> depth;
  std::vector<uint32_t> id;
  explicit ZBuffer(size_t cells) : depth(cells), id(cells) {}
  void clear() {
    std::fill(depth.begin(), depth.end(), kInfinity);
    std::fill(id.begin(), id.end(), UINT32_MAX);
  }
};

/// Rasterises polygon `poly` (local coordinates, in front of the hemicube's base) of element j
/// (plane: dot(m, x) = offset) onto one face, keeping the nearest element per cell centre.
void rasterise_face(const Hemicube& hc, int face, const Polygon& poly, Vec3 m, float offset,
                    uint32_t j, ZBuffer& zb) {
  const bool top = face == 0;
  Polygon a, c;
  a.n = poly.n;
  for (int k = 0; k < poly.n; ++k) a.p[k] = to_face(face, poly.p[k]);
  // The face's pyramid: |u| <= w, |v| <= w (side faces: v >= 0 holds as z > 0 already).
  const Vec3 planes[4] = {{-1, 0, 1}, {1, 0, 1}, {0, -1, 1}, {0, 1, 1}};
  for (int k = 0; k < (top ? 4 : 3); ++k) {
    int inside = 0;
    for (int q = 0; q < a.n; ++q) inside += dot(planes[k], a.p[q]) >= 0;
    if (inside == 0) return;
    if (inside == a.n) continue;
    clip(a, planes[k], 0.0f, c);
    a = c;
  }
  if (a.n < 3) return;
  // Project to cell coordinates (cell (i, k) has its centre at (i + 0.5, k + 0.5)).
  const float vmin = top ? -1.0f : 0.0f, inv_h = 1.0f / hc.h;
  float x[12], y[12], x0 = kInfinity, x1 = -kInfinity, y0 = kInfinity, y1 = -kInfinity;
  for (int k = 0; k < a.n; ++k) {
    x[k] = (a.p[k].x / a.p[k].z + 1.0f) * inv_h;
    y[k] = (a.p[k].y / a.p[k].z - vmin) * inv_h;
    x0 = std::min(x0, x[k]), x1 = std::max(x1, x[k]), y0 = std::min(y0, y[k]),
    y1 = std::max(y1, y[k]);
  }
  float area = 0;
  for (int k = 0; k < a.n; ++k) {
    const int q = (k + 1) % a.n;
    area += x[k] * y[q] - x[q] * y[k];
  }
  if (!(std::fabs(area) > 0)) return;
  const float sign = area > 0 ? 1.0f : -1.0f;
  const int cols = hc.res, rows = top ? hc.res : hc.half;
  const int ia = std::max(0, int(std::ceil(x0 - 0.5f))),
            ib = std::min(cols - 1, int(std::floor(x1 - 0.5f)));
  const int ka = std::max(0, int(std::ceil(y0 - 0.5f))),
            kb = std::min(rows - 1, int(std::floor(y1 - 0.5f)));
  const Vec3 mf = to_face(face, m);
  const size_t base = top ? 0 : hc.top.size() + size_t(face - 1) * hc.side.size();
  for (int k = ka; k <= kb; ++k) {
    const float py = k + 0.5f;
    for (int i = ia; i <= ib; ++i) {
      const float px = i + 0.5f;
      bool in = true;
      for (int e = 0; e < a.n && in; ++e) {
        const int q = (e + 1) % a.n;
        in = sign * ((x[q] - x[e]) * (py - y[e]) - (y[q] - y[e]) * (px - x[e])) >= 0;
      }
      if (!in) continue;
      // Distance along the cell's direction d = (u, v, 1) to the element's plane.
      const float u = px * hc.h - 1.0f, v = py * hc.h + vmin;
      const float depth = offset / (mf.x * u + mf.y * v + mf.z);
      const size_t cell = base + size_t(k) * cols + i;
      if (depth > 0 && depth < zb.depth[cell]) zb.depth[cell] = depth, zb.id[cell] = j;
    }
  }
}

/// Row i of the hemicube matrix.
void hemicube_row(const Hemicube& hc, const RadiosityMesh& mesh, size_t i, float near, float* row,
                  ZBuffer& zb) {
  const std::vector<RadiosityElement>& els = mesh.elements();
  const Vec3* vs = mesh.vertices().data();
  const RadiosityElement& ei = els[i];
  const Vec3 c = ei.centroid, n = ei.normal;
  Vec3 t, b;
  orthonormal_basis(n, t, b);
  auto local = [&](Vec3 p) {
    const Vec3 d = p - c;
    return Vec3(dot(d, t), dot(d, b), dot(d, n));
  };
  zb.clear();
  for (size_t j = 0; j < els.size(); ++j) {
    const RadiosityElement& ej = els[j];
    if (j == i || !(dot(ej.normal, c - ej.centroid) > 0)) continue;  // only elements facing i
    Polygon poly, clipped;
    poly.n = ej.corners;
    bool any_front = false;
    for (int k = 0; k < ej.corners; ++k) {
      poly.p[k] = local(vs[ej.v[k]]);
      any_front |= poly.p[k].z > near;
    }
    if (!any_front) continue;
    // Clip to the near plane z = near above the base.
    clip(poly, {0, 0, 1}, -near, clipped);
    if (clipped.n < 3) continue;
    const Vec3 m = {dot(ej.normal, t), dot(ej.normal, b), dot(ej.normal, n)};
    const float offset = dot(m, poly.p[0]);
    for (int face = 0; face < 5; ++face)
      rasterise_face(hc, face, clipped, m, offset, uint32_t(j), zb);
  }
  // Sum the delta form factors per element seen.
  const size_t top = hc.top.size(), side = hc.side.size();
  for (size_t cell = 0; cell < zb.id.size(); ++cell)
    if (zb.id[cell] != UINT32_MAX)
      row[zb.id[cell]] += cell < top ? hc.top[cell] : hc.side[(cell - top) % side];
}

}  // namespace

FormFactors raycast_form_factors(const World& world, const RadiosityMesh& mesh, int rays,
                                 uint64_t seed) {
  if (rays < 1) throw Error(fmt::format("form factors: rays must be at least 1, not {}", rays));
  FormFactors ff = allocate(mesh.size());
  const Timer timer;
  const size_t n = ff.n;
  parallel_for_range(
      n,
      [&](size_t begin, size_t end) {
        std::vector<uint32_t> hits;
        hits.reserve(size_t(rays));
        for (size_t i = begin; i < end; ++i)
          raycast_row(world, mesh, i, rays, seed, &ff.f[i * n], hits);
      },
      4);
  ff.seconds = timer.elapsed_s();
  form_factor_diagnostics(mesh, ff);
  return ff;
}

FormFactors hemicube_form_factors(const RadiosityMesh& mesh, int resolution) {
  if (resolution < 2 || resolution % 2 != 0 || resolution > 4096)
    throw Error(
        fmt::format("form factors: the hemicube resolution must be even and in [2, 4096], "
                    "not {}",
                    resolution));
  FormFactors ff = allocate(mesh.size());
  const Timer timer;
  const Hemicube hc(resolution);
  // The near plane: a millionth of the mesh's extent above the base (a neighbour sharing an
  // edge loses only that sliver).
  Bounds3 bounds;
  for (const Vec3& v : mesh.vertices()) bounds.extend(v);
  const float near = mesh.vertices().empty() ? 0.0f : 1e-6f * max_component(bounds.hi - bounds.lo);
  const size_t n = ff.n;
  parallel_for_range(
      n,
      [&](size_t begin, size_t end) {
        ZBuffer zb(hc.cells());
        for (size_t i = begin; i < end; ++i) hemicube_row(hc, mesh, i, near, &ff.f[i * n], zb);
      },
      4);
  ff.seconds = timer.elapsed_s();
  form_factor_diagnostics(mesh, ff);
  return ff;
}

FormFactors compute_form_factors(const World& world, const RadiosityMesh& mesh,
                                 const FormFactorOptions& options) {
  if (options.method == "raycast")
    return raycast_form_factors(world, mesh, options.rays, options.seed);
  if (options.method == "hemicube") return hemicube_form_factors(mesh, options.resolution);
  throw Error(
      fmt::format("form factors: unknown method '{}' (valid: hemicube, raycast)", options.method));
}

void form_factor_diagnostics(const RadiosityMesh& mesh, FormFactors& ff) {
  const size_t n = ff.n;
  const std::vector<RadiosityElement>& els = mesh.elements();
  std::vector<double> sums(n), num(n), den(n);
  // Per row, then summed in order: the same result for any thread count.
  parallel_for(
      n,
      [&](size_t i) {
        const float* row = &ff.f[i * n];
        double s = 0, a = 0, d = 0;
        for (size_t j = 0; j < n; ++j) {
          s += row[j];
          if (j <= i) continue;
          const double x = double(els[i].area) * row[j], y = double(els[j].area) * ff.f[j * n + i];
          a += std::fabs(x - y), d += x + y;
        }
        sums[i] = s, num[i] = a, den[i] = d;
      },
      16);
  double a = 0, d = 0;
  ff.max_row_sum = n ? -kInfinity : 0, ff.min_row_sum = n ? kInfinity : 0;
  for (size_t i = 0; i < n; ++i) {
    a += num[i], d += den[i];
    ff.max_row_sum = std::max(ff.max_row_sum, sums[i]);
    ff.min_row_sum = std::min(ff.min_row_sum, sums[i]);
  }
  ff.reciprocity_error = d > 0 ? a / d : 0;
}

}  // namespace penumbra
