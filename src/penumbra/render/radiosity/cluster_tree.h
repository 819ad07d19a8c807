#pragma once
/// The cluster tree of clustering radiosity: a binary volume hierarchy over planar patches, built
/// by median splits of their centroids, so that distant groups of patches can exchange energy
/// through one link (Smits, Arvo, Greenberg 1994, "A Clustering Algorithm for Radiosity in
/// Complex Environments"; Sillion 1995, "A Unified Hierarchical Algorithm for Global
/// Illumination with Scattering Volumes and Object Clusters"). It sees only boxes, centroids
/// and areas.
#include <cstdint>
#include <vector>

#include "penumbra/core/bounds.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// What the tree needs of one patch.
struct ClusterInput {
  Bounds3 box;
  Vec3 centroid;
  float area = 0;
};

/// A binary tree of clusters over patches 0..n-1: the root is cluster 0, every cluster has two
/// children (clusters or single patches), and a parent's index is below its children's.
class ClusterTree {
 public:
  /// Set in a child reference that names a cluster; without it the reference is a patch.
  static constexpr uint32_t kClusterBit = 1u << 31;
  static constexpr uint32_t kNone = UINT32_MAX;

  /// One cluster: the union of its members' geometry.
  struct Cluster {
    Bounds3 box;                         ///< of the members' boxes
    Vec3 centre;                         ///< area-weighted mean of the members' centroids
    float area = 0;                      ///< sum of the members' areas
    uint32_t child[2] = {kNone, kNone};  ///< kClusterBit | cluster, or a patch index
    uint32_t parent = kNone;             ///< kNone at the root
    uint32_t first = 0, count = 0;       ///< its members: members()[first, first + count)
  };

  /// The tree over `patches`; empty (no clusters) for fewer than two patches. Each cluster is
  /// split at the median of its members' centroids along the longest axis of their bounds
  /// (ties broken by index, so the tree depends on the input only).
  static ClusterTree build(const std::vector<ClusterInput>& patches);

  bool empty() const { return clusters_.empty(); }
  const std::vector<Cluster>& clusters() const { return clusters_; }
  /// Patch indices in tree order: every cluster's members are contiguous.
  const std::vector<uint32_t>& members() const { return members_; }
  /// The smallest cluster containing `patch` (kNone for an empty tree).
  uint32_t parent_of(uint32_t patch) const { return patch_parent_[patch]; }
  /// Where `patch` is in members(): it is member position(patch) - first of each cluster above.
  uint32_t position(uint32_t patch) const { return position_[patch]; }
  size_t memory_bytes() const;

 private:
  uint32_t build_range(const std::vector<ClusterInput>& patches, uint32_t first, uint32_t count,
                       uint32_t parent);

  std::vector<Cluster> clusters_;
  std::vector<uint32_t> members_;
  std::vector<uint32_t> patch_parent_;
  std::vector<uint32_t> position_;
};

}  // namespace penumbra
