#pragma once
/// Counting the work of a ray query, for the cost view (`raycast:mode=cost`) and accel-bench's
/// nodes per ray. Each structure's traversal is a template over a counting policy: `NoCost` in the
/// normal queries, whose empty calls compile away, and `CostCounter` in intersect_cost.
#include <cstdint>

namespace penumbra {

/// The work one or more queries did.
struct TraversalCost {
  /// Node records visited: inner nodes whose children's boxes (or split plane) were tested, and
  /// leaves or cells whose primitives were looked at. What a node is depends on the structure (an
  /// 8-wide BVH node tests eight boxes at once, a grid cell has no box): compare the counts of
  /// one structure across a scene, and primitive tests across structures.
  uint64_t nodes = 0;
  /// Primitive intersection tests (a triangle block of k lanes counts k; a primitive skipped by
  /// a mailbox does not count).
  uint64_t prims = 0;

  TraversalCost& operator+=(const TraversalCost& o) {
    nodes += o.nodes, prims += o.prims;
    return *this;
  }
};

/// The policy of the normal queries: counts nothing.
struct NoCost {
  static constexpr bool kCounts = false;
  void node(uint64_t = 1) const {}
  void prims(uint64_t) const {}
};

/// The policy of intersect_cost: adds to a TraversalCost.
struct CostCounter {
  static constexpr bool kCounts = true;
  TraversalCost* cost;
  void node(uint64_t n = 1) const { cost->nodes += n; }
  void prims(uint64_t n) const { cost->prims += n; }
};

}  // namespace penumbra
