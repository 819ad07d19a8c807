#pragma once
/// The GGX (Trowbridge-Reitz) microfacet distribution: normal density, Smith masking-shadowing and
/// sampling of visible normals, shared by the rough conductor and the rough dielectric.
#include "penumbra/core/vec.h"

namespace penumbra {

class SceneParams;

/// Trowbridge-Reitz / GGX normal distribution (Trowbridge, Reitz 1975, "Average irregularity
/// representation of a rough surface for ray reflection"; Walter, Marschner, Li, Torrance 2007,
/// "Microfacet Models for Refraction through Rough Surfaces"), anisotropic with widths alpha_x,
/// alpha_y along the local x and y axes, with Smith masking-shadowing (Heitz 2014, "Understanding
/// the Masking-Shadowing Function in Microfacet-Based BRDFs"). Directions are in the local shading
/// frame (z = macro-surface normal); microfacet normals h always have h.z > 0.
class MicrofacetDistribution {
 public:
  /// Widths below this are treated as a perfectly smooth surface (a delta lobe): the lobe is then
  /// narrower than 0.1 degree and its peak density 1 / (pi alpha^2) would exceed 3e5.
  static constexpr float kSmoothAlpha = 1e-3f;

  /// The width alpha for the perceptual `roughness` parameter r in [0, 1]: alpha = r^2 (Burley
  /// 2012, "Physically-Based Shading at Disney"), so that roughness 0.5 looks halfway rough.
  static constexpr float roughness_to_alpha(float roughness) { return roughness * roughness; }

  /// An isotropic distribution of width alpha.
  explicit MicrofacetDistribution(float alpha) : MicrofacetDistribution(alpha, alpha) {}
  /// An anisotropic distribution of widths alpha_x, alpha_y (clamped below to 1e-4 for robust
  /// arithmetic; effectively_smooth() tells callers to use a delta lobe instead).
  MicrofacetDistribution(float alpha_x, float alpha_y);

  /// Width along the local x axis.
  float alpha_x() const { return alpha_x_; }
  /// Width along the local y axis.
  float alpha_y() const { return alpha_y_; }
  /// True when both widths are below kSmoothAlpha: callers should scatter specularly.
  bool effectively_smooth() const { return alpha_x_ < kSmoothAlpha && alpha_y_ < kSmoothAlpha; }

  /// Microfacet normal density D(h) per unit solid angle, normalised so that the integral of
  /// D(h) h.z over the hemisphere is 1; zero for h.z <= 0.
  float d(Vec3 h) const;
  /// Smith's Lambda(w) (Heitz 2014): the masking term's auxiliary function; depends only
  /// on |w.z|, so it serves both sides of the surface.
  float lambda(Vec3 w) const;
  /// Smith masking G1(w) = 1 / (1 + Lambda(w)) of microfacets that face w.
  float g1(Vec3 w) const { return 1.0f / (1.0f + lambda(w)); }
  /// Height-correlated masking-shadowing for reflection, wo and wi on the same side
  /// (Heitz 2014): 1 / (1 + Lambda(wo) + Lambda(wi)).
  float g2_reflection(Vec3 wo, Vec3 wi) const { return 1.0f / (1.0f + lambda(wo) + lambda(wi)); }
  /// Height-correlated masking-shadowing for transmission, wo and wi on opposite sides
  /// (Heitz 2014): the Beta function B(1 + Lambda(wo), 1 + Lambda(wi)), which is
  /// smaller than G1(wo) G1(wi) since high microfacets are seen from above, low ones from below.
  float g2_transmission(Vec3 wo, Vec3 wi) const;

  /// Density of visible normals D_w(h) = G1(w) max(0, w.h) D(h) / w.z for a view direction with
  /// w.z > 0 (Heitz 2014); zero when w.z <= 0.
  float d_visible(Vec3 w, Vec3 h) const;
  /// Draws a microfacet normal from D_w for a view direction with w.z > 0 (Heitz 2018, "Sampling
  /// the GGX Distribution of Visible Normals", JCGT 7(4)).
  Vec3 sample_visible(Vec3 w, Vec2 u) const;

 private:
  float alpha_x_, alpha_y_;
};

/// Reads the material parameter "roughness" (in [0, 1], default 0.3); InputError outside.
float read_roughness(const SceneParams& params);

/// Mirror reflection of w about the unit normal n.
inline Vec3 reflect(Vec3 w, Vec3 n) {
  return n * (2.0f * dot(w, n)) - w;
}

}  // namespace penumbra
