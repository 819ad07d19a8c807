#include "penumbra/accel/triangle_blocks.h"

#include <limits>

#include "penumbra/core/parallel.h"

namespace penumbra {

void TriangleBlocks::resize(size_t blocks) {
  blocks_.clear();
  blocks_.resize(blocks);
}

namespace {

/// Lane `lane` of `blk` = triangle `id`, or padding (NaN vertices) for kNoPrim.
void set_lane(TriangleBlock& blk, int lane, const PrimitiveSet& prims, uint32_t id) {
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const Vec3* v = id == kNoPrim ? nullptr : prims.triangle(id);
  blk.id[lane] = id;
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) blk.v[k][a][lane] = v ? v[k][a] : kNaN;
}

}  // namespace

void TriangleBlocks::assign(const PrimitiveSet& prims, std::span<const uint32_t> ids) {
  resize(ids.size() / kLanes);
  parallel_for_range(
      blocks_.size(),
      [&](size_t begin, size_t end) {
        for (size_t b = begin; b < end; ++b)
          for (int lane = 0; lane < kLanes; ++lane)
            set_lane(blocks_[b], lane, prims, ids[b * kLanes + size_t(lane)]);
      },
      1024);
}

void TriangleBlocks::fill(uint32_t first, const PrimitiveSet& prims,
                          std::span<const PrimRef> refs) {
  const auto n = static_cast<uint32_t>(refs.size());
  for (uint32_t b = 0; b < blocks_for(n); ++b)
    for (int lane = 0; lane < kLanes; ++lane) {
      const uint32_t i = b * kLanes + uint32_t(lane);
      set_lane(blocks_[first + b], lane, prims, i < n ? refs[i].id : kNoPrim);
    }
}

}  // namespace penumbra
