#include "penumbra/render/integrator/distribution_integrator.h"

#include <cmath>

#include <fmt/format.h>

#include "penumbra/render/material/material.h"
#include "penumbra/render/sampling.h"

namespace penumbra {


DistributionIntegrator::DistributionIntegrator(const World& world, const ParamList& params,
                                               int max_depth)
    : world_(world),
      max_depth_(recursion_depth(params, max_depth, "distribution")),
      light_samples_(static_cast<int>(params.get_int("light_samples", 4, 1, 4096))),
      glossy_samples_(static_cast<int>(params.get_int("glossy_samples", 1, 1, 4096))) {
  params.check_all_used();
  // Jitter the light samples of one shading point over strata_x x strata_y cells.
  strata_x_ = static_cast<int>(std::sqrt(double(light_samples_)));
  while (light_samples_ % strata_x_ != 0) --strata_x_;
  strata_y_ = light_samples_ / strata_x_;
  for (const Light* light : world.lights()) {
    if (light->is_delta()) delta_lights_.push_back(light);
    else if (light->kind() == LightKind::kArea) area_lights_.push_back(light);
  }
}

std::string DistributionIntegrator::name() const {
  return fmt::format("distribution:light_samples={},glossy_samples={}", light_samples_,
                     glossy_samples_);
}

Rgb DistributionIntegrator::li(const Ray& ray, Sampler& sampler, RayCounter& counter) const {
  return trace(ray, 0, 0.0f, sampler, counter);
}

Rgb DistributionIntegrator::direct(const SurfaceInteraction& si, Vec3 wo, float time,
                                   Sampler& sampler, RayCounter& counter) const {
  const Material& m = *si.material;
  Rgb sum;
  // Point lights: one exact shadow ray each.
  for (const Light* light : delta_lights_) {
    const LightSample ls = light->sample_li(si.p, sampler.get_2d());
    if (ls.li.is_black()) continue;
    const Rgb f = m.eval(wo, si.to_local(ls.wi));
    if (f.is_black()) continue;
    if (world_.occluded(si.shadow_ray(ls, time), counter)) continue;
    sum += f * ls.li * (std::fabs(dot(ls.wi, si.ns)) / ls.pdf);
  }
  // Area lights: light_samples jittered points each.
  for (const Light* light : area_lights_) {
    Rgb light_sum;
    for (int k = 0; k < light_samples_; ++k) {
      const Vec2 u = sampler.get_2d();
      const Vec2 cell{(float(k % strata_x_) + u.x) / float(strata_x_),
                      (float(k / strata_x_) + u.y) / float(strata_y_)};
      const LightSample ls = light->sample_li(si.p, cell);
      if (ls.li.is_black() || !(ls.pdf > 0.0f)) continue;
      const Vec3 wi = si.to_local(ls.wi);
      const Rgb f = m.eval(wo, wi);
      if (f.is_black()) continue;
      if (world_.occluded(si.shadow_ray(ls, time), counter)) continue;
      // At glossy surfaces BSDF sampling also reaches this light: weight the two strategies.
      const float w = m.is_glossy() ? power_heuristic(float(light_samples_), ls.pdf,
                                                      float(glossy_samples_), m.pdf(wo, wi))
                                    : 1.0f;
      light_sum += f * ls.li * (std::fabs(dot(ls.wi, si.ns)) * w / ls.pdf);
    }
    sum += light_sum / float(light_samples_);
  }
  return sum;
}

Rgb DistributionIntegrator::trace(const Ray& ray, int depth, float bsdf_pdf, Sampler& sampler,
                                  RayCounter& counter) const {
  SurfaceInteraction si;
  if (!world_.intersect(ray, si, counter)) return world_.escaped(ray);
  MaterialScratch scratch;
  si.material = &si.material->at(si, scratch);  // textures evaluated at the hit
  Rgb radiance;
  // Emission seen directly or through specular paths counts fully; seen along a glossy BSDF
  // sample it is weighted against the light samples that also reached it.
  if (!si.emitted.is_black()) {
    float w = 1.0f;
    if (bsdf_pdf > 0.0f && si.area_light) {
      const float light_pdf = si.area_light->pdf_li(ray.o, ray.d, si.light_point());
      w = power_heuristic(float(glossy_samples_), bsdf_pdf, float(light_samples_), light_pdf);
    }
    radiance += si.emitted * w;
  }
  const Material& m = *si.material;
  const Vec3 wo = si.to_local(si.wo);
  if (m.has_non_specular()) radiance += direct(si, wo, ray.time, sampler, counter);
  if (depth >= max_depth_) return radiance;

  // Perfectly specular recursion: every lobe, deterministically.
  SpecularLobe lobes[2];
  const int n = m.specular_lobes(wo, lobes);
  for (int i = 0; i < n; ++i) {
    if (lobes[i].weight.is_black()) continue;
    const Ray next = si.spawn_ray(si.to_world(lobes[i].wi), ray.time);
    radiance += lobes[i].weight * trace(next, depth + 1, 0.0f, sampler, counter);
  }
  // Glossy recursion: directions sampled from the BSDF.
  if (m.is_glossy()) {
    Rgb glossy;
    for (int k = 0; k < glossy_samples_; ++k) {
      const float uc = sampler.get_1d();
      const auto bs = m.sample(wo, uc, sampler.get_2d());
      if (!bs || bs->f.is_black() || !(bs->pdf > 0.0f)) continue;
      const Vec3 wi = si.to_world(bs->wi);
      const Rgb weight = bs->f * (std::fabs(bs->wi.z) / bs->pdf);
      glossy += weight * trace(si.spawn_ray(wi, ray.time), depth + 1, bs->is_specular() ? 0.0f : bs->pdf,
                               sampler, counter);
    }
    radiance += glossy / float(glossy_samples_);
  }
  return radiance;
}

}  // namespace penumbra
