#pragma once
/// A triangle mesh prepared for collision queries: the triangles in a pose (double precision),
/// each classified valid or degenerate, their boxes, and a bounding-volume hierarchy over them.
/// The hierarchy is the shared binned-SAH binary BVH of accel/build (Wald 2007), built once over
/// the mesh's own (local) coordinates; a new pose transforms the triangles and refits the boxes
/// bottom-up without rebuilding.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/accel/build/bvh_node.h"
#include "penumbra/accel/collision/dvec3.h"
#include "penumbra/core/bounds.h"
#include "penumbra/core/transform.h"
#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra::collision {

/// Size and timing of a mesh's hierarchy.
struct HierarchyStats {
  size_t nodes = 0;      ///< nodes (inner and leaves)
  size_t leaves = 0;     ///< leaves
  size_t max_depth = 0;  ///< depth of the deepest leaf (root at 0)
  size_t bytes = 0;      ///< nodes, leaf ids, boxes and posed triangles
  double build_ms = 0;   ///< hierarchy build over the local coordinates
  double pose_ms = 0;    ///< latest pose: transforming the triangles and refitting the boxes
};

/// A mesh with its collision hierarchy. Triangles keep their index in the input mesh.
class CollisionMesh {
 public:
  /// Most references in one leaf of the hierarchy (small leaves suit overlap queries: a leaf
  /// pair costs the product of the two counts in exact tests).
  static constexpr int kMaxLeaf = 4;

  /// Builds the hierarchy over `mesh` and poses it with `pose`; throws Error when an index is
  /// out of range. Triangles with non-finite vertices are left out of the hierarchy.
  explicit CollisionMesh(const TriangleMesh& mesh, const Transform& pose = Transform());

  /// Moves the mesh: transforms the triangles (in double, the affine part of the matrix),
  /// reclassifies them and refits the hierarchy's boxes. O(n), no rebuild.
  void set_pose(const Transform& pose);

  /// Number of triangles (valid or not).
  size_t triangle_count() const { return world_.size(); }
  /// Triangle `id` in the current pose.
  const DTriangle& triangle(uint32_t id) const { return world_[id]; }
  /// True when triangle `id` is finite and not degenerate in the current pose.
  bool valid(uint32_t id) const { return valid_[id] != 0; }
  /// Number of valid triangles.
  size_t valid_count() const { return valid_count_; }
  /// Float box enclosing triangle `id` (rounded outward; empty for an invalid triangle).
  const Bounds3& triangle_box(uint32_t id) const { return boxes_[id]; }

  /// The hierarchy's nodes (BvhNode layout: root at 0, children in pairs); empty for a mesh
  /// without finite triangles.
  const BvhNodeArray& nodes() const { return nodes_; }
  /// Triangle ids in leaf order; a leaf covers leaf_ids()[index, index + count).
  const std::vector<uint32_t>& leaf_ids() const { return leaf_ids_; }
  /// Box of everything in the current pose (empty when no triangle is valid).
  Bounds3 bounds() const { return nodes_.empty() ? Bounds3() : nodes_[0].bounds(); }
  /// Size and timing of the hierarchy.
  const HierarchyStats& stats() const { return stats_; }

 private:
  std::vector<Vec3> local_;       ///< three vertices per triangle, as in the input
  std::vector<DTriangle> world_;  ///< posed triangles
  std::vector<Bounds3> boxes_;    ///< posed float boxes, rounded outward
  std::vector<uint8_t> valid_;    ///< posed triangle finite and not degenerate
  size_t valid_count_ = 0;
  BvhNodeArray nodes_;
  std::vector<uint32_t> leaf_ids_;
  HierarchyStats stats_;
};

/// The float box of a double box, rounded outward so that it encloses it.
Bounds3 round_outward(const DVec3& lo, const DVec3& hi);

}  // namespace penumbra::collision
