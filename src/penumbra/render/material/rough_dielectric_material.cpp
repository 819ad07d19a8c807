#include "penumbra/render/material/rough_dielectric_material.h"

#include <cmath>

namespace penumbra {

namespace {

// An index this close to 1 bends light by less than a tenth of a degree: a smooth interface.
constexpr float kIndexMatched = 1e-3f;

// The view direction on the +z side, as the microsurface sees it from wo's side.
Vec3 upper(Vec3 w) {
  return w.z < 0.0f ? -w : w;
}

}  // namespace

RoughDielectricMaterial::RoughDielectricMaterial(float ior, float roughness, Rgb tint)
    : ior_(ior),
      tint_(tint),
      distribution_(MicrofacetDistribution::roughness_to_alpha(roughness)),
      smooth_(distribution_.effectively_smooth() || std::fabs(ior - 1.0f) < kIndexMatched),
      specular_(ior, tint) {}

namespace {

// The parameters in declaration order: ior, roughness, tint.
RoughDielectricMaterial read(const SceneParams& params) {
  const float ior = params.get_float("ior", 1.5f);
  if (!(ior > 0.0f && ior < 100.0f)) params.fail("ior", "must lie in (0, 100)");
  const float roughness = read_roughness(params);
  const Rgb tint = params.get_rgb("tint", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(tint[c] >= 0.0f && tint[c] <= 1.0f)) params.fail("tint", "must lie in [0, 1]");
  params.check_all_used();
  return {ior, roughness, tint};
}

}  // namespace

RoughDielectricMaterial::RoughDielectricMaterial(const SceneParams& params)
    : RoughDielectricMaterial(read(params)) {}

std::optional<RoughDielectricMaterial::HalfVector> RoughDielectricMaterial::half_vector(
    Vec3 wo, Vec3 wi) const {
  const float cos_o = cos_theta(wo), cos_i = cos_theta(wi);
  if (cos_o == 0.0f || cos_i == 0.0f) return std::nullopt;
  const bool is_reflection = cos_o * cos_i > 0.0f;
  const float eta = is_reflection ? 1.0f : (cos_o > 0.0f ? ior_ : 1.0f / ior_);
  // h is parallel to eta_o wo + eta_i wi (the mirror half vector when eta = 1), turned outwards.
  Vec3 h = wo + wi * eta;
  const float len = length(h);
  if (!(len > 0.0f)) return std::nullopt;
  h = h / len;
  if (h.z < 0.0f) h = -h;
  // Microfacets seen from behind by either direction scatter nothing.
  if (!(dot(h, wo) * cos_o > 0.0f) || !(dot(h, wi) * cos_i > 0.0f)) return std::nullopt;
  return HalfVector{h, eta, is_reflection};
}

Rgb RoughDielectricMaterial::value(Vec3 wo, Vec3 wi, const HalfVector& hv, float fr,
                                   TransportMode mode) const {
  const float d = distribution_.d(hv.h);
  const float cos_oi = std::fabs(cos_theta(wo) * cos_theta(wi));
  if (hv.reflect) return Rgb(d * distribution_.g2_reflection(wo, wi) * fr / (4.0f * cos_oi));
  // Walter et al. 2007 transmission term with the radiance factor 1/eta^2 (none for importance):
  // f = |i.h| |o.h| (1 - F) D G2 / (|cos i| |cos o| (i.h + o.h / eta)^2 eta^2).
  const float o_h = dot(wo, hv.h), i_h = dot(wi, hv.h);
  const float denom = i_h + o_h / hv.eta;
  const float t = (1.0f - fr) * d * distribution_.g2_transmission(wo, wi) * std::fabs(i_h * o_h) /
                  (cos_oi * denom * denom);
  return tint_ * (mode == TransportMode::kRadiance ? t / (hv.eta * hv.eta) : t);
}

float RoughDielectricMaterial::density(Vec3 wo, Vec3 wi, const HalfVector& hv, float fr,
                                       float pdf_h) {
  // The lobe's probability times the visible-normal density times the Jacobian dh/dwi:
  // 1 / (4 |o.h|) for reflection, |i.h| / (i.h + o.h / eta)^2 for refraction.
  if (hv.reflect) return fr * pdf_h / (4.0f * std::fabs(dot(wo, hv.h)));
  const float i_h = dot(wi, hv.h);
  const float denom = i_h + dot(wo, hv.h) / hv.eta;
  return (1.0f - fr) * pdf_h * std::fabs(i_h) / (denom * denom);
}

Rgb RoughDielectricMaterial::eval(Vec3 wo, Vec3 wi, TransportMode mode) const {
  if (smooth_) return {};
  const auto hv = half_vector(wo, wi);
  if (!hv) return {};
  return value(wo, wi, *hv, fresnel_dielectric(dot(wo, hv->h), ior_), mode);
}

float RoughDielectricMaterial::pdf(Vec3 wo, Vec3 wi) const {
  if (smooth_) return 0.0f;
  const auto hv = half_vector(wo, wi);
  if (!hv) return 0.0f;
  const float pdf_h = distribution_.d_visible(upper(wo), hv->h);
  return density(wo, wi, *hv, fresnel_dielectric(dot(wo, hv->h), ior_), pdf_h);
}

std::optional<BsdfSample> RoughDielectricMaterial::sample(Vec3 wo, float uc, Vec2 u,
                                                          TransportMode mode) const {
  if (smooth_) return specular_.sample(wo, uc, u, mode);
  if (cos_theta(wo) == 0.0f) return std::nullopt;
  // A normal visible from wo's side (for wo inside: the microsurface seen from below).
  const Vec3 h = distribution_.sample_visible(upper(wo), u);
  const float pdf_h = distribution_.d_visible(upper(wo), h);
  if (!(pdf_h > 0.0f)) return std::nullopt;
  const float o_h = dot(wo, h);
  const float fr = fresnel_dielectric(o_h, ior_);

  // Reflect with probability F, else refract through the microfacet.
  HalfVector hv{h, 1.0f, uc < fr};
  Vec3 wi;
  if (hv.reflect) {
    wi = reflect(wo, h);
    if (!same_hemisphere(wo, wi)) return std::nullopt;
  } else {
    Vec3 t, b, wi_h;
    orthonormal_basis(h, t, b);
    if (!refract({dot(wo, t), dot(wo, b), o_h}, ior_, wi_h, hv.eta)) return std::nullopt;
    wi = t * wi_h.x + b * wi_h.y + h * wi_h.z;
    if (!(cos_theta(wi) * cos_theta(wo) < 0.0f)) return std::nullopt;
  }
  const float p = density(wo, wi, hv, fr, pdf_h);
  if (!(p > 0.0f) || cos_theta(wi) == 0.0f) return std::nullopt;
  return BsdfSample{wi, value(wo, wi, hv, fr, mode), p,
                    kBsdfGlossy | (hv.reflect ? kBsdfReflection : kBsdfTransmission),
                    hv.reflect ? 1.0f : hv.eta};
}

int RoughDielectricMaterial::specular_lobes(Vec3 wo, SpecularLobe out[2]) const {
  return smooth_ ? specular_.specular_lobes(wo, out) : 0;
}

}  // namespace penumbra
