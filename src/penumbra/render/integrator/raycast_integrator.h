#pragma once
/// `raycast`: the first hit only, the debugging view, and the cost view of the structures.
#include <memory>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/light/light_sampler.h"

namespace penumbra {

class Film;

/// Shades the first hit by its shading normal (mode=normal: (n + 1) / 2), its albedo
/// (mode=albedo; emitters show their radiance) or albedo times |cos| to the eye (mode=eyelight,
/// the default, which shows shape). Misses show the background.
///
/// mode=cost is the cost view of the acceleration structure: per pixel, the mean work of the
/// camera rays' closest-hit queries as counted by the structure itself (accel/traversal_cost.h):
/// `cost=nodes` (node records visited), `prims` (primitive tests) or `both` (their sum, the
/// default). After the last pass the mean counts become a heat map from black (0) through blue,
/// red and yellow to white (`scale`; 0, the default, takes the image's largest mean), with the
/// colour bar in the rightmost columns (0 at the bottom, the scale at the top); the summary
/// line says the scale. `raw=true` keeps the mean counts themselves in every channel (for EXR).
/// `rays=bounce` counts instead the closest-hit query of one diffuse bounce from each camera hit
/// (a cosine-weighted direction on the side the camera sees), `rays=shadow` the any-hit query of
/// one shadow ray from each camera hit to a light sample (the path tracer's light sampler,
/// `power`): the rays a path tracer spends its time on, as accel-bench's bounce and shadow
/// sets. A camera ray that hits nothing counts nothing there.
class RaycastIntegrator final : public SamplingIntegrator {
 public:
  enum class Mode { kNormal, kAlbedo, kEyelight, kCost };
  enum class Cost { kNodes, kPrims, kBoth };
  enum class Rays { kCamera, kBounce, kShadow };
  RaycastIntegrator(const World& world, const ParamList& params);
  std::string name() const override;
  RenderStats render(RenderJob& job) override;
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;

 private:
  /// Replaces the film's mean counts by the heat map and draws the colour bar; returns the scale.
  double colour_costs(Film& film) const;

  /// The counts of the secondary ray of `rays_` from the camera ray's hit.
  TraversalCost secondary_cost(const Ray& ray, Sampler& sampler, RayCounter& counter) const;

  const World& world_;
  Mode mode_;
  Cost cost_ = Cost::kBoth;
  Rays rays_ = Rays::kCamera;
  std::unique_ptr<LightSampler> lights_;  ///< for rays=shadow
  double scale_ = 0;  ///< count at the top of the colour map; 0: the image's largest
  bool raw_ = false;
};

/// The cost view's colour map at x in [0, 1] (clamped): black, blue, red, yellow, white.
Rgb heat_colour(float x);

}  // namespace penumbra
