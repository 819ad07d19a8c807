#pragma once
/// Lambertian (ideal diffuse) reflection.
#include "penumbra/render/material/material.h"
#include "penumbra/render/texture/texture.h"
#include "penumbra/scene/scene_desc.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Lambertian BRDF albedo / pi, reflecting on both sides. Parameters: albedo (RGB in [0, 1], or a
/// texture of such colours; default 0.5).
class DiffuseMaterial final : public Material {
 public:
  explicit DiffuseMaterial(Rgb albedo) : albedo_(albedo) {}
  /// From scene parameters; image textures may name one of `embedded`.
  explicit DiffuseMaterial(const SceneParams& params,
                           const std::vector<EmbeddedImage>* embedded = nullptr);
  Rgb eval(Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::kRadiance) const override;
  float pdf(Vec3 wo, Vec3 wi) const override;
  std::optional<BsdfSample> sample(Vec3 wo, float uc, Vec2 u,
                                   TransportMode mode = TransportMode::kRadiance) const override;
  int specular_lobes(Vec3, SpecularLobe[2]) const override { return 0; }
  BsdfFlags flags() const override { return kBsdfDiffuse | kBsdfReflection; }
  Rgb albedo() const override { return albedo_; }

 protected:
  const Material& resolve(const SurfaceInteraction& si, MaterialScratch& scratch) const override;

 private:
  Rgb albedo_;
  Texture albedo_texture_;  ///< used when textured_
};

}  // namespace penumbra
