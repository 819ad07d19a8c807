#pragma once
/// 2DBSP and 2DRANDOMBSP: the binary space partition of disjoint segments by auto-partition, as
/// de Berg, Cheong, van Kreveld and Overmars define it ("Computational Geometry: Algorithms and
/// Applications", 3rd ed. 2008, ch. 12; Paterson and Yao 1990, "Efficient binary space partitions
/// for hidden-surface removal and solid modeling"). A node splits by ℓ(s), the line through its
/// first segment; segments cut by ℓ(s) become fragments on both sides; fragments contained in ℓ(s)
/// are stored at the node; a leaf holds at most one fragment.
#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/accel2d/accel2d.h"
#include "penumbra/accel2d/line_tree.h"
#include "penumbra/core/params.h"

namespace penumbra::lab2d {

/// How a node picks its splitting segment.
enum class BspOrder {
  kRandom,     ///< 2DRANDOMBSP: the first fragment of a seeded random permutation
  kFirst,      ///< the first fragment in input order
  kFewestCuts  ///< the fragment whose line cuts the fewest others in the cell
};

/// The part t ∈ [t0, t1] of segment `seg` (parameters of Segment2::at, so a fragment's ends are
/// computed from the original segment and neighbouring fragments share their end exactly).
struct Fragment {
  uint32_t seg = 0;
  double t0 = 0, t1 = 1;
};

/// The BSP of segments. Parameters: order=random|first|fewest-cuts (random), seed=1.
class SegmentBsp final : public Accel2D {
 public:
  /// Reads `order` and `seed` from p (rejecting others).
  explicit SegmentBsp(const ParamList& p);
  /// A tree with the given order and seed.
  SegmentBsp(BspOrder order, uint64_t seed) : order_(order), seed_(seed) {}

  std::string name() const override;
  void build(const Scene2D& scene) override;
  Hit2 shoot(const Ray2& ray, TraceLog* trace = nullptr) const override;
  Stats2D stats() const override;
  Drawing2D draw(const Box2d& frame) const override;

  /// The tree: nodes (root first) and the segment ids their ranges index.
  const LineTree& tree() const { return tree_; }
  /// The fragments, parallel to tree().refs.
  const std::vector<Fragment>& fragments() const { return frags_; }
  /// The input segments.
  const std::vector<Segment2>& segments() const { return segs_; }
  /// The tolerance used by build and traversal.
  double eps() const { return eps_; }

 private:
  /// Index (within [begin, end) of work) of the fragment a node splits by.
  size_t pick_splitter(const std::vector<Fragment>& work, size_t begin, size_t end) const;
  /// How many fragments of [begin, end) the line of fragment `k` cuts.
  size_t cuts_of(const std::vector<Fragment>& work, size_t begin, size_t end, size_t k) const;

  BspOrder order_ = BspOrder::kRandom;
  uint64_t seed_ = 1;
  double eps_ = 0;
  std::vector<Segment2> segs_;
  LineTree tree_;
  std::vector<Fragment> frags_;
  double build_ms_ = 0;
};

/// The order named by text ("random", "first", "fewest-cuts"); throws Error listing them.
BspOrder parse_bsp_order(const std::string& text);
/// The name of an order.
const char* to_string(BspOrder order);

}  // namespace penumbra::lab2d
