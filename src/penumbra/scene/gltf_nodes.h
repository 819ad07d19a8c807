#pragma once
/// The glTF node hierarchy: local transforms (a column-major matrix, or translation, rotation and
/// scale) composed from the roots of the chosen scene down. The graph is checked first: a child
/// index out of range, a node with two parents, a cycle or a scene root that is someone's child are
/// errors naming the node; the traversal is iterative, so no depth overflows the stack.
#include <string>
#include <vector>

#include "penumbra/core/transform.h"
#include "penumbra/scene/gltf_accessors.h"

namespace penumbra {

/// A node reached from the scene's roots, with its node-to-world matrix.
struct GltfNodeVisit {
  int node = 0;
  Mat4 world;
  std::string path;  ///< "/nodes/N"
};

/// The local matrix of node `index`: `matrix` (16 numbers, column-major) or T * R * S.
Mat4 gltf_local_matrix(const GltfSource& src, int index);

/// The nodes of scene `scene` (or 0; all parentless nodes with a warning when the file has no
/// scenes) in depth-first pre-order, children in the order listed, each with its world matrix.
std::vector<GltfNodeVisit> traverse_gltf_scene(const GltfSource& src,
                                               std::vector<std::string>& warnings);

}  // namespace penumbra
