#include "penumbra/render/material/diffuse_material.h"

#include <cmath>
#include <numbers>

#include "penumbra/render/sampling.h"

namespace penumbra {

DiffuseMaterial::DiffuseMaterial(const SceneParams& params) {
  albedo_ = params.get_rgb("albedo", Rgb(0.5f));
  for (int c = 0; c < 3; ++c)
    if (!(albedo_[c] >= 0.0f && albedo_[c] <= 1.0f)) params.fail("albedo", "must lie in [0, 1]");
  params.check_all_used();
}

Rgb DiffuseMaterial::eval(Vec3 wo, Vec3 wi) const {
  if (!same_hemisphere(wo, wi)) return {};
  return albedo_ * std::numbers::inv_pi_v<float>;
}

float DiffuseMaterial::pdf(Vec3 wo, Vec3 wi) const {
  return same_hemisphere(wo, wi) ? std::fabs(cos_theta(wi)) * std::numbers::inv_pi_v<float> : 0.0f;
}

std::optional<BsdfSample> DiffuseMaterial::sample(Vec3 wo, float, Vec2 u) const {
  Vec3 wi = sample_cosine_hemisphere(u);
  if (wo.z < 0.0f) wi.z = -wi.z;
  const float p = pdf(wo, wi);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wo, wi), p, false};
}

}  // namespace penumbra
