#include "penumbra/accel/leaf_prims.h"

#include "penumbra/core/parallel.h"

namespace penumbra {

void LeafPrims::build(const PrimitiveSet& prims, std::span<const PrimRef> refs) {
  const size_t n = refs.size();
  ids_.resize(n);
  tris_.clear();
  if (prims.all_triangles()) tris_.resize(3 * n);
  parallel_for_range(
      n,
      [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
          const uint32_t id = refs[i].id;
          ids_[i] = id;
          if (!tris_.empty()) {
            const Vec3* v = prims.triangle(id);
            tris_[3 * i] = v[0], tris_[3 * i + 1] = v[1], tris_[3 * i + 2] = v[2];
          }
        }
      },
      4096);
}

}  // namespace penumbra
