#pragma once
/// `bvh` (16-wide on AVX targets, 4-wide elsewhere: registry.cpp) and `bvh4`: wide BVHs with
/// 4, 8 or 16 children per node, made by collapsing the binary binned-SAH BVH (Dammertz, Hanika,
/// Keller 2008, "Shallow Bounding Volume Hierarchies for Fast SIMD Ray Tracing of Incoherent
/// Rays"; Wald, Benthin, Boulos 2008, "Getting Rid of Packets"; Fuetterling et al. 2017,
/// "Accelerated Single Ray Tracing for Wide Vector Units", for 16). A node holds its children's
/// boxes in structure-of-arrays form, so one SIMD slab test covers all of them (SSE for 4, AVX
/// for 8, two AVX registers for 16); a ray reaches a leaf in half (a third, a quarter) of the
/// binary tree's dependent node fetches. Children are visited nearest first.
///
/// Parameters: leaf=N, the largest leaf (default 8; 16 for width 16), bins=N (default 16; 32 for
/// width 16), trav=X (default 2), exact=N|auto (nodes of up to N references split by the exact
/// SAH, bvh_sweep.h; auto, the default: 64 where binleaf merges, else 0); collapse=sah|greedy (the
/// SAH-optimal collapse of build/wide_collapse.h, the default, or largest-area opening);
/// binleaf=N|auto (with collapse=sah and N below leaf, the binary build stops at leaves of N and
/// the collapse may merge a subtree of up to `leaf` references into one leaf where the SAH says so;
/// 0: no merging; auto, the default: 8 for width 16 over sets of up to 2^16 primitives, no merging
/// otherwise); optimize=N|auto (passes of treelet restructuring over the binary tree before the
/// collapse, build/treelet_opt.h; auto, the default: one for sets of up to 2^18 primitives, none
/// above); interleave=auto|on|off (whether batch queries, intersect_batch and occluded_batch,
/// alternate between 8 rays' traversals a node at a time, so that each ray's next node loads while
/// the others work; auto: when the structure exceeds 16 MiB, where the loads miss the caches); the
/// 8-wide one also nodes=full|compressed (the node layout) and order=distance|octant (how
/// closest-hit rays order the children they visit); anyhit=auto|span|lanes (which inner child an
/// any-hit ray visits first when no leaf is hit: the longest span through its box, or the lowest
/// lane; auto: span on Intel CPUs and CPUs with AVX-512, lanes on others, chosen when the
/// program runs); prefetch=auto|whole|line (whether a child about to be visited starts loading
/// whole or its first line; auto: whole when the structure exceeds 1 MiB).
#include <string>
#include <vector>

#include "penumbra/accel/accelerator.h"
#include "penumbra/accel/build/bvh_builder.h"
#include "penumbra/accel/leaf_prims.h"
#include "penumbra/accel/prefetch.h"
#include "penumbra/accel/triangle_blocks.h"
#include "penumbra/accel/wide_node.h"
#include "penumbra/core/array_allocator.h"
#include "penumbra/core/params.h"

namespace penumbra {

template <int W>
struct WideBoxRay;

/// Wide BVH of width W (4, 8 or 16) with nodes of type Node (WideNode<W>, or CompressedNode for 8).
template <int W, class Node = WideNode<W>>
class WideBvh final : public Accelerator {
 public:
  /// Reads the binary build's parameters; throws Error on bad values.
  explicit WideBvh(const ParamList& params);
  std::string name() const override { return name_; }
  void build(const PrimitiveSet& prims) override;
  bool intersect(const Ray& ray, Hit& hit) const override;
  bool occluded(const Ray& ray) const override;
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const override;
  AccelStats stats() const override { return stats_; }
  /// Incoherent batches with interleaving on alternate between their rays' traversals, a node
  /// at a time (interleave()); the others go one ray at a time.
  void intersect_batch(std::span<const Ray> rays, std::span<Hit> hits,
                       BatchOrder order) const override;
  void occluded_batch(std::span<const Ray> rays, std::span<uint8_t> out,
                      BatchOrder order) const override;

  /// The nodes, root first.
  std::span<const Node> nodes() const { return {nodes_.data(), nodes_.size()}; }

