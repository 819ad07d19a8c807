#include "penumbra/scene/pbrt_shapes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/geometry/loop_subdivision.h"
#include "penumbra/scene/gzip_reader.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/ply_reader.h"
#include "penumbra/scene/transform_parser.h"

namespace penumbra {

namespace {

namespace fs = std::filesystem;

// Segments of a full disk; partial disks get a proportional share (at least 3).
constexpr int kDiskSegments = 64;

ShapeDesc make_shape(TriangleMesh mesh, const PbrtShapeContext& ctx) {
  ShapeDesc s;
  s.geometry = std::move(mesh);
  s.to_world = ctx.to_world;
  return s;
}

// pbrt's front side: the winding's normal, turned by ReverseOrientation, or (with per-vertex
// normals) the side the normals point to, for every triangle on its own; ReverseOrientation then
// negates the normals first (pbrt-v4's TriangleMesh does).
void orient(TriangleMesh& mesh, bool reverse) {
  if (mesh.normals.empty()) {
    if (reverse)
      for (size_t t = 0; t < mesh.indices.size(); t += 3)
        std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    return;
  }
  if (reverse)
    for (Vec3& n : mesh.normals) n = -n;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const Vec3 ng =
        cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    const Vec3 ns = mesh.normals[a] + mesh.normals[b] + mesh.normals[c];
    if (dot(ng, ns) < 0) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  }
}

// Positions, normals and uvs of a mesh-like shape, checked against each other.
TriangleMesh read_vertices(const PbrtEntity& e) {
  TriangleMesh mesh;
  mesh.positions = e.params.get_vec3s("P", "point3");
  if (mesh.positions.empty()) e.loc.fail(e.what("Shape") + " needs \"point3 P\"");
  mesh.normals = e.params.get_vec3s("N", "normal3");
  mesh.uvs = e.params.get_vec2s("uv");
  const size_t n = mesh.positions.size();
  if (!mesh.normals.empty() && mesh.normals.size() != n)
    e.params.find("N", "normal3")
        ->loc.fail("\"N\" has " + std::to_string(mesh.normals.size()) + " normals for " +
                   std::to_string(n) + " positions");
  if (!mesh.uvs.empty() && mesh.uvs.size() != n)
    e.params.find("uv", "point2 vector2 float")
        ->loc.fail("\"uv\" has " + std::to_string(mesh.uvs.size()) + " pairs for " +
                   std::to_string(n) + " positions");
  for (const Vec3& nn : mesh.normals)
    if (nn == Vec3(0.0f)) e.params.find("N", "normal3")->loc.fail("\"N\" holds a zero normal");
  return mesh;
}

// The "indices" of a mesh of polygons with `per` vertices; optional when there is just one.
std::vector<uint32_t> read_indices(const PbrtEntity& e, size_t per, size_t vertices) {
  const PbrtParam* p = e.params.find("indices", "integer");
  if (!p) {
    if (vertices != per)
      e.loc.fail(e.what("Shape") + " needs \"integer indices\" (optional only with exactly " +
                 std::to_string(per) + " vertices)");
    std::vector<uint32_t> all(per);
    for (size_t i = 0; i < per; ++i) all[i] = uint32_t(i);
    return all;
  }
  if (p->numbers.size() % per != 0)
    p->loc.fail("\"indices\" needs a multiple of " + std::to_string(per) + " values, got " +
                std::to_string(p->numbers.size()));
  std::vector<uint32_t> out;
  out.reserve(p->numbers.size());
  for (double v : p->numbers) {
    // Written so that NaN fails too; the value is printed as a double (a fuzzed 2.4e59 made the
    // former int64_t conversion undefined).
    if (!(v >= 0 && v < double(vertices)) || v != std::floor(v))
      p->loc.fail(
          fmt::format("vertex index {:g} out of range or not an integer (the mesh has {} "
                      "vertices)",
                      v, vertices));
    out.push_back(uint32_t(v));
  }
  return out;
}

std::vector<ShapeDesc> triangle_mesh(const PbrtEntity& e, const PbrtShapeContext& ctx) {
  TriangleMesh mesh = read_vertices(e);
  mesh.indices = read_indices(e, 3, mesh.positions.size());
  orient(mesh, ctx.reverse_orientation);
  std::vector<ShapeDesc> out;
  out.push_back(make_shape(std::move(mesh), ctx));
  return out;
}

std::vector<ShapeDesc> bilinear_mesh(const PbrtEntity& e, const PbrtShapeContext& ctx,
                                     std::vector<std::string>& warnings) {
  TriangleMesh mesh = read_vertices(e);
  const std::vector<uint32_t> quads = read_indices(e, 4, mesh.positions.size());
  // Patch (p00, p10, p01, p11) as the triangles (p00, p10, p11) and (p00, p11, p01): the same
  // front side as the patch's dp/du x dp/dv, exact when the patch is planar.
  size_t bent = 0;
  for (size_t q = 0; q < quads.size(); q += 4) {
    const uint32_t v00 = quads[q], v10 = quads[q + 1], v01 = quads[q + 2], v11 = quads[q + 3];
    mesh.indices.insert(mesh.indices.end(), {v00, v10, v11, v00, v11, v01});
    const Vec3& p00 = mesh.positions[v00];
    const Vec3 n = cross(mesh.positions[v10] - p00, mesh.positions[v01] - p00);
    const Vec3 d = mesh.positions[v11] - p00;
    if (std::fabs(dot(n, d)) > 1e-4f * length(n) * length(d)) ++bent;
  }
  if (bent)
    pbrt_warn(warnings, e.loc,
              std::to_string(bent) + " of " + std::to_string(quads.size() / 4) +
                  " bilinear patches are not planar; each is approximated by two triangles");
  orient(mesh, ctx.reverse_orientation);
  std::vector<ShapeDesc> out;
  out.push_back(make_shape(std::move(mesh), ctx));
  return out;
}

// pbrt-v4's "loopsubdiv": control points "P", triangles "indices" (required), "levels" (3);
// subdivided by geometry/loop_subdivision.h, with limit positions and normals as pbrt's.
std::vector<ShapeDesc> loop_subdiv(const PbrtEntity& e, const PbrtShapeContext& ctx,
                                   std::vector<std::string>& warnings) {
  const std::vector<Vec3> p = e.params.get_vec3s("P", "point3");
  if (p.empty()) e.loc.fail("Shape \"loopsubdiv\" needs \"point3 P\"");
  if (!e.params.has("indices")) e.loc.fail("Shape \"loopsubdiv\" needs \"integer indices\"");
  const std::vector<uint32_t> indices = read_indices(e, 3, p.size());
  const int levels = e.params.get_int("levels", 3);
  LoopSubdivision sub;
  try {
    sub = loop_subdivide(p, indices, levels);
  } catch (const InputError&) {
    throw;
  } catch (const Error& err) {
    const PbrtParam* lp = e.params.find("levels", "integer");
    const bool about_levels = std::string(err.what()).find("\"levels\"") != std::string::npos;
    (lp && about_levels ? lp->loc : e.loc).fail(std::string("Shape \"loopsubdiv\": ") + err.what());
  }
  if (sub.nonmanifold_edges)
    pbrt_warn(warnings, e.loc,
              fmt::format("loopsubdiv: {} edges are shared by more than two triangles; they are "
                          "subdivided as creases (boundary rules)",
                          sub.nonmanifold_edges));
  if (sub.nonmanifold_vertices)
    pbrt_warn(warnings, e.loc,
              fmt::format("loopsubdiv: {} vertices are not on one fan of triangles; they are kept "
                          "fixed (corners)",
                          sub.nonmanifold_vertices));
  orient(sub.mesh, ctx.reverse_orientation);
  std::vector<ShapeDesc> out;
  out.push_back(make_shape(std::move(sub.mesh), ctx));
  return out;
}

std::vector<ShapeDesc> ply_mesh(const PbrtEntity& e, const PbrtShapeContext& ctx,
                                std::vector<std::string>& warnings) {
  const std::string name = e.params.get_string("filename", "");
  if (name.empty()) e.loc.fail("Shape \"plymesh\" needs \"string filename\"");
  const std::string path = pbrt_resolve(name, ctx.search_dirs);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) e.loc.fail("PLY file not found: " + path);
  TriangleMesh mesh = path.ends_with(".gz")
                          ? parse_ply(pbrt_read_file(path, e.loc), path, &warnings)
                          : read_ply(path, &warnings);
  if (mesh.triangle_count() == 0) e.loc.fail("PLY file has no faces: " + path);
  orient(mesh, ctx.reverse_orientation);
  std::vector<ShapeDesc> out;
  out.push_back(make_shape(std::move(mesh), ctx));
  return out;
}

