#include "penumbra/render/integrator/whitted_integrator.h"

#include <cmath>

#include "penumbra/render/light/emitter_point_light.h"
#include "penumbra/render/material/material.h"

namespace penumbra {

WhittedIntegrator::WhittedIntegrator(const World& world, const ParamList& params, int max_depth)
    : world_(world), max_depth_(static_cast<int>(params.get_int("max_depth", max_depth, 0, 1000))) {
  params.check_all_used();
  for (const auto& light : world.lights()) lights_.push_back(light.get());
  for (const Emitter& e : world.emitters()) {
    stand_ins_.push_back(std::make_unique<EmitterPointLight>(world, e));
    lights_.push_back(stand_ins_.back().get());
  }
}

Rgb WhittedIntegrator::li(const Ray& ray, Sampler& sampler, RayCounter& counter) const {
  return trace(ray, 0, sampler, counter);
}

Rgb WhittedIntegrator::trace(const Ray& ray, int depth, Sampler& sampler,
                             RayCounter& counter) const {
  SurfaceInteraction si;
  if (!world_.intersect(ray, si, counter)) return world_.background();
  MaterialScratch scratch;
  si.material = &si.material->at(si, scratch);  // textures evaluated at the hit
  Rgb radiance = si.emitted;
  const Material& material = *si.material;
  const Vec3 wo = si.to_local(si.wo);

  // Direct light: one shadow ray per light.
  if (material.has_non_specular()) {
    for (const Light* light : lights_) {
      const LightSample ls = light->sample_li(si.p, sampler.get_2d());
      if (ls.li.is_black() || !(ls.pdf > 0.0f)) continue;
      const Rgb f = material.eval(wo, si.to_local(ls.wi));
      if (f.is_black()) continue;
      if (world_.occluded(si.spawn_ray_to(si.p + ls.wi * ls.distance, ray.time), counter)) continue;
      radiance += f * ls.li * (std::fabs(dot(ls.wi, si.ns)) / ls.pdf);
    }
  }

  // Specular recursion: mirror reflection, refraction.
  if (depth < max_depth_) {
    SpecularLobe lobes[2];
    const int n = material.specular_lobes(wo, lobes);
    for (int i = 0; i < n; ++i) {
      if (lobes[i].weight.is_black()) continue;
      const Vec3 wi = si.to_world(lobes[i].wi);
      radiance += lobes[i].weight * trace(si.spawn_ray(wi, ray.time), depth + 1, sampler, counter);
    }
  }
  return radiance;
}

}  // namespace penumbra
