#include "penumbra/scene/shape_parser.h"

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <system_error>
#include <vector>

#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/transform_parser.h"

namespace penumbra {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Fails when `v` has a key that neither every shape nor a shape of `type` takes.
void check_shape_keys(const json& v, const JsonPlace& place, const std::string& type) {
  std::vector<std::string> known = {"type",      "name",      "material",     "emission",
                                    "two_sided", "transform", "transform_end"};
  if (type == "sphere") {
    known.insert(known.end(), {"center", "radius"});
  } else if (type == "quad") {
    known.insert(known.end(), {"origin", "edge1", "edge2"});
  } else if (type == "mesh") {
    known.insert(known.end(), {"positions", "indices", "normals", "uvs"});
  } else if (type == "obj" || type == "ply") {
    known.push_back("file");
  } else {
    place.key("type").fail("unknown shape type \"" + type +
                           "\" (expected one of: instance, mesh, obj, ply, quad, sphere)");
  }
  json_check_keys(v, place, known, "a " + type + " shape");
}

SphereData parse_sphere(const json& v, const JsonPlace& place) {
  SphereData s;
  s.center = json_vec3(json_require(v, place, "center"), place.key("center"));
  s.radius = json_float(json_require(v, place, "radius"), place.key("radius"));
  if (!(s.radius > 0)) place.key("radius").fail("radius must be positive");
  return s;
}

QuadData parse_quad(const json& v, const JsonPlace& place) {
  QuadData q;
  q.p = json_vec3(json_require(v, place, "origin"), place.key("origin"));
  q.e1 = json_vec3(json_require(v, place, "edge1"), place.key("edge1"));
  q.e2 = json_vec3(json_require(v, place, "edge2"), place.key("edge2"));
  if (cross(q.e1, q.e2) == Vec3(0.0f))
    place.fail("edge1 and edge2 are parallel or zero: the quad has no area");
  return q;
}

// The array at `key` of `v`, which must have `count` elements, one per position.
const json* per_vertex_array(const json& v, const JsonPlace& place, const std::string& key,
                             size_t count) {
  const json* a = json_find(v, key);
  if (!a) return nullptr;
  json_array(*a, place.key(key));
  if (a->size() != count)
    place.key(key).fail("expected " + std::to_string(count) + " " + key +
                        " (one per position), got " + std::to_string(a->size()));
  return a;
}

TriangleMesh parse_inline_mesh(const json& v, const JsonPlace& place) {
  TriangleMesh mesh;
  // Positions.
  const JsonPlace pp = place.key("positions");
  const json& positions = json_array(json_require(v, place, "positions"), pp);
  if (positions.size() > UINT32_MAX) pp.fail("too many positions (at most 2^32 - 1)");
  mesh.positions.reserve(positions.size());
  for (size_t i = 0; i < positions.size(); ++i)
    mesh.positions.push_back(json_vec3(positions[i], pp.index(i)));

  // Triangles: three indices into the positions each.
  const JsonPlace ip = place.key("indices");
  const json& indices = json_array(json_require(v, place, "indices"), ip);
  if (indices.empty()) ip.fail("a mesh needs at least one triangle");
  mesh.indices.reserve(3 * indices.size());
  for (size_t t = 0; t < indices.size(); ++t) {
    const JsonPlace tp = ip.index(t);
    if (!indices[t].is_array() || indices[t].size() != 3)
      tp.fail("expected an array of 3 vertex indices");
    for (size_t k = 0; k < 3; ++k) {
      const int64_t i = json_int(indices[t][k], tp.index(k), 0, UINT32_MAX);
      if (static_cast<size_t>(i) >= positions.size())
        tp.index(k).fail("vertex index " + std::to_string(i) + " out of range (the mesh has " +
                         std::to_string(positions.size()) + " positions)");
      mesh.indices.push_back(static_cast<uint32_t>(i));
    }
  }

  // Optional per-vertex normals and texture coordinates.
  if (const json* normals = per_vertex_array(v, place, "normals", positions.size())) {
    mesh.normals.reserve(normals->size());
    for (size_t i = 0; i < normals->size(); ++i) {
      const Vec3 n = json_vec3((*normals)[i], place.key("normals").index(i));
      if (n == Vec3(0.0f)) place.key("normals").index(i).fail("normal must not be zero");
      mesh.normals.push_back(n);
    }
  }
  if (const json* uvs = per_vertex_array(v, place, "uvs", positions.size())) {
    mesh.uvs.reserve(uvs->size());
    for (size_t i = 0; i < uvs->size(); ++i)
      mesh.uvs.push_back(json_vec2((*uvs)[i], place.key("uvs").index(i)));
  }
  return mesh;
}

// Reads the OBJ or PLY file named by "file", relative to `base_dir` unless absolute; appends
// the reader's warnings to `warnings`.
TriangleMesh read_mesh_file(const json& v, const JsonPlace& place, const std::string& type,
                            const std::string& base_dir, std::vector<std::string>& warnings) {
  const JsonPlace fp = place.key("file");
  const std::string file = json_string(json_require(v, place, "file"), fp);
  if (file.empty()) fp.fail("must not be empty");
  fs::path path(file);
  if (path.is_relative() && !base_dir.empty()) path = fs::path(base_dir) / path;
  const std::string resolved = path.lexically_normal().string();

  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != "." + type)
    fp.fail("a shape of type \"" + type + "\" needs a ." + type + " file, got \"" + file + "\"");
  std::error_code ec;
  if (!fs::exists(path, ec)) fp.fail("mesh file not found: " + resolved);
  if (!fs::is_regular_file(path, ec)) fp.fail("not a regular file: " + resolved);

