#pragma once
/// glTF mesh primitives as penumbra triangle meshes: TRIANGLES (indexed or not), TRIANGLE_STRIP
/// and TRIANGLE_FAN (converted to triangles); POINTS and LINES are skipped with a warning.
#include <optional>
#include <string>
#include <vector>

#include "penumbra/geometry/triangle_mesh.h"
#include "penumbra/scene/gltf_accessors.h"

namespace penumbra {

/// One primitive of a glTF mesh, read and checked.
struct GltfPrimitive {
  TriangleMesh mesh;
  int material = -1;  ///< glTF material index, -1 for the default material
  std::string path;   ///< "/meshes/M/primitives/P"
};

/// The primitives of mesh `index` that have triangles (POSITION, optional NORMAL and TEXCOORD_0,
/// v flipped to penumbra's bottom-left uv origin). Every index is checked against the vertex
/// count; other attributes, morph targets and skipped modes go to `warnings`.
std::vector<GltfPrimitive> read_gltf_mesh(const GltfSource& src, int index,
                                          std::vector<std::string>& warnings);

}  // namespace penumbra