std::vector<ShapeDesc> sphere(const PbrtEntity& e, const PbrtShapeContext& ctx,
                              std::vector<std::string>& warnings) {
  const double radius = e.params.get_float("radius", 1.0);
  if (!(radius > 0)) e.loc.fail("sphere radius must be positive");
  const double zmin = e.params.get_float("zmin", -radius),
               zmax = e.params.get_float("zmax", radius);
  const double phimax = e.params.get_float("phimax", 360);
  if (zmin > -radius || zmax < radius || phimax < 360)
    pbrt_warn(warnings, e.loc,
              "partial spheres (zmin, zmax, phimax) are not supported; the whole sphere is used");
  if (ctx.reverse_orientation)
    pbrt_warn(warnings, e.loc,
              "ReverseOrientation on a sphere is not supported: its front side stays outward");
  if (!is_similarity(ctx.to_world))
    e.loc.fail(
        "a sphere's transform must be a similarity (rotations, translations, uniform "
        "scales): penumbra has no ellipsoids");
  ShapeDesc s;
  s.geometry = SphereData{{0, 0, 0}, float(radius)};
  s.to_world = ctx.to_world;
  std::vector<ShapeDesc> out;
  out.push_back(std::move(s));
  return out;
}

std::vector<ShapeDesc> disk(const PbrtEntity& e, const PbrtShapeContext& ctx,
                            std::vector<std::string>& warnings) {
  const float h = float(e.params.get_float("height", 0));
  const double r = e.params.get_float("radius", 1), ri = e.params.get_float("innerradius", 0);
  const double phimax = std::clamp(e.params.get_float("phimax", 360), 0.0, 360.0);
  if (!(r > 0) || ri < 0 || ri >= r) e.loc.fail("disk needs 0 <= innerradius < radius");
  if (!(phimax > 0)) e.loc.fail("disk phimax must be positive");
  const int n = std::max(3, int(std::ceil(kDiskSegments * phimax / 360.0)));
  TriangleMesh m;
  // Rings of vertices at radius r (outer) and ri (inner, or the centre), u = phi / phimax,
  // v = (r - radius) / (r - ri) as pbrt's disk parameterisation; front side +z.
  for (int i = 0; i <= n; ++i) {
    const double phi = phimax * std::numbers::pi / 180.0 * i / n;
    const float c = float(std::cos(phi)), s = float(std::sin(phi)), u = float(i) / float(n);
    m.positions.push_back({float(r) * c, float(r) * s, h});
    m.positions.push_back({float(ri) * c, float(ri) * s, h});
    m.uvs.push_back({u, 0.0f});
    m.uvs.push_back({u, 1.0f});
  }
  for (uint32_t i = 0; i < uint32_t(n); ++i) {
    const uint32_t out0 = 2 * i, in0 = 2 * i + 1, out1 = 2 * i + 2, in1 = 2 * i + 3;
    m.indices.insert(m.indices.end(), {in0, out0, out1});
    if (ri > 0) m.indices.insert(m.indices.end(), {in0, out1, in1});
  }
  pbrt_warn(warnings, e.loc,
            "disk tessellated into " + std::to_string(m.triangle_count()) + " triangles");
  orient(m, ctx.reverse_orientation);
  std::vector<ShapeDesc> out;
  out.push_back(make_shape(std::move(m), ctx));
  return out;
}

}  // namespace

