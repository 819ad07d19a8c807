#include "penumbra/render/integrator/distribution_integrator.h"

#include <cmath>

#include <fmt/format.h>

#include "penumbra/render/material/material.h"

namespace penumbra {

namespace {
/// Power heuristic with exponent 2 for a sample of strategy a against strategy b, each density
/// already multiplied by its sample count.
float power_heuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}
}  // namespace

DistributionIntegrator::DistributionIntegrator(const World& world, const ParamList& params,
                                               int max_depth)
    : world_(world),
      max_depth_(static_cast<int>(params.get_int("max_depth", max_depth, 0, 1000))),
      light_samples_(static_cast<int>(params.get_int("light_samples", 4, 1, 4096))),
      glossy_samples_(static_cast<int>(params.get_int("glossy_samples", 1, 1, 4096))) {
  params.check_all_used();
  // Jitter the light samples of one shading point over strata_x x strata_y cells.
  strata_x_ = static_cast<int>(std::sqrt(double(light_samples_)));
  while (light_samples_ % strata_x_ != 0) --strata_x_;
  strata_y_ = light_samples_ / strata_x_;
  for (const Emitter& e : world.emitters()) {
    if (light_of_shape_.size() <= e.shape) light_of_shape_.resize(e.shape + 1, -1);
    light_of_shape_[e.shape] = static_cast<int>(area_lights_.size());
    area_lights_.push_back(std::make_unique<AreaLight>(world, e));
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
  for (const auto& light : world_.lights()) {
    const LightSample ls = light->sample_li(si.p, sampler.get_2d());
    if (ls.li.is_black()) continue;
    const Rgb f = m.eval(wo, si.to_local(ls.wi));
    if (f.is_black()) continue;
    if (world_.occluded(si.spawn_ray_to(si.p + ls.wi * ls.distance, time), counter)) continue;
    sum += f * ls.li * (std::fabs(dot(ls.wi, si.ns)) / ls.pdf);
  }
  // Area lights: light_samples jittered points each.
  for (const auto& light : area_lights_) {
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
      if (world_.occluded(si.spawn_ray_to(si.p + ls.wi * ls.distance, time), counter)) continue;
      // At glossy surfaces BSDF sampling also reaches this light: weight the two strategies.
      const float w = m.is_glossy() ? power_heuristic(float(light_samples_) * ls.pdf,
                                                      float(glossy_samples_) * m.pdf(wo, wi))
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
  if (!world_.intersect(ray, si, counter)) return world_.background();
  MaterialScratch scratch;
  si.material = &si.material->at(si, scratch);  // textures evaluated at the hit
  Rgb radiance;
  // Emission seen directly or through specular paths counts fully; seen along a glossy BSDF
  // sample it is weighted against the light samples that also reached it.
  if (!si.emitted.is_black()) {
    float w = 1.0f;
    const int light = si.shape < light_of_shape_.size() ? light_of_shape_[si.shape] : -1;
    if (bsdf_pdf > 0.0f && light >= 0) {
      const float light_pdf = area_lights_[size_t(light)]->pdf_li(ray.o, si.p, si.ng);
      w = power_heuristic(float(glossy_samples_) * bsdf_pdf, float(light_samples_) * light_pdf);
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
      glossy += weight * trace(si.spawn_ray(wi, ray.time), depth + 1, bs->delta ? 0.0f : bs->pdf,
                               sampler, counter);
    }
    radiance += glossy / float(glossy_samples_);
  }
  return radiance;
}

}  // namespace penumbra
