#include "penumbra/render/material/conductor_material.h"

#include "penumbra/render/texture/texture_params.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

namespace penumbra {

Rgb fresnel_conductor(float cos_i, Rgb eta, Rgb k) {
  cos_i = std::clamp(std::fabs(cos_i), 0.0f, 1.0f);
  const float sin2_i = 1.0f - cos_i * cos_i;
  Rgb result;
  for (int c = 0; c < 3; ++c) {
    // Snell's law and the Fresnel amplitudes with a complex index: the transmitted cosine is
    // complex (an evanescent wave), the formulas are otherwise the dielectric ones.
    const std::complex<float> n(eta[c], k[c]);
    const std::complex<float> cos_t = std::sqrt(1.0f - sin2_i / (n * n));
    const std::complex<float> r_parallel = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    const std::complex<float> r_perpendicular = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    result[c] = 0.5f * (std::norm(r_parallel) + std::norm(r_perpendicular));
  }
  return result;
}

Rgb fresnel_schlick(float cos_i, Rgb f0) {
  const float m = 1.0f - std::clamp(std::fabs(cos_i), 0.0f, 1.0f);
  const float m5 = (m * m) * (m * m) * m;
  return f0 + (Rgb(1.0f) - f0) * m5;
}

Rgb ConductorFresnel::eval(float cos_i) const {
  return schlick ? fresnel_schlick(cos_i, f0) : fresnel_conductor(cos_i, eta, k);
}

ConductorMaterial::ConductorMaterial(ConductorFresnel fresnel, float roughness)
    : fresnel_(fresnel),
      distribution_(MicrofacetDistribution::roughness_to_alpha(roughness)),
      smooth_(distribution_.effectively_smooth()) {}

ConductorMaterial::ConductorMaterial(ConductorFresnel fresnel,
                                     const MicrofacetDistribution& distribution)
    : fresnel_(fresnel), distribution_(distribution), smooth_(distribution.effectively_smooth()) {}

namespace {

// Reads `key` as an RGB whose channels must lie in [lo, hi] (lo excluded when `open_lo`); the
// message names the interval.
Rgb get_rgb_in(const SceneParams& params, const char* key, float lo, float hi, bool open_lo,
               const char* interval) {
  const Rgb v = params.get_rgb(key, Rgb(0.0f));
  for (int c = 0; c < 3; ++c)
    if (!((open_lo ? v[c] > lo : v[c] >= lo) && v[c] <= hi))
      params.fail(key, std::string("must lie in ") + interval);
  return v;
}

// The Fresnel form from either eta and k or reflectance (its texture to `f0`); exactly one form
// must be given.
ConductorFresnel read_fresnel(const SceneParams& params, const std::vector<EmbeddedImage>* embedded,
                              Texture& f0) {
  const bool has_ior = params.has("eta") || params.has("k");
  const bool has_f0 = params.has("reflectance");
  if (has_ior && has_f0)
    params.fail("reflectance", "give either \"eta\" and \"k\" or \"reflectance\", not both");
  if (!has_ior && !has_f0)
    params.fail("type",
                "a conductor needs \"eta\" and \"k\" (complex index of refraction) or "
                "\"reflectance\" (Schlick's normal-incidence colour)");
  if (has_f0) {
    f0 = read_texture(params, "reflectance", Rgb(0.0f), 0.0f, 1.0f, embedded);
    return ConductorFresnel::schlick_f0(f0.eval(TextureQuery{}));
  }
  if (!params.has("eta")) params.fail("eta", "missing: \"eta\" and \"k\" go together");
  if (!params.has("k")) params.fail("k", "missing: \"eta\" and \"k\" go together");
  return ConductorFresnel::complex_ior(get_rgb_in(params, "eta", 0, 100, true, "(0, 100]"),
                                       get_rgb_in(params, "k", 0, 100, false, "[0, 100]"));
}

}  // namespace

ConductorMaterial::ConductorMaterial(const SceneParams& params,
                                     const std::vector<EmbeddedImage>* embedded)
    : distribution_(MicrofacetDistribution::roughness_to_alpha(read_roughness(params))),
      smooth_(distribution_.effectively_smooth()) {
  fresnel_ = read_fresnel(params, embedded, f0_texture_);
  textured_ = !f0_texture_.is_constant();
  params.check_all_used();
}

const Material& ConductorMaterial::resolve(const SurfaceInteraction& si,
                                           MaterialScratch& scratch) const {
  return scratch.emplace<ConductorMaterial>(ConductorFresnel::schlick_f0(f0_texture_.eval(si)),
                                            distribution_);
}

Rgb ConductorMaterial::eval(Vec3 wo, Vec3 wi, TransportMode) const {
  if (smooth_ || !same_hemisphere(wo, wi)) return {};
  if (wo.z < 0.0f) wo.z = -wo.z, wi.z = -wi.z;  // the back side reflects alike
  const Vec3 sum = wo + wi;
  const float len = length(sum);
  if (!(len > 0.0f)) return {};
  const Vec3 h = sum / len;
  const float scale =
      distribution_.d(h) * distribution_.g2_reflection(wo, wi) / (4.0f * wo.z * wi.z);
  return fresnel_.eval(dot(wo, h)) * scale;
}

float ConductorMaterial::pdf(Vec3 wo, Vec3 wi) const {
  if (smooth_ || !same_hemisphere(wo, wi)) return 0.0f;
  if (wo.z < 0.0f) wo.z = -wo.z, wi.z = -wi.z;
  const Vec3 sum = wo + wi;
  const float len = length(sum);
  if (!(len > 0.0f)) return 0.0f;
  const Vec3 h = sum / len;
  const float wo_h = dot(wo, h);
  if (!(wo_h > 0.0f)) return 0.0f;
  // Visible-normal density times the Jacobian dh/dwi = 1 / (4 wo.h) of reflection.
  return distribution_.d_visible(wo, h) / (4.0f * wo_h);
}

std::optional<BsdfSample> ConductorMaterial::sample(Vec3 wo, float, Vec2 u, TransportMode) const {
  if (smooth_) {
    SpecularLobe lobe;
    specular_lobes(wo, &lobe);
    const float c = std::fabs(cos_theta(lobe.wi));
    if (!(c > 0.0f)) return std::nullopt;
    return BsdfSample{lobe.wi, lobe.weight / c, 1.0f, kBsdfSpecular | kBsdfReflection};
  }
  if (wo.z == 0.0f) return std::nullopt;
  const bool back = wo.z < 0.0f;
  if (back) wo.z = -wo.z;
  // Visible normal, mirror reflection about it; directions below the surface are rejected.
  const Vec3 h = distribution_.sample_visible(wo, u);
  Vec3 wi = reflect(wo, h);
  const float wo_h = dot(wo, h);
  if (!(wi.z > 0.0f) || !(wo_h > 0.0f)) return std::nullopt;
  const float pdf = distribution_.d_visible(wo, h) / (4.0f * wo_h);
  if (!(pdf > 0.0f)) return std::nullopt;
  const Rgb f = fresnel_.eval(wo_h) *
                (distribution_.d(h) * distribution_.g2_reflection(wo, wi) / (4.0f * wo.z * wi.z));
  if (back) wi.z = -wi.z;
  return BsdfSample{wi, f, pdf, kBsdfGlossy | kBsdfReflection};
}

int ConductorMaterial::specular_lobes(Vec3 wo, SpecularLobe out[2]) const {
  if (!smooth_) return 0;
  out[0] = {{-wo.x, -wo.y, wo.z}, fresnel_.eval(wo.z)};
  return 1;
}

}  // namespace penumbra
