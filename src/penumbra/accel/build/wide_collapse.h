#pragma once
/// The SAH-optimal collapse of a binary BVH into a wide one (Ylitie, Karras & Laine 2017,
/// "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", section 3.1): by
/// dynamic programming over the binary tree, the wide tree of least SAH cost among those whose
/// nodes gather binary subtrees, instead of greedily opening the child of largest area. Binary
/// leaves stay leaves, so the leaves (and their triangle blocks) are the binary build's.
#include <cstdint>
#include <vector>

#include "penumbra/accel/build/bvh_node.h"

namespace penumbra {

/// Cost model: a wide node costs `node_cost` times its area, a leaf its area times its tests
/// (⌈count / 2^block_shift⌉ blocks); the total is divided by the root's area.
class SahCollapse {
 public:
  static constexpr int kMaxWidth = 16;

  /// Plans the collapse of `bin` (root at 0, an inner node) into nodes of at most `width` (2..16)
  /// children. With `max_leaf` > 0, a binary inner node whose subtree holds at most that many
  /// references may also become one leaf of them all (merged(); the root too, then the wide
  /// tree's one leaf).
  SahCollapse(const BvhNodeArray& bin, int width, float node_cost, int block_shift,
              uint32_t max_leaf = 0);

  /// The children of the wide node made for binary inner node `b`; returns their number.
  int children(uint32_t b, uint32_t* kids) const;

  /// True where binary inner node `b` (a child slot of a planned wide node, or the root) is to
  /// be one leaf of its subtree's references.
  bool merged(uint32_t b) const { return !bin_[b].is_leaf() && choice_[row(b)] == kMerge; }

  /// SAH cost of the planned wide tree, relative to the root's area.
  double cost() const;

 private:
  /// Tables of at least this many rows fill their top `kParallelDepth` levels' subtrees as
  /// parallel tasks.
  static constexpr uint32_t kParallelRows = 1 << 16;
  static constexpr int kParallelDepth = 10;

  /// Fills the table for the subtree of binary node `b`; its first `parallel_depth` levels split
  /// into parallel tasks.
  void plan(uint32_t b, int parallel_depth);
  /// The least cost of inner node `b`'s two children sharing `j` slots; `best_k` gets the left
  /// child's share.
  float distribute(uint32_t b, int j, int& best_k) const;
  /// Appends the slots of `b`'s subtree as at most `i` slots to kids[n...].
  void expand(uint32_t b, int i, uint32_t* kids, int& n) const;
  /// Row of binary node `b` (reachable nodes only are numbered).
  size_t row(uint32_t b) const { return size_t(dense_[b]) * width_; }

  /// choice_ of a binary inner node made one leaf (one slot: the low nibble is 0).
  static constexpr uint8_t kMerge = 0x10;

  const BvhNodeArray& bin_;
  int width_, block_shift_;
  float node_cost_;
  uint32_t max_leaf_;
  // The tables take tens of megabytes on a million triangles: in huge pages (ArrayAllocator),
  // whose first touch costs a tenth of that of ordinary pages on the virtual machines measured,
  // and not zeroed first (every entry read is written before: those of reachable nodes).
  template <class T>
  using Table = std::vector<T, NoInitArrayAllocator<T>>;
  Table<uint32_t> dense_;  ///< binary node -> row
  /// cost_[row + i - 1]: the least cost of the subtree as at most i slots of a wide node (i in
  /// 1..width). choice_ says how: low nibble `split` = 0 for one slot (the node itself: a leaf,
  /// an inner node that becomes a wide node, or with kMerge one that becomes a leaf), else the
  /// left child takes `split` of `used` (high nibble: used - 1, so that 16 fits) slots and the
  /// right one the rest.
  Table<float> cost_;
  Table<uint8_t> choice_;
  Table<uint32_t> refs_;  ///< references in the subtree of each row (when merging)
  float root_cost_ = 0;
};

}  // namespace penumbra