std::string pbrt_resolve(const std::string& file, const std::vector<std::string>& dirs) {
  const fs::path p(file);
  if (p.is_absolute()) return file;
  std::error_code ec;
  for (const std::string& d : dirs) {
    const fs::path candidate = d.empty() ? p : fs::path(d) / p;
    if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
  }
  return (dirs.empty() || dirs[0].empty() ? p : fs::path(dirs[0]) / p).lexically_normal().string();
}

std::string pbrt_read_file(const std::string& path, const PbrtLoc& loc) {
  // Both through read_input_file: regular files only, bounded by their size. Gzip data is
  // inflated in memory up to the memory limit; its errors (at their byte offset) also name the
  // directive that asked for the file.
  if (!path.ends_with(".gz")) return read_file_contents(path);
  try {
    return read_gzip_file(path);
  } catch (const InputError& e) {
    loc.fail(e.what());
  }
}

std::vector<ShapeDesc> map_pbrt_shape(const PbrtEntity& e, const PbrtShapeContext& ctx,
                                      std::vector<std::string>& warnings) {
  if (e.params.find("alpha", "float texture"))
    pbrt_warn(warnings, e.loc, "\"alpha\" (cut-outs) is not supported; the shape is opaque");
  if (e.type == "trianglemesh") return triangle_mesh(e, ctx);
  if (e.type == "bilinearmesh") return bilinear_mesh(e, ctx, warnings);
  if (e.type == "plymesh") return ply_mesh(e, ctx, warnings);
  if (e.type == "sphere") return sphere(e, ctx, warnings);
  if (e.type == "disk") return disk(e, ctx, warnings);
  if (e.type == "loopsubdiv") return loop_subdiv(e, ctx, warnings);
  if (e.type == "cylinder" || e.type == "curve")
    pbrt_warn(warnings, e.loc, "Shape \"" + e.type + "\" is not supported; skipped");
  else
    e.loc.fail("unknown Shape \"" + e.type +
               "\" (pbrt-v4 has: bilinearmesh, curve, cylinder, disk, loopsubdiv, plymesh, "
               "sphere, trianglemesh)");
  for (const PbrtParam& p : e.params.all()) p.used = true;  // skipped: no unused reports
  return {};
}

}  // namespace penumbra
