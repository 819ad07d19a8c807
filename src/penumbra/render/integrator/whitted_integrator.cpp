#include "penumbra/render/integrator/whitted_integrator.h"

#include <cmath>

#include "penumbra/render/light/emitter_point_light.h"
#include "penumbra/render/material/material.h"

namespace penumbra {

WhittedIntegrator::WhittedIntegrator(const World& world, const ParamList& params, int max_depth)
    : world_(world), max_depth_(recursion_depth(params, max_depth, "whitted")) {
  params.check_all_used();
  for (const Light* light : world.lights())
    if (light->is_delta()) lights_.push_back(light);
  for (const Emitter& e : world.emitters()) stand_ins_.emplace_back(world, e);
}

Rgb WhittedIntegrator::li(const Ray& ray, Sampler& sampler, RayCounter& counter) const {
  return trace(ray, 0, sampler, counter);
}

Rgb WhittedIntegrator::trace(const Ray& ray, int depth, Sampler& sampler,
                             RayCounter& counter) const {
  SurfaceInteraction si;
  if (!world_.intersect(ray, si, counter)) return world_.escaped(ray);
  MaterialScratch scratch;
  si.material = &si.material->at(si, scratch);  // textures evaluated at the hit
  Rgb radiance = si.emitted;
  const Material& material = *si.material;
  const Vec3 wo = si.to_local(si.wo);

  // Direct light: one shadow ray per light.
  if (material.has_non_specular()) {
    const auto add = [&](const LightSample& ls) {
      if (ls.li.is_black() || !(ls.pdf > 0.0f)) return;
      const Rgb f = material.eval(wo, si.to_local(ls.wi));
      if (f.is_black()) return;
      if (world_.occluded(si.shadow_ray(ls, ray.time), counter)) return;
      radiance += f * ls.li * (std::fabs(dot(ls.wi, si.ns)) / ls.pdf);
    };
    for (const Light* light : lights_) add(light->sample_li(si.p, sampler.get_2d()));
    for (const EmitterPointLight& light : stand_ins_) add(light.sample_li(si.p, sampler.get_2d()));
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
