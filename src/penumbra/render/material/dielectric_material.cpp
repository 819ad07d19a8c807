#include "penumbra/render/material/dielectric_material.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, -1.0f, 1.0f);
  if (cos_i < 0.0f) eta = 1.0f / eta, cos_i = -cos_i;  // leaving the inside
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

bool refract(Vec3 wo, float eta, Vec3& wi, float& eta_rel) {
  float cos_i = wo.z;
  Vec3 n{0, 0, 1};
  eta_rel = eta;
  if (cos_i < 0.0f) eta_rel = 1.0f / eta, cos_i = -cos_i, n = -n;  // wo inside
  const float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta_rel * eta_rel);
  if (sin2_t >= 1.0f) return false;
  const float cos_t = std::sqrt(1.0f - sin2_t);
  // Snell's law in vector form: wi = -wo / eta + (cos_i / eta - cos_t) n.
  wi = -wo / eta_rel + n * (cos_i / eta_rel - cos_t);
  return true;
}

DielectricMaterial::DielectricMaterial(const SceneParams& params) {
  ior_ = params.get_float("ior", 1.5f);
  if (!(ior_ > 0.0f && ior_ < 100.0f)) params.fail("ior", "must lie in (0, 100)");
  tint_ = params.get_rgb("tint", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(tint_[c] >= 0.0f && tint_[c] <= 1.0f)) params.fail("tint", "must lie in [0, 1]");
  params.check_all_used();
}

int DielectricMaterial::specular_lobes(Vec3 wo, SpecularLobe out[2]) const {
  const float f = fresnel_dielectric(wo.z, ior_);
  int n = 0;
  out[n++] = {{-wo.x, -wo.y, wo.z}, Rgb(f)};
  Vec3 wt;
  float eta_rel;
  if (f < 1.0f && refract(wo, ior_, wt, eta_rel))
    out[n++] = {wt, tint_ * ((1.0f - f) / (eta_rel * eta_rel))};  // radiance scales by 1/eta^2
  return n;
}

std::optional<BsdfSample> DielectricMaterial::sample(Vec3 wo, float uc, Vec2) const {
  SpecularLobe lobes[2];
  const int n = specular_lobes(wo, lobes);
  const float f = fresnel_dielectric(wo.z, ior_);
  // Choose reflection with probability F, refraction with 1 - F.
  const int pick = (n == 2 && uc >= f) ? 1 : 0;
  const float prob = n == 2 ? (pick == 0 ? f : 1.0f - f) : 1.0f;
  const float c = std::fabs(lobes[pick].wi.z);
  if (!(c > 0.0f) || !(prob > 0.0f)) return std::nullopt;
  return BsdfSample{lobes[pick].wi, lobes[pick].weight * (prob / c), prob, true};
}

}  // namespace penumbra
