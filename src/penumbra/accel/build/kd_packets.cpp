#include "penumbra/accel/build/kd_packets.h"

#include <limits>

#include "penumbra/core/parallel.h"

namespace penumbra {

std::vector<KdTriPacket, ArrayAllocator<KdTriPacket>> make_kd_packets(
    const PrimitiveSet& prims, std::span<const uint32_t> ids) {
  std::vector<KdTriPacket, ArrayAllocator<KdTriPacket>> packets(ids.size() / 4);
  parallel_for_range(
      packets.size(),
      [&](size_t begin, size_t end) {
        for (size_t p = begin; p < end; ++p) {
          for (int lane = 0; lane < 4; ++lane) {
            const uint32_t id = ids[4 * p + size_t(lane)];
            for (int k = 0; k < 3; ++k) {
              const Vec3 q = id == kNoPrim ? Vec3(std::numeric_limits<float>::quiet_NaN())
                                           : prims.triangle(id)[k];
              for (int a = 0; a < 3; ++a) packets[p].v[k][a][lane] = q[a];
            }
          }
        }
      },
      1024);
  return packets;
}

}  // namespace penumbra
