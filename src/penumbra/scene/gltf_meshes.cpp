#include "penumbra/scene/gltf_meshes.h"

#include <numeric>

namespace penumbra {

namespace {

// The triangles' vertex indices of a primitive of `mode` from its index list (strips and fans
// converted, keeping the winding of the first triangle as the spec's formulas do).
std::vector<uint32_t> triangulate(const GltfSource& src, int mode, std::vector<uint32_t> idx,
                                  const std::string& at) {
  std::vector<uint32_t> out;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (idx.size() % 3 != 0)
      src.fail(at, std::to_string(idx.size()) + " vertices is not a multiple of 3 (TRIANGLES)");
    return idx;
  }
  if (idx.size() < 3) return out;
  out.reserve((idx.size() - 2) * 3);
  for (size_t i = 0; i + 2 < idx.size(); ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      // Triangle i is (p_i, p_{i+1+i%2}, p_{i+2-i%2}).
      const size_t odd = i % 2;
      out.insert(out.end(), {idx[i], idx[i + 1 + odd], idx[i + 2 - odd]});
    } else {  // fan: (p_{i+1}, p_{i+2}, p_0)
      out.insert(out.end(), {idx[i + 1], idx[i + 2], idx[0]});
    }
  }
  return out;
}

// The primitive's mode; absent (-1 in tinygltf) means TRIANGLES.
int primitive_mode(const tinygltf::Primitive& p) {
  return p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
}

const char* mode_name(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS:
      return "POINTS";
    case TINYGLTF_MODE_LINE:
      return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
      return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
      return "LINE_STRIP";
    default:
      return "?";
  }
}

GltfPrimitive read_primitive(const GltfSource& src, const tinygltf::Primitive& p,
                             const std::string& at, std::vector<std::string>& warnings) {
  GltfPrimitive out;
  out.path = at;
  out.material = p.material;
  if (p.material >= 0 && size_t(p.material) >= src.model.materials.size())
    src.fail(at + "/material", "material " + std::to_string(p.material) + " out of range (" +
                                   std::to_string(src.model.materials.size()) + " materials)");
  const std::string attrs = at + "/attributes/";
  TriangleMesh& mesh = out.mesh;
  mesh.positions = read_gltf_vec3(src, p.attributes.at("POSITION"), attrs + "POSITION");
  const size_t n = mesh.positions.size();
  for (const auto& [name, accessor] : p.attributes) {
    if (name == "POSITION") continue;
    if (name == "NORMAL") {
      mesh.normals = read_gltf_vec3(src, accessor, attrs + name);
    } else if (name == "TEXCOORD_0") {
      mesh.uvs = read_gltf_uv(src, accessor, attrs + name);
      for (Vec2& uv : mesh.uvs) uv.y = 1.0f - uv.y;  // glTF's v runs down the image
    } else {
      warnings.push_back(src.message(attrs + name, "attribute ignored"));
      continue;
    }
    const size_t count = name == "NORMAL" ? mesh.normals.size() : mesh.uvs.size();
    if (count != n)
      src.fail(attrs + name,
               "count " + std::to_string(count) + " differs from POSITION's " + std::to_string(n));
  }
  if (!p.targets.empty()) warnings.push_back(src.message(at + "/targets", "morph targets ignored"));
  // Indices (or 0, 1, 2, ... for a non-indexed primitive), each checked against the vertices.
  std::vector<uint32_t> idx;
  if (p.indices >= 0) {
    idx = read_gltf_indices(src, p.indices, at + "/indices");
    for (uint32_t i : idx)
      if (i >= n)
        src.fail(at + "/indices", "index " + std::to_string(i) + " out of range (" +
                                      std::to_string(n) + " vertices)");
  } else {
    idx.resize(n);
    std::iota(idx.begin(), idx.end(), 0u);
  }
  mesh.indices =
      triangulate(src, primitive_mode(p), std::move(idx), p.indices >= 0 ? at + "/indices" : at);
  return out;
}

}  // namespace

std::vector<GltfPrimitive> read_gltf_mesh(const GltfSource& src, int index,
                                          std::vector<std::string>& warnings) {
  std::vector<GltfPrimitive> out;
  const tinygltf::Mesh& m = src.model.meshes[size_t(index)];
  for (size_t j = 0; j < m.primitives.size(); ++j) {
    const tinygltf::Primitive& p = m.primitives[j];
    const std::string at = "/meshes/" + std::to_string(index) + "/primitives/" + std::to_string(j);
    const int mode = primitive_mode(p);
    if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
      warnings.push_back(src.message(
          at + "/mode", std::string(mode_name(mode)) + " primitive skipped (no triangles)"));
      continue;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN)
      src.fail(at + "/mode", "invalid mode " + std::to_string(mode));
    if (p.attributes.find("POSITION") == p.attributes.end()) {
      warnings.push_back(src.message(at + "/attributes", "no POSITION: primitive skipped"));
      continue;
    }
    GltfPrimitive prim = read_primitive(src, p, at, warnings);
    if (prim.mesh.indices.empty()) {
      warnings.push_back(src.message(at, "no triangles: primitive skipped"));
      continue;
    }
    out.push_back(std::move(prim));
  }
  return out;
}

}  // namespace penumbra
