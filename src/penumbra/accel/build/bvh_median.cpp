#include "penumbra/accel/build/bvh_median.h"

#include <algorithm>

namespace penumbra {

namespace {

/// Box and centroid bounds of `refs`.
void child_bounds(std::span<const PrimRef> refs, Bounds3& box, Bounds3& centroids) {
  for (const PrimRef& r : refs) box.extend(r.bounds()), centroids.extend(r.centroid2());
}

}  // namespace

NodeSplit object_median_split(std::span<PrimRef> refs, uint32_t offset, const Bounds3& centroids) {
  const size_t half = refs.size() / 2;
  const int a = centroids.max_extent_axis();
  // Selection, not sorting: nth_element is O(n) on average.
  if (centroids.diagonal()[a] > 0.0f)
    std::nth_element(refs.begin(), refs.begin() + half, refs.end(),
                     [a](const PrimRef& x, const PrimRef& y) {
                       const float cx = x.centroid2()[a], cy = y.centroid2()[a];
                       return cx < cy || (cx == cy && x.id < y.id);
                     });
  NodeSplit s;
  s.mid = offset + uint32_t(half);
  child_bounds(refs.first(half), s.left, s.left_centroids);
  child_bounds(refs.subspan(half), s.right, s.right_centroids);
  return s;
}

}  // namespace penumbra