 private:
  /// kOctant: closest-hit rays visit children in the octant order (order=octant).
  template <bool kAnyHit, bool kTriangles, bool kOctant = false, class Cost = NoCost>
  bool traverse(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;
  /// Traversal stack entries: kBvhStackSize levels of W - 1 deferred children, and W more.
  static constexpr int kStackSize = kBvhStackSize * (W - 1) + W;
  struct StackEntry {  ///< a deferred child: its (child, count) payload and entry distance
    uint32_t child, count;
    float t;
  };
  struct Walk;
  /// One node or leaf of an interleaved ray's traversal `w` (distance order); true when its
  /// query is done (w.found: a hit).
  template <bool kAnyHit, bool kTriangles>
  bool step(const Node* nodes, const WideBoxRay<W>& b, const PreparedRay& pr, Hit& hit,
            Walk& w) const;
  /// The batch queries' rays in flight at once (8 measured best: 4 and 16 slower on the terrain
  /// and spheres-1m).
  static constexpr int kInterleave = 8;
  /// A batch through interleave() or one ray at a time; kAnyHit: into `blocked`.
  template <bool kAnyHit>
  void batch(std::span<const Ray> rays, std::span<Hit> hits, std::span<uint8_t> blocked,
             BatchOrder order) const;
  /// The rays of a batch traversed kInterleave at a time, a step of each in turn.
  template <bool kAnyHit, bool kTriangles>
  void interleave(std::span<const Ray> rays, std::span<Hit> hits, std::span<uint8_t> blocked) const;
  /// Closest hit of `pr` in the order the tree was built for.
  template <class Cost = NoCost>
  bool closest(const PreparedRay& pr, Hit& hit, Cost cost = {}) const;

  /// Moves the leaves' triangles into blocks and points the leaf children of `nodes` at them.
  void make_blocks(std::span<WideNode<W>> nodes, const PrimitiveSet& prims,
                   std::span<const PrimRef> refs);

  std::string name_;
  BvhBuildParams params_;
  bool sah_collapse_ = true;  ///< collapse=sah (default): the SAH-optimal collapse, else greedy
  double presplit_ = 0;        ///< presplit=F: extra references for large triangles (presplit.h)
  bool bins_given_ = false;    ///< bins=N given (else the 16-wide tree uses 32)
  int exact_below_ = -1;       ///< exact=N given (else auto: 64 where leaves merge, else 0)
  /// binleaf=N: the binary build's leaf size when the collapse merges (0: none); -1: auto
  int bin_leaf_ = -1;
  int optimize_ = -1;  ///< optimize=N: treelet restructuring passes (treelet_opt.h); -1: auto
  /// order=octant: closest-hit rays visit the children a node's test keeps in the order of the
  /// ray's octant (slots laid out for it by the collapse) instead of by entry distance.
  bool octant_order_ = false;
  /// anyhit=span: an any-hit ray with no leaf among the children a node's test keeps visits
  /// the one its box crosses longest first; anyhit=lanes: the lowest lane (auto: by the CPU).
  bool any_hit_span_ = false;
  /// interleave=on|off|auto (1, 0, -1): batch queries interleave their rays; auto: when the
  /// structure takes more than kInterleaveBytes, beyond what the caches hold.
  int interleave_mode_ = -1;
  bool interleave_ = false;  ///< the build's outcome of interleave_mode_
  static constexpr size_t kInterleaveBytes = size_t(16) << 20;
  /// prefetch=whole|line|auto (1, 0, -1): a child's prefetch loads all of a node's or a leaf's
  /// lines, or the first; auto: all when the structure takes more than kPrefetchWholeBytes (the
  /// Zen 4's L2), where its lines come from beyond the L2.
  int prefetch_mode_ = -1;
  bool prefetch_whole_ = false;  ///< the build's outcome of prefetch_mode_
  static constexpr size_t kPrefetchWholeBytes = size_t(1) << 20;
  /// Starts loading node `n`: all its lines, or with prefetch=line the first.
  void prefetch_node(const Node* n) const {
    if (prefetch_whole_)
      prefetch_bytes<int(sizeof(Node) / kCacheLine)>(n, sizeof(Node));
    else
      prefetch_line(n);
  }
  /// Starts loading the leaf of `count` triangles at block `first`: all its blocks, or the first
  /// line.
  void prefetch_leaf(uint32_t first, uint32_t count) const {
    if (prefetch_whole_)
      blocks_.prefetch(first, count);
    else
      prefetch_line(blocks_.block(first));
  }
  /// Starts loading the child (`c`, `count`) of a node in `nodes`: a leaf of triangle blocks
  /// (kTriangles and count > 0) or an inner node (count 0); a leaf of other primitives is not
  /// prefetched.
  template <bool kTriangles>
  void prefetch_child(const Node* nodes, uint32_t c, uint32_t count) const {
    if (count == 0)
      prefetch_node(&nodes[c]);
    else if constexpr (kTriangles)
      prefetch_leaf(c, count);
  }
  const PrimitiveSet* prims_ = nullptr;
  std::vector<Node, ArrayAllocator<Node>> nodes_;
  LeafPrims leaf_;         ///< leaf order ids, when not every primitive is a triangle
  TriangleBlocks blocks_;  ///< the leaves' triangles, when every primitive is one
  AccelStats stats_;
};

extern template class WideBvh<4>;
extern template class WideBvh<8>;
extern template class WideBvh<8, CompressedNode>;
extern template class WideBvh<16>;

}  // namespace penumbra
