#pragma once
/// The stand-in for an emissive shape used by the Whitted integrator until true area lights: a point
/// light at the shape's centre that emits the shape's power with the shape's angular distribution.
#include <vector>

#include "penumbra/render/light/light.h"
#include "penumbra/render/world.h"

namespace penumbra {

/// Point light standing in for an emitter of radiance L. Its radiant intensity towards a unit
/// direction w is the far field of the shape: L (sum over planar primitives of A_i max(0, n_i . w)
/// — |n_i . w| when two-sided — plus pi r^2 per sphere), so its total power equals the shape's
/// (pi A L for a one-sided flat emitter). It sits at the area-weighted centroid of the planar
/// primitives; a sphere's stand-in sits on the sphere's surface point facing the receiver (its
/// centre would be hidden by the sphere itself). A closed emissive mesh shadows its own centroid:
/// true area lights (distribution ray tracing) replace this approximation. Not a scene Light: only
/// `whitted` uses it, beside the world's delta lights.
class EmitterPointLight {
 public:
  EmitterPointLight(const World& world, const Emitter& emitter);
  /// The incident light at `p` (delta: pdf 1).
  LightSample sample_li(Vec3 p, Vec2 u) const;
  /// Total emitted power, the shape's.
  Rgb power() const;
  /// Radiant intensity (W/sr) towards the unit direction w.
  Rgb intensity(Vec3 w) const;

 private:
  Vec3 centroid_;
  std::vector<Vec3> area_normals_;  ///< A_i n_i of planar primitives
  std::vector<SphereData> spheres_;
  Rgb radiance_;
  bool two_sided_;
  float area_ = 0;
};

}  // namespace penumbra
