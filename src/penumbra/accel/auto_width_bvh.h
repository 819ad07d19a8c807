#pragma once
/// `bvh` with width=auto (the default): the 8-wide BVH, or, on targets with AVX-512, the 16-wide
/// one for sets of more than kWide16Above primitives. A 16-wide node takes one 512-bit box test
/// and eight cache lines, and a ray reaches a leaf through fewer of them: fewer dependent node
/// fetches, which is what a ray through a structure larger than the caches waits on. Where the
/// nodes stay in the caches, the wider node's dearer test and ordering cost more than the levels
/// save (Fuetterling et al. 2017, "Accelerated Single Ray Tracing for Wide Vector Units", make the
/// case for 16-wide nodes on AVX-512; docs/accel.md gives the measurements behind the choice).
///
/// Parameters: those of WideBvh (wide_bvh.h); the choice is made when build() sees the set's size
/// and reported in the stats ("width").
#include <cstddef>
#include <string>

#include "penumbra/accel/accelerator.h"
#include "penumbra/accel/wide_bvh.h"
#include "penumbra/core/params.h"

namespace penumbra {

class AutoWidthBvh final : public Accelerator {
 public:
  /// Sets of more than this many primitives get 16-wide nodes where the target has AVX-512.
  static constexpr size_t kWide16Above = size_t(1) << 17;

  /// Reads WideBvh's parameters (for both widths); throws Error on bad values.
  explicit AutoWidthBvh(const ParamList& params);
  std::string name() const override { return narrow_.name(); }
  void build(const PrimitiveSet& prims) override;
  // The calls go to final classes: direct, not virtual.
  bool intersect(const Ray& ray, Hit& hit) const override {
    return wide_ ? wider_.intersect(ray, hit) : narrow_.intersect(ray, hit);
  }
  bool occluded(const Ray& ray) const override {
    return wide_ ? wider_.occluded(ray) : narrow_.occluded(ray);
  }
  void intersect_batch(std::span<const Ray> rays, std::span<Hit> hits,
                       BatchOrder order) const override {
    wide_ ? wider_.intersect_batch(rays, hits, order) : narrow_.intersect_batch(rays, hits, order);
  }
  void occluded_batch(std::span<const Ray> rays, std::span<uint8_t> out,
                      BatchOrder order) const override {
    wide_ ? wider_.occluded_batch(rays, out, order) : narrow_.occluded_batch(rays, out, order);
  }
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override {
    return wide_ ? wider_.intersect_cost(ray, hit, cost) : narrow_.intersect_cost(ray, hit, cost);
  }
  AccelStats stats() const override { return stats_; }

  /// The width the last build chose (8 or 16), and the two structures (one of them unbuilt).
  int width() const { return wide_ ? 16 : 8; }
  const WideBvh<8>& narrow() const { return narrow_; }
  const WideBvh<16>& wider() const { return wider_; }
  /// The width build() chooses for a set of `prims` primitives on this target.
  static int width_for(size_t prims);

 private:
  ParamList params_;
  WideBvh<8> narrow_;  ///< the tree when width() is 8, else unbuilt
  WideBvh<16> wider_;  ///< the tree when width() is 16, else unbuilt
  bool wide_ = false;  ///< the last build made wider_
  AccelStats stats_;
};

}  // namespace penumbra
