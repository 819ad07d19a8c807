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
/// front side (the geometric normal's) or from both sides. Its primitives are grouped into
/// sampling units: two consecutive triangles of a mesh that form a parallelogram (a quad as a
/// modeller triangulates it: they share an edge and the other two vertices are its mirror
/// images) are one unit, every other primitive is a unit of its own. sample_li picks one unit in
/// proportion to its area, then samples it by its own strategy:
///  - a sphere seen from outside: uniform in the cone it subtends (pbrt-v4 Sphere::Sample; Shirley,
///    Wang 1994), density 1 / (2 pi (1 - cos theta_max)); from inside, on the surface or within
///    0.1% of the radius of it: by area;
///  - a rectangle (a parallelogram with perpendicular edges) whose solid angle is in
///    [kMinSphericalSolidAngle, kMaxSphericalSolidAngle]: uniform in solid angle (Urena, Fajardo,
///    King 2013, "An Area-Preserving Parametrization for Spherical Rectangles"), density 1 / Omega;
///  - everything else (triangles, pairs of triangles, skewed parallelograms, rectangles seen at a
///    tiny or almost hemispherical solid angle): a uniform point by area, density
///    d^2 / (|cos theta_l| A_u) for a unit of area A_u. A pair is sampled as its parallelogram,
///    linearly in both numbers: stratified numbers stay stratified over the whole quad (two
///    triangles each warped by a square root would not), it costs no square root, and the density
///    is the same uniform density by area as the two triangles sampled apart.
/// pdf_li(p, wi, hit) = P(unit of hit.prim) * that unit's density, exactly the density of
/// sample_li in the path-space sense (the point hit is the point that would have been sampled).
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
  /// Probability that a sample lands on world primitive `prim` (zero outside this light).
  float prim_pmf(uint32_t prim) const;
  /// Number of sampling units (primitives, with pairs of triangles that form a parallelogram
  /// counted once).
  size_t unit_count() const { return units_.size(); }

  // For shaders of many paths at once (path's lanes), which sample planar units eight at a time
  // with the same operations as sample_li.
  enum class UnitKind : uint8_t {
    kTriangle,       ///< o, e1, e2 as the triangle's vertex 0 and its two edges from it
    kParallelogram,  ///< o + s e1 + t e2, s, t in [0, 1]: a quad or a pair of triangles
    kRectangle,      ///< a quad with perpendicular edges: spherical-rectangle candidate
    kSphere,
  };
  /// One sampling unit: its geometry (time 0: emitters never move) and area.
  struct Unit {
    Vec3 o, e1, e2;
    Vec3 n;  ///< unit front normal (planar units)
    float area = 0;
    UnitKind kind = UnitKind::kTriangle;
  };
  /// The unit chosen by a number u and u's remainder, uniform in [0, 1).
  struct Picked {
    uint32_t unit;
    float u;
  };
  /// Inverts the CDF (a binary search without branches: the step that u falls in is as
  /// unpredictable as u), then stretches that step back to [0, 1): the map from [0, 1)^2 to the
  /// surface stays continuous and area-preserving, so stratified u stay stratified. Inline: an
  /// out-of-line call, with its remainder returned through memory, cost 2 % of a Cornell box
  /// render.
  Picked pick(float u) const {
    const float* base = cdf_.data();
    size_t len = cdf_.size();
    while (len > 1) {
      const size_t half = len / 2;
      base += size_t(base[half - 1] <= u) * half;  // a flag times a step: no branch
      len -= half;
    }
    const size_t i = std::min(size_t(base - cdf_.data()) + (*base <= u), cdf_.size() - 1);
    return {uint32_t(i), std::clamp((u - cdf_lo_[i]) * inv_pmf_[i], 0.0f, 0x1.fffffep-1f)};
  }
  /// Sampling unit i.
  const Unit& unit(size_t i) const { return units_[i]; }
  /// P(unit i), as sample_li multiplies it into its density.
  float unit_pmf(size_t i) const { return pmf_[i]; }
  /// What pick() reads of unit i: the CDF at its end and its start, and 1 / P(unit i).
  float unit_cdf(size_t i) const { return cdf_[i]; }
  float unit_cdf_lo(size_t i) const { return cdf_lo_[i]; }
  float unit_inv_pmf(size_t i) const { return inv_pmf_[i]; }
  /// The constant emitted radiance.
  Rgb radiance() const { return radiance_; }

 private:
  /// A uniform point q on unit `unit` by area, with its unit front normal n.
  void sample_area(const Unit& unit, Vec2 u, Vec3& q, Vec3& n) const;
  /// True when the receiver at p sees the unit by its solid-angle strategy.
  bool solid_angle_sampled(const Unit& unit, Vec3 p, float* solid_angle_pdf) const;
  /// Density d^2 / (|cos| A_u) of area sampling the unit at point q (normal n) from p.
  static float area_density(const Unit& unit, Vec3 p, Vec3 q, Vec3 n);
  /// The same from the squared distance and the cosine at the light (zero when it is 0).
  static float area_density(const Unit& unit, float dist2, float cos_l);

  uint32_t first_prim_ = 0;
  std::vector<Unit> units_;
  std::vector<float> cdf_;            ///< cumulative area fractions, per unit
  std::vector<float> pmf_;            ///< P(unit) = difference of cdf_ (zero when degenerate)
  std::vector<float> inv_pmf_;        ///< 1 / pmf_ (zero for a degenerate unit, never picked)
  std::vector<float> cdf_lo_;         ///< where each unit's step starts: cdf_[i - 1], or 0
  std::vector<uint32_t> prim_unit_;   ///< the unit of each primitive of the emitter
  std::vector<float> prim_fraction_;  ///< the primitive's share of its unit's area
  Rgb radiance_;
  bool two_sided_;
  float area_ = 0;
};

}  // namespace penumbra
