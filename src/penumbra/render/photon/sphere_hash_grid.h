#pragma once
/// A hash grid over spheres, for finding the spheres that contain a point: SPPM's visible
/// points (each with its own search radius) found from every photon (Hachisuka, Jensen 2009,
/// "Stochastic Progressive Photon Mapping", and pbrt-v4's SPPMIntegrator).
#include <cstdint>
#include <vector>

#include "penumbra/core/bounds.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// A uniform grid of cubic cells hashed into a table of twice as many buckets as spheres. Each
/// sphere is listed in the bucket of every cell its bounding box overlaps; a point's candidates
/// are the spheres listed in its cell's bucket (a superset: hash collisions and box corners
/// bring in spheres that do not contain it, which the caller tests). Built in compressed rows
/// (offsets and one index array), so a build allocates twice and a lookup touches one row.
class SphereHashGrid {
 public:
  /// Builds the grid over spheres (centres[i], radii[i]) for the i where radii[i] > 0; the cell
  /// size is the largest diameter, so a sphere overlaps at most 8 cells.
  void build(const std::vector<Vec3>& centres, const std::vector<float>& radii);

  /// The indices of the spheres that may contain p, as [begin, end) into an internal array
  /// (empty when p is outside every sphere's box).
  std::pair<const uint32_t*, const uint32_t*> candidates(Vec3 p) const;

  /// Bytes held.
  size_t bytes() const { return (offsets_.capacity() + items_.capacity()) * sizeof(uint32_t); }

 private:
  /// The bucket of integer cell (x, y, z).
  uint32_t bucket(int x, int y, int z) const;
  /// The integer cell of p along each axis (unclamped).
  void cell_of(Vec3 p, int c[3]) const;

  Bounds3 bounds_;
  float inv_cell_ = 0;
  std::vector<uint32_t> offsets_;  ///< bucket b lists items_[offsets_[b] .. offsets_[b + 1])
  std::vector<uint32_t> items_;
};

}  // namespace penumbra
