#pragma once
/// Input checks of the meshes that accel-bench and collide read directly (the renderer's World
/// makes the same checks on scenes), and the printing of their readers' warnings.
#include <string>
#include <vector>

#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// Throws InputError naming `file` when `mesh` has no triangles, or when a vertex that a
/// triangle uses is NaN, infinite or beyond kMaxCoordinate (naming the vertex and its value):
/// such meshes gave NaN statistics, and Embree asserts on coordinates above about 1e18.
void check_mesh_input(const TriangleMesh& mesh, const std::string& file);

/// Prints each warning to stderr as "warning: ...", as `render` prints its scene's.
void print_warnings(const std::vector<std::string>& warnings);

}  // namespace penumbra