  TriangleMesh mesh = read_mesh(resolved, &warnings);
  if (mesh.triangle_count() == 0) fp.fail("mesh file has no triangles: " + resolved);
  return mesh;
}

// The end transform of a moving shape ("transform_end", time 1), with its checks.
void parse_motion(const json& ops, const JsonPlace& place, const std::string& type,
                  ShapeDesc& shape) {
  const JsonPlace ep = place.key("transform_end");
  const Transform end = parse_transform(ops, ep);
  if (shape.emission)
    ep.fail(
        "a moving shape cannot be emissive: area lights sample points on their shapes without a "
        "time (make the light static, or give the moving shape no \"emission\")");
  if (type == "sphere" && !is_similarity(end))
    ep.fail(
        "a sphere's transform_end must be a similarity (rotations, translations, uniform "
        "scales); this one scales non-uniformly or shears");
  if (end.swaps_handedness() != shape.to_world.swaps_handedness())
    ep.fail(
        "transform_end mirrors the shape and transform does not (or the reverse): the shape "
        "would turn inside out while moving");
  shape.to_world_end = end;
}

std::string unknown_material(const std::string& name, const std::set<std::string>& materials) {
  if (materials.empty()) return "unknown material \"" + name + "\" (no materials are defined)";
  std::string list;
  for (const std::string& m : materials) list += (list.empty() ? "" : ", ") + m;
  return "unknown material \"" + name + "\" (defined: " + list + ")";
}

}  // namespace

ShapeDesc parse_shape(const json& v, const JsonPlace& place, const std::set<std::string>& materials,
                      const std::string& base_dir, std::vector<std::string>& warnings) {
  if (!v.is_object()) place.fail("expected an object");
  const std::string type = json_string(json_require(v, place, "type"), place.key("type"));
  check_shape_keys(v, place, type);

  // Keys every shape takes; checked before any mesh file is read.
  ShapeDesc shape;
  shape.path = place.path;
  const JsonPlace mp = place.key("material");
  shape.material = json_string(json_require(v, place, "material"), mp);
  if (!materials.count(shape.material)) mp.fail(unknown_material(shape.material, materials));
  if (const json* name = json_find(v, "name")) shape.name = json_string(*name, place.key("name"));
  const json* emission = json_find(v, "emission");
  if (emission) {
    const Rgb radiance = json_radiance(*emission, place.key("emission"));
    if (!radiance.is_black()) shape.emission = radiance;  // black emission: not a light
  }
  if (const json* two_sided = json_find(v, "two_sided")) {
    if (!emission)
      place.key("two_sided")
          .fail(
              "\"two_sided\" applies to emission, and this shape has no "
              "\"emission\"");
    shape.two_sided_emission = json_bool(*two_sided, place.key("two_sided"));
  }
  if (const json* ops = json_find(v, "transform")) {
    shape.to_world = parse_transform(*ops, place.key("transform"));
    if (type == "sphere" && !is_similarity(shape.to_world))
      place.key("transform")
          .fail(
              "a sphere's transform must be a similarity (rotations, translations, uniform "
              "scales); "
              "this one scales non-uniformly or shears");
  }
  if (const json* ops = json_find(v, "transform_end")) parse_motion(*ops, place, type, shape);

  // The geometry, in object space.
  if (type == "sphere") {
    shape.geometry = parse_sphere(v, place);
  } else if (type == "quad") {
    shape.geometry = parse_quad(v, place);
  } else if (type == "mesh") {
    shape.geometry = parse_inline_mesh(v, place);
  } else {
    shape.geometry = read_mesh_file(v, place, type, base_dir, warnings);
  }
  return shape;
}

}  // namespace penumbra
