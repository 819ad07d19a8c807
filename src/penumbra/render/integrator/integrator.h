#pragma once
/// Integrators estimate the radiance arriving along a camera ray.
#include <string>

#include "penumbra/core/color.h"
#include "penumbra/core/ray.h"
#include "penumbra/render/sampler/sampler.h"
#include "penumbra/render/world.h"

namespace penumbra {

/// A light-transport algorithm bound to a world. Implementations are immutable and thread-safe;
/// all per-sample randomness comes from the sampler.
class Integrator {
 public:
  virtual ~Integrator() = default;
  /// The registered name with its parameters.
  virtual std::string name() const = 0;
  /// Radiance arriving at the camera along `ray`.
  virtual Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const = 0;
};

}  // namespace penumbra
