#pragma once
/// Making a wide BVH's nodes from the binary tree (WideBvh::build): the collapse into W-wide
/// nodes, greedy or as SahCollapse plans it (merging small subtrees into leaves where it says
/// so), the deduplication of pre-split leaves, and the wide tree's SAH cost.
#include <algorithm>
#include <cstdint>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "penumbra/accel/build/bvh_node.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/build/wide_collapse.h"
#include "penumbra/accel/wide_node.h"
#include "penumbra/core/array_allocator.h"
#include "penumbra/core/bounds.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/ray.h"

namespace penumbra::wide_build {

/// Sorts [first, last) by primitive id and keeps one reference of each; returns the new end.
inline PrimRef* unique_by_id(PrimRef* first, PrimRef* last) {
  std::sort(first, last, [](const PrimRef& a, const PrimRef& b) { return a.id < b.id; });
  return std::unique(first, last, [](const PrimRef& a, const PrimRef& b) { return a.id == b.id; });
}

/// The pieces of a pre-split triangle may share a leaf: keep one reference of each triangle
/// (sorted by id) so that it is tested once.
template <int W>
void dedupe_leaves(std::span<WideNode<W>> nodes, std::span<PrimRef> refs) {
  parallel_for_range(
      nodes.size(),
      [&](size_t begin, size_t end) {
        for (size_t n = begin; n < end; ++n)
          for (int i = 0; i < W; ++i) {
            const uint32_t count = nodes[n].count[i];
            if (count < 2) continue;
            PrimRef* first = refs.data() + nodes[n].child[i];
            nodes[n].count[i] = static_cast<uint32_t>(unique_by_id(first, first + count) - first);
          }
      },
      1024);
}

template <int W>
using WideNodeArray = std::vector<WideNode<W>, ArrayAllocator<WideNode<W>>>;

/// Collapses the binary tree into W-wide nodes: each wide node takes its binary node's two
/// children and, while it has fewer than W, opens the child with the largest surface area
/// (Wald, Benthin, Boulos 2008). Depth first, so a node's children follow it closely.
template <int W>
class Collapser {
 public:
  /// Collapses greedily, or as `plan` says when given; with `octant_slots`, children take the
  /// slots of the octant order (octant_slots()).
  Collapser(const BvhNodeArray& bin, WideNodeArray<W>& out, const SahCollapse* plan,
            bool octant_slots = false, PrimRefArray* refs = nullptr)
      : bin_(bin), out_(out), plan_(plan), octant_slots_(octant_slots), refs_(refs) {}

  /// Emits the wide node for binary inner node `b`; returns its index.
  uint32_t emit(uint32_t b, size_t depth) {
    uint32_t kids[W];
    const int n = gather(b, kids);
    const auto me = static_cast<uint32_t>(out_.size());
    out_.push_back(empty_node());
    int slot[W];
    for (int i = 0; i < W; ++i) slot[i] = i;
    if (octant_slots_) octant_slots(bin_[b].bounds(), kids, n, slot);
    for (int i = 0; i < n; ++i) {
      const BvhNode& k = bin_[kids[i]];
      uint32_t child = k.index, count = k.count;
      if (k.is_leaf() || (plan_ && plan_->merged(kids[i]))) {
        if (!k.is_leaf()) std::tie(child, count) = merge(kids[i]);
        ++leaves_;
        max_depth_ = std::max(max_depth_, depth + 1);
      } else {
        child = emit(kids[i], depth + 1);
      }
      WideNode<W>& node = out_[me];  // emit() may have reallocated
      float box[6];
      std::copy(k.box, k.box + 6, box);
      grow_box(box);  // for culling at cull_bound(hit.t) (hit.h)
      for (int r = 0; r < 6; ++r) node.box[r][slot[i]] = box[r];
      node.child[slot[i]] = child;
      node.count[slot[i]] = count;
    }
    return me;
  }

  /// A root node holding a single leaf (when the binary tree is one leaf).
  void emit_leaf_root(const BvhNode& leaf) {
    WideNode<W> node = empty_node();
    float box[6];
    std::copy(leaf.box, leaf.box + 6, box);
    grow_box(box);
    for (int r = 0; r < 6; ++r) node.box[r][0] = box[r];
    node.child[0] = leaf.index;
    node.count[0] = leaf.count;
    out_.push_back(node);
    leaves_ = 1, max_depth_ = 1;
  }

  /// A root node holding one leaf of all the references (plan_->merged(0)).
  void emit_merged_root() {
    BvhNode leaf = bin_[0];
    std::tie(leaf.index, leaf.count) = merge(0);
    emit_leaf_root(leaf);
  }

  /// Leaves and depth of what was emitted.
  size_t leaves() const { return leaves_; }
  size_t max_depth() const { return max_depth_; }

