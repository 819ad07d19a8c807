#include "penumbra/render/integrator/direct_lighting.h"

#include <cmath>

namespace penumbra {

Rgb estimate_direct(const World& world, const LightSampler& lights, const SurfaceInteraction& si,
                    const Material& m, Vec3 wo, float time, Sampler& sampler, RayCounter& counter) {
  const float u_light = sampler.get_1d();
  const Vec2 u = sampler.get_2d();
  const SampledLight picked = lights.sample(u_light);
  if (!picked.light || !(picked.pmf > 0.0f)) return {};
  const LightSample ls = picked.light->sample_li(si.p, u);
  if (ls.li.is_black() || !(ls.pdf > 0.0f)) return {};
  const Rgb f = m.eval(wo, si.to_local(ls.wi)) * std::fabs(dot(ls.wi, si.ns));
  if (f.is_black()) return {};
  if (world.occluded(si.shadow_ray(ls, time), counter)) return {};
  return f * ls.li / (picked.pmf * ls.pdf);
}

}  // namespace penumbra
