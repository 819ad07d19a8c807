#pragma once
/// An indexed triangle mesh: shared vertex positions, optional per-vertex normals and UVs.
#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/core/vec.h"

namespace penumbra {

/// Indexed triangle mesh. Triangle i uses vertices indices[3i], indices[3i+1], indices[3i+2];
/// the triangle order is the primitive id order. `normals` and `uvs` are empty or have one entry
/// per position.
struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<Vec2> uvs;
  std::vector<uint32_t> indices;

  /// Number of triangles.
  size_t triangle_count() const { return indices.size() / 3; }
};

}  // namespace penumbra