 private:
  /// The children of wide node `b`: its two binary children, then repeatedly the two children of
  /// the inner one with the largest surface area in place of it, up to W.
  int gather(uint32_t b, uint32_t (&kids)[W]) const {
    if (plan_) return plan_->children(b, kids);
    kids[0] = bin_[b].index, kids[1] = bin_[b].index + 1;
    int n = 2;
    while (n < W) {
      int open = -1;
      float largest = -1.0f;
      for (int i = 0; i < n; ++i) {
        const BvhNode& k = bin_[kids[i]];
        const float area = k.bounds().surface_area();
        if (!k.is_leaf() && area > largest) open = i, largest = area;
      }
      if (open < 0) break;
      const uint32_t first = bin_[kids[open]].index;
      kids[open] = first, kids[n++] = first + 1;
    }
    return n;
  }

  /// Slots for the octant order of the traversal: a ray whose direction has the signs of
  /// octant o (bit a set where component a is negative) visits slots in the order o, o ^ 1,
  /// o ^ 2, ..., so slot s should hold the child met first by rays of octant s: the one whose
  /// centre lies farthest back along that octant's diagonal. Pairs (child, slot) are taken in
  /// order of that cost, least first, each child and slot once (a greedy assignment, as the
  /// auction of Ylitie, Karras & Laine 2017, section 3.2, approximates the best one). Centres
  /// are taken relative to the centre of `parent`, the box of the node's binary subtree.
  void octant_slots(const Bounds3& parent, const uint32_t* kids, int n, int* slot) const {
    const Vec3 mid = (parent.lo + parent.hi) * 0.5f;
    float cost[W][W];
    for (int i = 0; i < n; ++i) {
      const Bounds3 b = bin_[kids[i]].bounds();
      const Vec3 c = (b.lo + b.hi) * 0.5f - mid;
      for (int s = 0; s < W; ++s)
        cost[i][s] = ((s & 1) ? -c.x : c.x) + ((s & 2) ? -c.y : c.y) + ((s & 4) ? -c.z : c.z);
    }
    unsigned child_free = (1u << n) - 1, slot_free = (1u << W) - 1;
    for (int k = 0; k < n; ++k) {
      int bi = -1, bs = -1;
      for (int i = 0; i < n; ++i) {
        if (!(child_free >> i & 1)) continue;
        for (int s = 0; s < W; ++s)
          if ((slot_free >> s & 1) && (bi < 0 || cost[i][s] < cost[bi][bs])) bi = i, bs = s;
      }
      slot[bi] = bs;
      child_free &= ~(1u << bi), slot_free &= ~(1u << bs);
    }
  }

  /// The references of binary inner node `b`'s leaves made one leaf, appended to the references
  /// (treelet restructuring leaves a subtree's leaves anywhere in them), each primitive once
  /// (spatial splits may have put parts of one in two of the leaves), in id order. Returns
  /// (first, count).
  std::pair<uint32_t, uint32_t> merge(uint32_t b) {
    const auto first = static_cast<uint32_t>(refs_->size());
    uint32_t stack[64];
    int sp = 0;
    stack[sp++] = b;
    while (sp > 0) {
      const BvhNode& n = bin_[stack[--sp]];
      if (!n.is_leaf()) {
        stack[sp++] = n.index, stack[sp++] = n.index + 1;
        continue;
      }
      for (uint32_t i = n.index; i < n.index + n.count; ++i) refs_->push_back((*refs_)[i]);
    }
    PrimRef* const begin = refs_->data() + first;
    refs_->resize(size_t(unique_by_id(begin, refs_->data() + refs_->size()) - refs_->data()));
    return {first, static_cast<uint32_t>(refs_->size() - first)};
  }

  static WideNode<W> empty_node() {
    WideNode<W> n;
    for (int i = 0; i < W; ++i) {
      for (int a = 0; a < 3; ++a) n.box[2 * a][i] = kInfinity, n.box[2 * a + 1][i] = -kInfinity;
      n.child[i] = 0, n.count[i] = 0;
    }
    return n;
  }

  const BvhNodeArray& bin_;
  WideNodeArray<W>& out_;
  const SahCollapse* plan_;
  bool octant_slots_;
  PrimRefArray* refs_;  ///< the binary tree's references (merge() appends to them)
  size_t leaves_ = 0, max_depth_ = 0;
};

/// SAH cost of a wide tree relative to its root's area: `node_cost` per node times its box's
/// area, plus each leaf's area times its tests (2^block_shift primitives per test).
template <int W>
double wide_sah_cost(const WideNodeArray<W>& nodes, float node_cost, int block_shift) {
  if (nodes.empty()) return 0.0;
  double total = 0.0;
  Bounds3 root;
  for (size_t n = 0; n < nodes.size(); ++n) {
    const WideNode<W>& w = nodes[n];
    for (int i = 0; i < W; ++i) {
      if (!(w.box[0][i] <= w.box[1][i])) continue;  // an empty slot
      const Bounds3 b{{w.box[0][i], w.box[2][i], w.box[4][i]},
                      {w.box[1][i], w.box[3][i], w.box[5][i]}};
      if (n == 0) root.extend(b);
      const double area = b.surface_area();
      total += w.count[i] ? area * double(((w.count[i] - 1) >> block_shift) + 1)
                          : area * double(node_cost);
    }
  }
  const double root_area = root.surface_area();
  return root_area > 0 ? total / root_area + node_cost : 0.0;
}

}  // namespace penumbra::wide_build
