#pragma once
/// The kd-tree's 8-byte node, its build settings, and the flat arrays a builder produces
/// (layout of Pharr, Jakob, Humphreys, "Physically Based Rendering", 3rd ed., section 4.4.1).
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/core/bounds.h"

namespace penumbra {

/// Deepest level a kd-tree may have (root at 0); the traversal stack holds one entry per level.
inline constexpr int kKdMaxDepth = 64;

/// One kd-tree node in 8 bytes. Inner: the split position, the axis (0..2) in the low two bits
/// of `bits_` and the index of the child above the plane in the upper 30; the child below is
/// the next node. Leaf: the index of its first reference in the reference array, 3 in the low
/// bits and the reference count in the upper 30. KdTree stores its nodes with the children that
/// are empty leaves marked (the top two bits, which leaves 28 for the index) and left out of
/// the array: there, the next node of an inner node whose below child is empty is its above
/// child (see KdTree::build).
class KdNode {
 public:
  /// An inner node splitting `axis` at `split`, whose above child is node `above`. A split at
  /// -0 is stored as +0 (the same plane), as the traversal compares origins and splits by
  /// their bits.
  static KdNode inner(int axis, float split, uint32_t above) {
    return KdNode(std::bit_cast<uint32_t>(split + 0.0f), (above << 2) | uint32_t(axis));
  }
  /// A leaf holding references [first, first + count).
  static KdNode leaf(uint32_t first, uint32_t count) { return KdNode(first, (count << 2) | 3u); }

  bool is_leaf() const { return (bits_ & 3u) == 3u; }
  /// Split axis of an inner node.
  int axis() const { return int(bits_ & 3u); }
  /// The word holding the axis in its low two bits (and above() and the marks above them), for
  /// a traversal that picks a per-axis bit by shifting with it (kdtree.cpp, swap_by_axis).
  uint32_t axis_word() const { return bits_; }
  /// Split position of an inner node.
  float split() const { return std::bit_cast<float>(word_); }
  /// Index of the child above the plane (inner nodes; the one below is this index + 1).
  uint32_t above() const { return (bits_ & kIndexMask) >> 2; }
  /// Which children are empty leaves (bit 0: below, bit 1: above), once marked.
  uint32_t empty_children() const { return bits_ >> 30; }
  /// The same inner node with its children marked as empty leaves (`mask` as
  /// empty_children()); its above() must be below 2^28.
  KdNode with_empty_children(uint32_t mask) const {
    return KdNode(word_, (bits_ & kIndexMask) | (mask << 30));
  }
  /// First reference of a leaf.
  uint32_t first() const { return word_; }
  /// Number of references of a leaf.
  uint32_t count() const { return bits_ >> 2; }
  /// The same node with child and reference indices moved by (node_base, ref_base).
  KdNode shifted(uint32_t node_base, uint32_t ref_base) const {
    return is_leaf() ? KdNode(word_ + ref_base, bits_) : KdNode(word_, bits_ + (node_base << 2));
  }

 private:
  KdNode(uint32_t word, uint32_t bits) : word_(word), bits_(bits) {}
  /// Axis and above index of an inner node (the top two bits mark empty children).
  static constexpr uint32_t kIndexMask = (1u << 30) - 1;
  uint32_t word_;
  uint32_t bits_;
};
static_assert(sizeof(KdNode) == 8);

/// Largest node index or leaf count the 30-bit fields hold.
inline constexpr uint32_t kKdMaxIndex = (1u << 30) - 1;

/// How split planes are chosen.
enum class KdCriterion { kSah, kMedian, kGap };

/// Settings of a kd-tree build.
struct KdBuildParams {
  KdCriterion criterion = KdCriterion::kSah;
  float traversal_cost = 1.0f;  ///< ct: cost of an inner node
  float intersect_cost = 0.4f;  ///< ci: cost of one leaf test (a block or a primitive), vs ct
  float empty_bonus = 0.1f;     ///< the cost of a split with an empty side is scaled by 1 - this
  int max_leaf = 0;             ///< nodes with at most this many references become leaves
  int max_depth = 0;            ///< deepest level; 0 = round(8 + 1.3 log2 N) (pbrt)
  bool clip = true;             ///< clip straddling primitives to the children ("perfect splits")
  /// Leaves are tested 2^block_shift primitives at a time (SIMD blocks): the SAH counts blocks.
  int block_shift = 0;
  size_t parallel_min = 16384;  ///< nodes with more references build their children as tasks
};

/// The depth limit for `n` primitives: `params.max_depth`, or round(8 + 1.3 log2 n) when 0,
/// at most kKdMaxDepth.
int kd_depth_limit(const KdBuildParams& params, size_t n);

/// A chosen split plane; axis < 0 means "make a leaf".
struct KdPlane {
  int axis = -1;
  float pos = 0.0f;
};

/// One primitive reference during the build: the part of its box inside the current node.
struct KdPrim {
  Bounds3 box;
  uint32_t id;
};

/// A built subtree in depth-first order: the below child follows its parent, node and reference
/// indices relative to the start of these arrays.
struct KdSubtree {
  std::vector<KdNode> nodes;
  std::vector<uint32_t> refs;  ///< primitive ids; leaves index into this
  size_t leaves = 0;           ///< all leaves
  size_t empty_leaves = 0;     ///< leaves without references
  size_t max_depth = 0;        ///< deepest leaf (absolute depth in the whole tree)

  /// Appends a leaf over the references `prims` at `depth`.
  void add_leaf(const std::vector<KdPrim>& prims, int depth);
  /// Appends `other` (built separately), moving its indices past what is here.
  void append(const KdSubtree& other);
};

}  // namespace penumbra
