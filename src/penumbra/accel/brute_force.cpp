#include "penumbra/accel/brute_force.h"

#include "penumbra/core/timer.h"

namespace penumbra {

BruteForce::BruteForce(const ParamList& params) : name_(params.to_string()) {
  params.check_all_used();
}

void BruteForce::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  valid_.clear();
  for (uint32_t i = 0; i < prims.size(); ++i)
    if (!prims.prim_bounds(i).empty()) valid_.push_back(i);
  stats_ = {};
  stats_.nodes = stats_.leaves = 1;
  stats_.prim_refs = valid_.size();
  stats_.bytes = valid_.capacity() * sizeof(uint32_t);
  stats_.build_ms = timer.elapsed_ms();
}

bool BruteForce::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  const PreparedRay pr(ray);
  for (uint32_t id : valid_) prims_->intersect(id, pr, hit);
  return hit.valid();
}

bool BruteForce::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  const PreparedRay pr(ray);
  cost.nodes += 1;  // the one "leaf": every primitive
  cost.prims += valid_.size();
  for (uint32_t id : valid_) prims_->intersect(id, pr, hit);
  return hit.valid();
}

bool BruteForce::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray)) return false;
  const PreparedRay pr(ray);
  cost.nodes += 1;  // the one "leaf", tested up to the first primitive in the way
  for (uint32_t id : valid_) {
    cost.prims += 1;
    if (prims_->occludes(id, pr)) return true;
  }
  return false;
}

bool BruteForce::occluded(const Ray& ray) const {
  if (!traceable(ray)) return false;
  const PreparedRay pr(ray);
  for (uint32_t id : valid_)
    if (prims_->occludes(id, pr)) return true;
  return false;
}

}  // namespace penumbra
