#include "penumbra/app/mesh_check.h"

#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/geometry/primitive_set.h"

namespace penumbra {

void check_mesh_input(const TriangleMesh& mesh, const std::string& file) {
  if (mesh.triangle_count() == 0) throw InputError(file, "", "the mesh has no triangles");
  for (size_t k = 0; k < mesh.indices.size(); ++k) {
    const uint32_t i = mesh.indices[k];
    const Vec3 p = mesh.positions[i];
    const bool ok = is_finite(p) && std::fabs(p.x) <= kMaxCoordinate &&
                    std::fabs(p.y) <= kMaxCoordinate && std::fabs(p.z) <= kMaxCoordinate;
    if (!ok)
      throw InputError(file, fmt::format("vertex {}", i),
                       fmt::format("({:g}, {:g}, {:g}) is NaN, infinite or beyond +-{:g} (used by "
                                   "triangle {})",
                                   p.x, p.y, p.z, kMaxCoordinate, k / 3));
  }
}

void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) fmt::print(stderr, "warning: {}\n", w);
}

}  // namespace penumbra
