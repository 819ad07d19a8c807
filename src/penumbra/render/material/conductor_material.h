#pragma once
/// Metals: microfacet reflection with the Fresnel factor of a conductor (glossy reflection).
#include "penumbra/render/material/material.h"
#include "penumbra/render/material/microfacet.h"
#include "penumbra/render/texture/texture.h"
#include "penumbra/scene/scene_desc.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Exact Fresnel reflectance for unpolarised light of a conductor of complex index of refraction
/// eta + i k (relative to the outside), per channel, for the cosine of the incident angle (Born,
/// Wolf 1999, "Principles of Optics", section 14.2).
Rgb fresnel_conductor(float cos_i, Rgb eta, Rgb k);

/// Schlick's approximation F0 + (1 - F0) (1 - cos)^5 (Schlick 1994, "An Inexpensive BRDF Model for
/// Physically-based Rendering").
Rgb fresnel_schlick(float cos_i, Rgb f0);

/// How a conductor's reflectance depends on the angle: a complex index of refraction or a Schlick
/// colour.
struct ConductorFresnel {
  bool schlick = false;
  Rgb eta, k;  ///< complex index eta + i k (when !schlick)
  Rgb f0;      ///< reflectance at normal incidence (when schlick)

  /// The exact form for a complex index of refraction.
  static ConductorFresnel complex_ior(Rgb eta, Rgb k) { return {false, eta, k, {}}; }
  /// Schlick's approximation with normal-incidence reflectance f0.
  static ConductorFresnel schlick_f0(Rgb f0) { return {true, {}, {}, f0}; }
  /// Reflectance at the cosine |cos_i| between the direction and the microfacet normal.
  Rgb eval(float cos_i) const;
};

/// Rough conductor: f = D G2 F / (4 |cos o| |cos i|) with the GGX distribution, height-correlated
/// Smith G2 (Walter et al. 2007; Heitz 2014), importance-sampled by visible normals (Heitz 2018).
/// Reflects on both sides. Parameters: roughness (in [0, 1], default 0.3; alpha = roughness^2;
/// alpha < 1e-3 is a perfect mirror); either eta and k (RGB, complex index of refraction) or
/// reflectance (RGB in [0, 1] or a texture of such colours, Schlick's F0), exactly one of the two
/// forms.
class ConductorMaterial final : public Material {
 public:
  ConductorMaterial(ConductorFresnel fresnel, float roughness);
  /// A conductor with this Fresnel form and distribution (a textured one at a surface point).
  ConductorMaterial(ConductorFresnel fresnel, const MicrofacetDistribution& distribution);
  /// From scene parameters; an image texture of reflectance may name one of `embedded`.
  explicit ConductorMaterial(const SceneParams& params,
                             const std::vector<EmbeddedImage>* embedded = nullptr);
  Rgb eval(Vec3 wo, Vec3 wi, TransportMode mode = TransportMode::kRadiance) const override;
  float pdf(Vec3 wo, Vec3 wi) const override;
  std::optional<BsdfSample> sample(Vec3 wo, float uc, Vec2 u,
                                   TransportMode mode = TransportMode::kRadiance) const override;
  int specular_lobes(Vec3 wo, SpecularLobe out[2]) const override;
  BsdfFlags flags() const override {
    return (smooth_ ? kBsdfSpecular : kBsdfGlossy) | kBsdfReflection;
  }
  /// The reflectance at normal incidence.
  Rgb albedo() const override { return fresnel_.eval(1.0f); }
  /// The microfacet distribution.
  const MicrofacetDistribution& distribution() const { return distribution_; }

 protected:
  const Material& resolve(const SurfaceInteraction& si, MaterialScratch& scratch) const override;

 private:
  ConductorFresnel fresnel_;
  MicrofacetDistribution distribution_;
  bool smooth_;
  Texture f0_texture_;  ///< Schlick's F0 over the surface, used when textured_
};

}  // namespace penumbra
