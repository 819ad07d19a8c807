#pragma once
/// Area lights: the emissive shapes of the scene, sampled by points on their surfaces.
#include <vector>

#include "penumbra/render/light/light.h"
#include "penumbra/render/world.h"

namespace penumbra {

/// An emissive shape (triangles, parallelograms, spheres) of constant radiance L, emitting from its
/// front side (or both sides). A sample picks a primitive in proportion to its area and a uniform
/// point on it, so points are uniform over the whole emitting area A; the solid-angle density at a
/// receiver is then d^2 / (|cos theta_l| A). The estimate f L |cos theta| / pdf of the incident
/// light converges to the true irradiance integral (the lecture's "intensity ~ hits / rays" is the
/// special case of a small light of uniform brightness).
class AreaLight final : public Light {
 public:
  AreaLight(const World& world, const Emitter& emitter);
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  Rgb power() const override;
  /// Solid-angle density with which sample_li, called from `p`, would pick the point `q` of this
  /// light with unit front normal `n` (for multiple importance sampling).
  float pdf_li(Vec3 p, Vec3 q, Vec3 n) const;
  /// Total emitting area.
  float area() const { return area_; }

 private:
  /// A sampled point with its unit front normal.
  void sample_point(Vec2 u, Vec3& q, Vec3& n) const;

  const World& world_;
  std::vector<uint32_t> prims_;
  std::vector<float> cdf_;  ///< cumulative area fractions of prims_
  Rgb radiance_;
  bool two_sided_;
  float area_ = 0;
};

}  // namespace penumbra
