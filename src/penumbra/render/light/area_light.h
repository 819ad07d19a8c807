#pragma once
/// Area lights: the emissive shapes of the scene, sampled by solid angle where that is cheap and
/// exact (spheres, rectangles) and by area elsewhere.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "penumbra/render/light/light.h"
#include "penumbra/render/world.h"

namespace penumbra {

/// An emissive shape (triangles, parallelograms, spheres) of constant radiance L, emitting from its
/// front side (the geometric normal's) or from both sides. sample_li picks one primitive in
/// proportion to its area, then samples it by its own strategy:
///  - a sphere seen from outside: uniform in the cone it subtends (pbrt-v4 Sphere::Sample; Shirley,
///    Wang 1994), density 1 / (2 pi (1 - cos theta_max)); from inside, on the surface or within
///    0.1% of the radius of it: by area;
///  - a rectangle (a parallelogram with perpendicular edges) whose solid angle is in
///    [kMinSphericalSolidAngle, kMaxSphericalSolidAngle]: uniform in solid angle (Urena, Fajardo,
///    King 2013, "An Area-Preserving Parametrization for Spherical Rectangles"), density 1 / Omega;
///  - everything else (triangles, skewed parallelograms, rectangles seen at a tiny or almost
///    hemispherical solid angle): a uniform point by area, density d^2 / (|cos theta_l| A_i).
/// pdf_li(p, wi, hit) = P(hit.prim) * that primitive's density, exactly the density of sample_li
/// in the path-space sense (the point hit is the point that would have been sampled).
class AreaLight final : public Light {
 public:
  /// Below this solid angle (sr) a rectangle is sampled by area: its area density is then almost
  /// proportional to solid angle already, and area sampling is cheaper (pbrt-v4's
  /// MinSphericalSampleArea).
  static constexpr float kMinSphericalSolidAngle = 3e-4f;
  /// Above this solid angle (the receiver almost in the rectangle's plane, over it) the spherical
  /// parametrization loses precision; sampled by area instead (pbrt-v4's MaxSphericalSampleArea).
  static constexpr float kMaxSphericalSolidAngle = 6.22f;

  AreaLight(const World& world, const Emitter& emitter);
  LightKind kind() const override { return LightKind::kArea; }
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  float pdf_li(Vec3 p, Vec3 wi, const LightPoint& hit) const override;
  Rgb l(const LightPoint& hit, Vec3 w) const override;
  /// A uniform point on the emitting area and a cosine-distributed direction on its emitting
  /// side (either side with probability 1/2 when two-sided).
  LightLeSample sample_le(Vec2 u_pos, Vec2 u_dir, float time) const override;
  /// pdf_pos = 1 / A; pdf_dir = |cos| / pi on an emitting side (halved when two-sided).
  void pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const override;
  /// pi A L, twice that when two-sided.
  Rgb power() const override;
  /// True when both sides emit.
  bool two_sided() const { return two_sided_; }
  /// Total emitting area.
  float area() const { return area_; }
  /// Probability that a sample picks world primitive `prim` (zero outside this light).
  float prim_pmf(uint32_t prim) const;

 private:
  /// The primitive chosen by a number u and u's remainder, uniform in [0, 1).
  struct Picked {
    uint32_t local;  ///< prim id - first_prim_
    float u;
  };
  /// Inverts the CDF, then stretches the step that u fell in back to [0, 1): the map from
  /// [0, 1)^2 to the surface stays continuous and area-preserving, so stratified u stay
  /// stratified. Inline: an out-of-line call, with its remainder returned through memory, cost
  /// 2 % of a Cornell box render.
  Picked pick(float u) const {
    const size_t n = cdf_.size();
    const size_t i =
        std::min(size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin()), n - 1);
    const float lo = i ? cdf_[i - 1] : 0.0f;
    return {uint32_t(i), std::clamp((u - lo) / pmf_[i], 0.0f, 0x1.fffffep-1f)};
  }
  /// A uniform point q on primitive `local` by area, with its unit front normal n.
  void sample_area(uint32_t local, Vec2 u, Vec3& q, Vec3& n) const;
  /// True when the receiver at p sees primitive `local` by its solid-angle strategy.
  bool solid_angle_sampled(uint32_t local, Vec3 p, float* solid_angle_pdf) const;
  /// Density d^2 / (|cos| A_i) of area sampling primitive `local` at point q (normal n) from p.
  float area_density(uint32_t local, Vec3 p, Vec3 q, Vec3 n) const;

  const World& world_;
  uint32_t first_prim_ = 0;
  std::vector<float> cdf_;      ///< cumulative area fractions, per primitive of the emitter
  std::vector<float> pmf_;      ///< P(primitive) = difference of cdf_ (zero when degenerate)
  std::vector<float> areas_;    ///< area of each primitive
  std::vector<uint8_t> rects_;  ///< 1 for a rectangle (spherical-rectangle candidate)
  std::vector<Vec3> normals_;   ///< unit front normal of each planar primitive (computed once)
  Rgb radiance_;
  bool two_sided_;
  float area_ = 0;
};

}  // namespace penumbra
