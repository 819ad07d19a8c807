#include "penumbra/render/radiosity/cluster_tree.h"

#include <algorithm>
#include <numeric>

namespace penumbra {

ClusterTree ClusterTree::build(const std::vector<ClusterInput>& patches) {
  ClusterTree t;
  const uint32_t n = static_cast<uint32_t>(patches.size());
  if (n < 2) return t;
  t.members_.resize(n);
  std::iota(t.members_.begin(), t.members_.end(), 0u);
  t.patch_parent_.assign(n, kNone);
  t.clusters_.reserve(n - 1);  // a binary tree with n leaves has n - 1 inner nodes
  t.build_range(patches, 0, n, kNone);
  t.position_.resize(n);
  for (uint32_t i = 0; i < n; ++i) t.position_[t.members_[i]] = i;
  return t;
}

// Pre-order: the cluster's index first, then its left and right subtrees, so children come
// after their parents and one backward pass visits every child before its parent.
uint32_t ClusterTree::build_range(const std::vector<ClusterInput>& patches, uint32_t first,
                                  uint32_t count, uint32_t parent) {
  const uint32_t index = static_cast<uint32_t>(clusters_.size());
  clusters_.push_back({});
  clusters_[index].parent = parent;
  clusters_[index].first = first, clusters_[index].count = count;

  // Median split of the centroids along the longest axis of their bounds.
  Bounds3 cb;
  for (uint32_t i = first; i < first + count; ++i) cb.extend(patches[members_[i]].centroid);
  const int axis = cb.max_extent_axis();
  const uint32_t half = count / 2;
  const auto begin = members_.begin() + first;
  std::nth_element(begin, begin + half, begin + count, [&](uint32_t a, uint32_t b) {
    const float ca = patches[a].centroid[axis], cb_ = patches[b].centroid[axis];
    return ca < cb_ || (ca == cb_ && a < b);
  });

  // Children: a single patch is referenced directly, a larger range becomes a cluster.
  const uint32_t ranges[2][2] = {{first, half}, {first + half, count - half}};
  for (int c = 0; c < 2; ++c) {
    const uint32_t f = ranges[c][0], k = ranges[c][1];
    if (k == 1) {
      clusters_[index].child[c] = members_[f];
      patch_parent_[members_[f]] = index;
    } else {
      clusters_[index].child[c] = kClusterBit | build_range(patches, f, k, index);
    }
  }

  // Geometry from the children.
  Cluster& cl = clusters_[index];
  Vec3 weighted(0.f);
  for (uint32_t ref : cl.child) {
    if (ref & kClusterBit) {
      const Cluster& c = clusters_[ref & ~kClusterBit];
      cl.box.extend(c.box);
      weighted += c.centre * c.area;
      cl.area += c.area;
    } else {
      const ClusterInput& p = patches[ref];
      cl.box.extend(p.box);
      weighted += p.centroid * p.area;
      cl.area += p.area;
    }
  }
  cl.centre = cl.area > 0 ? weighted / cl.area : cl.box.center();
  return index;
}

size_t ClusterTree::memory_bytes() const {
  return clusters_.capacity() * sizeof(Cluster) +
         (members_.capacity() + patch_parent_.capacity() + position_.capacity()) * sizeof(uint32_t);
}

}  // namespace penumbra
