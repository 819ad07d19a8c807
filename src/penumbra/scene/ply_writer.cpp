#include "penumbra/scene/ply_writer.h"

#include <bit>
#include <cstdint>
#include <cstring>

namespace penumbra {

namespace {

static_assert(std::endian::native == std::endian::little, "the PLY writer assumes little endian");

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace

std::string encode_ply(const TriangleMesh& mesh) {
  const size_t n = mesh.positions.size(), faces = mesh.indices.size() / 3;
  const bool normals = mesh.normals.size() == n && n > 0;
  const bool uvs = mesh.uvs.size() == n && n > 0;
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by penumbra\n";
  out += "element vertex " + std::to_string(n) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  if (normals) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (uvs) out += "property float u\nproperty float v\n";
  out += "element face " + std::to_string(faces) + "\n";
  out += "property list uchar uint vertex_indices\nend_header\n";
  out.reserve(out.size() + n * 4 * (3 + (normals ? 3 : 0) + (uvs ? 2 : 0)) + faces * 13);
  for (size_t i = 0; i < n; ++i) {
    put(out, mesh.positions[i].x), put(out, mesh.positions[i].y), put(out, mesh.positions[i].z);
    if (normals)
      put(out, mesh.normals[i].x), put(out, mesh.normals[i].y), put(out, mesh.normals[i].z);
    if (uvs) put(out, mesh.uvs[i].x), put(out, mesh.uvs[i].y);
  }
  for (size_t f = 0; f < faces; ++f) {
    put(out, uint8_t{3});
    for (int k = 0; k < 3; ++k) put(out, uint32_t{mesh.indices[3 * f + k]});
  }
  return out;
}

}  // namespace penumbra
