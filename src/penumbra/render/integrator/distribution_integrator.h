#pragma once
/// `distribution`: distribution ray tracing (Cook, Porter, Carpenter 1984, "Distributed Ray
/// Tracing", SIGGRAPH).
#include <memory>
#include <vector>

#include "penumbra/core/params.h"
#include "penumbra/render/integrator/integrator.h"
#include "penumbra/render/light/light.h"

namespace penumbra {

/// Direct light from every light with shadow rays (`light_samples` jittered points on each area
/// light per shading point: soft shadows), perfectly specular recursion (mirror, refraction), and
/// glossy recursion along `glossy_samples` directions sampled from the BSDF (glossy reflection,
/// blurry translucency). At glossy surfaces light sampling and BSDF sampling both see the
/// lights; their estimates are combined by multiple importance sampling with the power heuristic
/// (Veach, Guibas 1995, "Optimally Combining Sampling Techniques for Monte Carlo Rendering"), so an
/// emitter reflected in a glossy surface is counted once. Diffuse surfaces take direct light only
/// (no indirect diffuse: that is path tracing). Infinite lights are only seen, not sampled (the
/// background of rays that miss). Parameters: light_samples (default 4),
/// glossy_samples (default 1), max_depth (else the scene's).
class DistributionIntegrator final : public SamplingIntegrator {
 public:
  DistributionIntegrator(const World& world, const ParamList& params, int max_depth);
  std::string name() const override;
  Rgb li(const Ray& ray, Sampler& sampler, RayCounter& counter) const override;

 private:
  /// Radiance along `ray`; `bsdf_pdf` > 0 when the ray was sampled from a glossy BSDF (so an
  /// emitter it hits is weighted against light sampling), 0 for camera and specular rays.
  Rgb trace(const Ray& ray, int depth, float bsdf_pdf, Sampler& sampler, RayCounter& counter) const;
  /// Direct light at a non-specular surface point from every light.
  Rgb direct(const SurfaceInteraction& si, Vec3 wo, float time, Sampler& sampler,
             RayCounter& counter) const;

  const World& world_;
  int max_depth_, light_samples_, glossy_samples_;
  int strata_x_, strata_y_;  ///< light_samples = strata_x * strata_y
  std::vector<const Light*> delta_lights_;  ///< point and directional lights: one sample each
  std::vector<const Light*> area_lights_;   ///< the world's area lights: light_samples each
};

}  // namespace penumbra
