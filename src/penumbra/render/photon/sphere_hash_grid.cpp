#include "penumbra/render/photon/sphere_hash_grid.h"

#include <algorithm>
#include <cmath>

#include "penumbra/core/rng.h"

namespace penumbra {

namespace {

/// Cells per axis at most, so that integer cell coordinates stay small whatever the scene.
constexpr float kMaxResolution = 1 << 20;

}  // namespace

uint32_t SphereHashGrid::bucket(int x, int y, int z) const {
  // The cell's 21-bit coordinates packed and mixed: the classic xor of coordinates times primes
  // (Teschner et al.) clusters badly modulo an even table size.
  constexpr uint64_t kMask = (1u << 21) - 1;
  const uint64_t key = (uint64_t(uint32_t(x)) & kMask) | ((uint64_t(uint32_t(y)) & kMask) << 21) |
                       ((uint64_t(uint32_t(z)) & kMask) << 42);
  return uint32_t(mix64(key) % uint64_t(offsets_.size() - 1));
}

void SphereHashGrid::cell_of(Vec3 p, int c[3]) const {
  for (int a = 0; a < 3; ++a) {
    const float f = (p[a] - bounds_.lo[a]) * inv_cell_;
    c[a] = int(std::clamp(std::floor(f), -1.0f, kMaxResolution));
  }
}

void SphereHashGrid::build(const std::vector<Vec3>& centres, const std::vector<float>& radii) {
  bounds_ = Bounds3();
  float max_r = 0.0f;
  size_t n = 0;
  for (size_t i = 0; i < centres.size(); ++i)
    if (radii[i] > 0.0f) {
      bounds_.extend(centres[i] - Vec3(radii[i]));
      bounds_.extend(centres[i] + Vec3(radii[i]));
      max_r = std::max(max_r, radii[i]);
      ++n;
    }
  offsets_.assign(2 * std::max<size_t>(n, 1) + 1, 0);  // two buckets per sphere
  items_.clear();
  if (n == 0) {
    inv_cell_ = 0.0f;
    return;
  }
  // Cells as wide as the largest sphere, but no more than kMaxResolution per axis.
  const float extent = max_component(bounds_.diagonal());
  const float cell = std::max(2.0f * max_r, extent / kMaxResolution);
  inv_cell_ = 1.0f / cell;

  // Two sweeps over the spheres' cells: count per bucket, then fill (compressed rows). A sphere
  // is listed once per bucket even when two of its cells hash to the same one, or a photon
  // would be counted twice.
  auto for_each_cell = [&](size_t i, auto&& f) {
    int lo[3], hi[3];
    cell_of(centres[i] - Vec3(radii[i]), lo);
    cell_of(centres[i] + Vec3(radii[i]), hi);
    uint32_t seen[8];
    int count = 0;
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const uint32_t b = bucket(x, y, z);
          if (std::find(seen, seen + count, b) != seen + count) continue;
          if (count < 8) seen[count++] = b;
          f(b);
        }
  };
  for (size_t i = 0; i < centres.size(); ++i)
    if (radii[i] > 0.0f) for_each_cell(i, [&](uint32_t b) { ++offsets_[b + 1]; });
  for (size_t b = 1; b < offsets_.size(); ++b) offsets_[b] += offsets_[b - 1];
  items_.resize(offsets_.back());
  std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (size_t i = 0; i < centres.size(); ++i)
    if (radii[i] > 0.0f) for_each_cell(i, [&](uint32_t b) { items_[fill[b]++] = uint32_t(i); });
}

std::pair<const uint32_t*, const uint32_t*> SphereHashGrid::candidates(Vec3 p) const {
  if (items_.empty() || !bounds_.contains(p)) return {nullptr, nullptr};
  int c[3];
  cell_of(p, c);
  const uint32_t b = bucket(c[0], c[1], c[2]);
  return {items_.data() + offsets_[b], items_.data() + offsets_[b + 1]};
}

}  // namespace penumbra
