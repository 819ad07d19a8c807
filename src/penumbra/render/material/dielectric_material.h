#pragma once
/// A smooth dielectric interface (glass, water): Fresnel-weighted specular reflection and refraction.
#include "penumbra/render/material/material.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Unpolarised Fresnel reflectance of a dielectric interface for the cosine of the incident angle
/// (measured from the side the normal points to) and eta = n_inside / n_outside; 1 under total
/// internal reflection.
float fresnel_dielectric(float cos_i, float eta);

/// Refracts the local direction wo through the interface whose normal is +z; eta = n_inside /
/// n_outside. Returns false under total internal reflection.
bool refract(Vec3 wo, float eta, Vec3& wi, float& eta_rel);

/// Smooth dielectric boundary; the front side (the normal's) is outside. Parameters: ior (index of
/// refraction inside, relative to outside; default 1.5), tint (RGB transmittance factor, default 1).
class DielectricMaterial final : public Material {
 public:
  DielectricMaterial(float ior, Rgb tint) : ior_(ior), tint_(tint) {}
  explicit DielectricMaterial(const SceneParams& params);
  Rgb eval(Vec3, Vec3, TransportMode = TransportMode::kRadiance) const override { return {}; }
  float pdf(Vec3, Vec3) const override { return 0.0f; }
  std::optional<BsdfSample> sample(Vec3 wo, float uc, Vec2 u,
                                   TransportMode mode = TransportMode::kRadiance) const override;
  int specular_lobes(Vec3 wo, SpecularLobe out[2]) const override;
  BsdfFlags flags() const override {
    return kBsdfSpecular | kBsdfReflection | kBsdfTransmission;
  }
  Rgb albedo() const override { return tint_; }

 private:
  float ior_;
  Rgb tint_;
};

}  // namespace penumbra
