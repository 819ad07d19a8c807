#pragma once
/// `octree`: recursive subdivision of a cube into eight equal children (Glassner 1984, "Space
/// Subdivision for Fast Ray Tracing"), traversed front to back with the parametric child order of
/// Revelles, Ureña, Lastra 2000, "An Efficient Parametric Algorithm for Octree Traversal".
///
/// The root is the scene box made cubic, 1% larger and offset irregularly (so split planes miss
/// the round coordinates CAD models are centred on). A node holding more than `leaf` primitives
/// is split into its eight octants; a primitive goes to every octant it really overlaps (exact
/// tests of build/prim_box_overlap.h). Nodes are laid out breadth first, the eight children of
/// a node consecutive. Subdivision stops at `depth`, and where splitting does not pay (the rules
/// are in OctreeBuilder::split, octree.cpp):
///   - no separation: two or more octants would each receive every primitive of the node (many
///     primitives through one point, along one line, or overlapping in one plane);
///   - a fan: one octant receives them all and at least half of them reach a sibling too (the
///     triangles around a vertex of higher valence than `leaf`, which would otherwise be zoomed
///     in on down to `depth`, copying the fan at every level);
///   - no expected gain by the surface area heuristic: trav + sum(n_octant) / 4 >= n;
///   - a level that would take the references past kOctreeMaxRefsPerPrim per primitive (memory
///   stays
///     linear in N whatever the geometry).
///
/// Parameters (`octree:leaf=16,depth=16`):
///   leaf=N     most primitives in a leaf before it is split, 1..1024 (default 16)
///   depth=N    deepest level, 1..kMaxOctreeDepth (default 16)
///   trav=X     cost of an inner node step relative to a primitive test, 0..1000 (default 1)
///   mailbox=N  per-ray mailbox slots, 0 (off), 8, 16, 32 or 64 (default 16)
///   copy=0|1   triangle-only scenes: copy the vertices into leaf order (default 1; skipped above
///              8 references per primitive)
#include <span>
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/core/array_allocator.h"
#include "penumbra/core/params.h"

namespace penumbra {

/// Deepest level the octree may reach (the traversal stack is sized for it).
inline constexpr int kMaxOctreeDepth = 20;
/// Reference budget: a level whose splits would take the references past this many per
/// primitive is not split (pathological geometry only; real scenes stay far below).
inline constexpr double kOctreeMaxRefsPerPrim = 64.0;

/// An octree node in 8 bytes. Inner node: `index` is the first of its eight children, stored
/// consecutively and ordered by octant (bit 0: upper x half, bit 1: upper y, bit 2: upper z);
/// `info` holds kInner and the mask of non-empty children. Leaf: `index` is its first primitive
/// in the flat id array and `info` the count.
struct OctreeNode {
  static constexpr uint32_t kInner = 0x80000000u;  ///< flag of an inner node in `info`
  uint32_t index;  ///< inner: first child; leaf: first primitive in the id array
  uint32_t info;   ///< inner: kInner | child mask; leaf: primitive count

  /// True for an inner node.
  bool inner() const { return (info & kInner) != 0; }
  /// Inner node: bit c set when child c holds any primitive.
  unsigned child_mask() const { return info & 0xffu; }
  /// Leaf: number of primitives.
  uint32_t count() const { return info; }
};

/// Octree over any primitive set.
class Octree final : public Accelerator {
 public:
  /// Reads leaf, depth, trav, mailbox and copy from `params` (see the file comment); throws
  /// Error on bad values.
  explicit Octree(const ParamList& params);
  std::string name() const override { return name_; }
  void build(const PrimitiveSet& prims) override;
  bool intersect(const Ray& ray, Hit& hit) const override;
  bool occluded(const Ray& ray) const override;
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const override;
  AccelStats stats() const override { return stats_; }

  /// The nodes, root at 0 (empty when nothing was built).
  std::span<const OctreeNode> nodes() const { return nodes_; }
  /// Primitive ids of the leaves.
  std::span<const uint32_t> leaf_ids() const { return ids_; }
  /// The root cube.
  Bounds3 root_bounds() const { return {root_lo_, root_lo_ + Vec3(half_[0] * 2.0f)}; }
  /// Lower corner of child `c` (octant bits as in OctreeNode) of a node at `depth` with lower
  /// corner `lo`: exactly the value the traversal computes.
  Vec3 child_lo(Vec3 lo, int depth, unsigned c) const;
  /// Edge length of the nodes at `depth`.
  float size_at(int depth) const { return half_[depth] * 2.0f; }

 private:
  template <bool kAnyHit, bool kTriangles, int kMailbox, class Cost = NoCost>
  bool traverse(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;
  template <bool kAnyHit, class Cost = NoCost>
  bool dispatch(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;

  std::string name_;
  int leaf_size_ = 16;
  int max_depth_ = 16;
  double trav_cost_ = 1.0;
  bool copy_ = true;
  int mailbox_ = 16;
  const PrimitiveSet* prims_ = nullptr;
  Vec3 root_lo_;
  float half_[kMaxOctreeDepth + 1] = {};  ///< half the edge length at each depth
  std::vector<OctreeNode, ArrayAllocator<OctreeNode>> nodes_;
  std::vector<uint32_t, ArrayAllocator<uint32_t>> ids_;
  /// Triangle-only sets: three vertices per leaf slot, or empty.
  std::vector<Vec3, ArrayAllocator<Vec3>> tris_;
  float max_extent_ = 0;  ///< the largest extent of a primitive box (cull_slack, hit.h)
  AccelStats stats_;
};

}  // namespace penumbra
