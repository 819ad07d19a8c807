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

std::optional<BsdfSample> DielectricMaterial::sample(Vec3 wo, float uc, Vec2,
                                                     TransportMode mode) const {
  const float f = fresnel_dielectric(wo.z, ior_);
  Vec3 wt;
  float eta_rel = 1.0f;
  const bool can_refract = f < 1.0f && refract(wo, ior_, wt, eta_rel);
  // Choose reflection with probability F, refraction with 1 - F.
  if (!can_refract || uc < f) {
    const Vec3 wi{-wo.x, -wo.y, wo.z};
    const float prob = can_refract ? f : 1.0f;
    const float c = std::fabs(wi.z);
    if (!(c > 0.0f) || !(prob > 0.0f)) return std::nullopt;
    // f = lobe weight / |cos|, so f |cos| / pdf = weight / probability: unbiased for one lobe.
    return BsdfSample{wi, Rgb(f) / c, prob, kBsdfSpecular | kBsdfReflection, 1.0f};
  }
  const float prob = 1.0f - f;
  const float c = std::fabs(wt.z);
  if (!(c > 0.0f) || !(prob > 0.0f)) return std::nullopt;
  // Radiance is compressed into the denser medium: it scales by 1/eta^2 crossing the interface;
  // importance does not (Veach 1997, section 5.2).
  const float scale = mode == TransportMode::kRadiance ? 1.0f / (eta_rel * eta_rel) : 1.0f;
  return BsdfSample{wt, tint_ * ((1.0f - f) * scale / c), prob, kBsdfSpecular | kBsdfTransmission,
                    eta_rel};
}

}  // namespace penumbra
