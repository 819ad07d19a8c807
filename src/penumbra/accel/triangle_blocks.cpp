#include "penumbra/accel/triangle_blocks.h"

#include <cstring>
#include <limits>

namespace penumbra {

void TriangleBlocks::resize(size_t blocks) {
  blocks_.clear();
  blocks_.resize(blocks);
}

template <class IdAt>
void TriangleBlocks::write(uint32_t b, int lanes, const PrimitiveSet& prims, IdAt id) {
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  // Through bytes: a pair's rows run across the two blocks' members.
  auto* bytes = reinterpret_cast<unsigned char*>(&blocks_[b]);
  for (int lane = 0; lane < lanes; ++lane) {
    const uint32_t i = id(lane);
    const Vec3* v = i == kNoPrim ? nullptr : prims.triangle(i);
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) {
        const float x = v ? v[k][a] : kNaN;
        std::memcpy(bytes + sizeof(float) * size_t((3 * k + a) * lanes + lane), &x, sizeof x);
      }
    std::memcpy(bytes + sizeof(float) * size_t(9 * lanes + lane), &i, sizeof i);
  }
}

template <class IdAt>
void TriangleBlocks::write_leaf(uint32_t first, uint32_t n, const PrimitiveSet& prims, IdAt id) {
  // Lanes past n are padding. The same walk as intersect(): pairs where kPairs, then an odd
  // block.
  const uint32_t blocks = blocks_for(n);
  for (uint32_t b = 0; b < blocks;) {
    const int lanes = kPairs && b + 1 < blocks ? 2 * kLanes : kLanes;
    write(first + b, lanes, prims, [&](int lane) {
      const uint32_t i = b * kLanes + uint32_t(lane);
      return i < n ? id(i) : kNoPrim;
    });
    b += uint32_t(lanes / kLanes);
  }
}

void TriangleBlocks::fill(uint32_t first, const PrimitiveSet& prims,
                          std::span<const PrimRef> refs) {
  write_leaf(first, uint32_t(refs.size()), prims, [&](uint32_t i) { return refs[i].id; });
}

void TriangleBlocks::fill(uint32_t first, const PrimitiveSet& prims,
                          std::span<const uint32_t> ids) {
  write_leaf(first, uint32_t(ids.size()), prims, [&](uint32_t i) { return ids[i]; });
}

}  // namespace penumbra
