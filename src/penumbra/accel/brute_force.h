#pragma once
/// `brute`: tests every primitive for every ray. The reference the other structures are checked
/// against; O(N) per ray.
#include "penumbra/accel/accelerator.h"
#include "penumbra/core/params.h"

namespace penumbra {

/// Brute-force "structure": no parameters of its own (`isa=` is every structure's: registry.h).
class BruteForce final : public Accelerator {
 public:
  explicit BruteForce(const ParamList& params);
  std::string name() const override { return name_; }
  void build(const PrimitiveSet& prims) override;
  bool intersect(const Ray& ray, Hit& hit) const override;
  bool occluded(const Ray& ray) const override;
  bool intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const override;
  bool occluded_cost(const Ray& ray, TraversalCost& cost) const override;
  AccelStats stats() const override { return stats_; }

 private:
  std::string name_;
  const PrimitiveSet* prims_ = nullptr;
  std::vector<uint32_t> valid_;  ///< ids of primitives with finite bounds
  AccelStats stats_;
};

}  // namespace penumbra
