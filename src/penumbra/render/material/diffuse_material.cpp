#include "penumbra/render/material/diffuse_material.h"

#include <cmath>
#include <numbers>

#include "penumbra/render/sampling.h"
#include "penumbra/render/texture/texture_params.h"

namespace penumbra {

DiffuseMaterial::DiffuseMaterial(const SceneParams& params,
                                 const std::vector<EmbeddedImage>* embedded) {
  albedo_texture_ = read_texture(params, "albedo", Rgb(0.5f), 0.0f, 1.0f, embedded);
  textured_ = !albedo_texture_.is_constant();
  albedo_ = albedo_texture_.eval(TextureQuery{});  // the colour itself when constant
  params.check_all_used();
}

const Material& DiffuseMaterial::resolve(const SurfaceInteraction& si,
                                         MaterialScratch& scratch) const {
  return scratch.emplace<DiffuseMaterial>(albedo_texture_.eval(si));
}

Rgb DiffuseMaterial::eval(Vec3 wo, Vec3 wi, TransportMode) const {
  if (!same_hemisphere(wo, wi)) return {};
  return albedo_ * std::numbers::inv_pi_v<float>;
}

float DiffuseMaterial::pdf(Vec3 wo, Vec3 wi) const {
  return same_hemisphere(wo, wi) ? std::fabs(cos_theta(wi)) * std::numbers::inv_pi_v<float> : 0.0f;
}

std::optional<BsdfSample> DiffuseMaterial::sample(Vec3 wo, float, Vec2 u, TransportMode) const {
  Vec3 wi = sample_cosine_hemisphere(u);
  if (wo.z < 0.0f) wi.z = -wi.z;
  const float p = pdf(wo, wi);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wo, wi), p, kBsdfDiffuse | kBsdfReflection};
}

}  // namespace penumbra
