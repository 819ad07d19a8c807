#pragma once
/// Perfect specular reflection.
#include "penumbra/render/material/material.h"
#include "penumbra/render/texture/texture.h"
#include "penumbra/scene/scene_desc.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// An ideal mirror. Parameters: reflectance (RGB in [0, 1], or a texture of such colours; default
/// 1).
class MirrorMaterial final : public Material {
 public:
  explicit MirrorMaterial(Rgb reflectance) : reflectance_(reflectance) {}
  /// From scene parameters; image textures may name one of `embedded`.
  explicit MirrorMaterial(const SceneParams& params,
                          const std::vector<EmbeddedImage>* embedded = nullptr);
  Rgb eval(Vec3, Vec3, TransportMode = TransportMode::kRadiance) const override { return {}; }
  float pdf(Vec3, Vec3) const override { return 0.0f; }
  std::optional<BsdfSample> sample(Vec3 wo, float uc, Vec2 u,
                                   TransportMode mode = TransportMode::kRadiance) const override;
  int specular_lobes(Vec3 wo, SpecularLobe out[2]) const override;
  BsdfFlags flags() const override { return kBsdfSpecular | kBsdfReflection; }
  Rgb albedo() const override { return reflectance_; }

 protected:
  const Material& resolve(const SurfaceInteraction& si, MaterialScratch& scratch) const override;

 private:
  Rgb reflectance_;
  Texture reflectance_texture_;  ///< used when textured_
};

}  // namespace penumbra
