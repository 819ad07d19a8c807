#pragma once
/// Light sources sampled by shadow rays.
#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// Incident light at a point from one sample of a light.
struct LightSample {
  Vec3 wi;            ///< unit direction from the shading point towards the light
  float distance = 0; ///< distance to the sampled light point (for the shadow ray)
  Rgb li;             ///< incident radiance (for a delta light: intensity / distance^2)
  float pdf = 0;      ///< solid-angle density of wi (1 for a delta light)
  bool delta = false; ///< a point light: no density, one sample is exact
};

/// A light source. Implementations are immutable and thread-safe.
class Light {
 public:
  virtual ~Light() = default;
  /// Samples the light as seen from point `p` with the uniform pair `u`.
  virtual LightSample sample_li(Vec3 p, Vec2 u) const = 0;
  /// Total emitted power (W, per channel).
  virtual Rgb power() const = 0;
};

}  // namespace penumbra
