#pragma once
/// A rough dielectric interface (frosted glass): microfacet reflection and transmission, the
/// blurry translucency of distribution ray tracing.
#include <optional>

#include "penumbra/render/material/dielectric_material.h"
#include "penumbra/render/material/material.h"
#include "penumbra/render/material/microfacet.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Rough dielectric boundary after Walter, Marschner, Li, Torrance 2007, "Microfacet Models for
/// Refraction through Rough Surfaces": GGX normals, height-correlated Smith masking (Heitz 2014),
/// visible-normal sampling (Heitz 2018), reflection or refraction chosen by the Fresnel factor of
/// the sampled microfacet. The front side (the normal's) is outside. Transmitted radiance scales
/// by 1/eta^2 (eta = index on wi's side / index on wo's side), as in DielectricMaterial;
/// importance does not.
/// Parameters: ior (inside relative to outside, in (0, 100), default 1.5), roughness (in [0, 1],
/// default 0.3; alpha = roughness^2), tint (RGB transmittance factor in [0, 1], default 1).
/// alpha < 1e-3 or |ior - 1| < 1e-3 scatter as the smooth DielectricMaterial (delta lobes).
class RoughDielectricMaterial final : public Material {
 public:
  RoughDielectricMaterial(float ior, float roughness, Rgb tint);
  explicit RoughDielectricMaterial(const SceneParams& params);
  Rgb eval(Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::kRadiance) const override;
  float pdf(Vec3 wo, Vec3 wi) const override;
  std::optional<BsdfSample> sample(Vec3 wo, float uc, Vec2 u,
                                   TransportMode mode = TransportMode::kRadiance) const override;
  int specular_lobes(Vec3 wo, SpecularLobe out[2]) const override;
  BsdfFlags flags() const override {
    return (smooth_ ? kBsdfSpecular : kBsdfGlossy) | kBsdfReflection | kBsdfTransmission;
  }
  Rgb albedo() const override { return tint_; }
  /// The microfacet distribution.
  const MicrofacetDistribution& distribution() const { return distribution_; }
  /// The index of refraction inside relative to outside.
  float ior() const { return ior_; }

 private:
  /// The generalised half vector of a pair of directions and what it implies.
  struct HalfVector {
    Vec3 h;        ///< microfacet normal, h.z > 0
    float eta;     ///< index on wi's side / index on wo's side (1 for reflection)
    bool reflect;  ///< wo and wi on the same side
  };
  /// The microfacet normal that scatters wo into wi (Walter et al. 2007); none for
  /// grazing directions or when the microfacet would face away from either direction.
  std::optional<HalfVector> half_vector(Vec3 wo, Vec3 wi) const;
  /// The BSDF value for a pair with half vector hv and Fresnel factor fr.
  Rgb value(Vec3 wo, Vec3 wi, const HalfVector& hv, float fr, TransportMode mode) const;
  /// The density of choosing wi, given the visible-normal density pdf_h of hv.h.
  static float density(Vec3 wo, Vec3 wi, const HalfVector& hv, float fr, float pdf_h);

  float ior_;
  Rgb tint_;
  MicrofacetDistribution distribution_;
  bool smooth_;
  DielectricMaterial specular_;  ///< the smooth interface, used when smooth_
};

}  // namespace penumbra
