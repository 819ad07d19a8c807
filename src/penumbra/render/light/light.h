#pragma once
/// Light sources: the operations unbiased light transport needs (pbrt-v4's Light interface:
/// SampleLi, PDF_Li, L, Le, SampleLe, PDF_Le, Phi; Mitsuba 3's Emitter).
#include <cmath>
#include <cstdint>

#include "penumbra/core/bounds.h"
#include "penumbra/core/color.h"
#include "penumbra/core/ray.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// What kind of light: delta lights are sampled exactly and never hit by rays; area lights sit on
/// the scene's emissive shapes; infinite lights surround the scene.
enum class LightKind : uint8_t {
  kDeltaPosition,   ///< a point: one direction per receiver, no density
  kDeltaDirection,  ///< a direction from infinitely far away (the sun)
  kArea,            ///< an emissive shape, hit by rays
  kInfinite,        ///< radiance arriving from every direction (environment)
};

/// Incident light at a point from one sample of a light.
struct LightSample {
  Vec3 wi;             ///< unit direction from the shading point towards the light
  float distance = 0;  ///< distance to the sampled light point (for the shadow ray; kInfinity
                       ///< for infinite and directional lights)
  Rgb li;              ///< incident radiance (for a delta light: intensity / distance^2)
  float pdf = 0;       ///< solid-angle density of wi (1 for a delta light)
  bool delta = false;  ///< a delta light: no density, one sample is exact
};

/// A point on an area light, as a ray found it: what pdf_li and l need.
struct LightPoint {
  Vec3 p;             ///< the point
  Vec3 n;             ///< unit geometric normal (the emitting side is where it points)
  uint32_t prim = 0;  ///< primitive id in the world
};

/// A ray leaving a light (for photons and light paths).
struct LightLeSample {
  Ray ray;             ///< origin on the light, unit direction
  Vec3 n;              ///< unit surface normal at the origin (zero for points and infinite lights)
  Rgb l;               ///< radiance along the ray (delta position: intensity)
  float pdf_pos = 0;   ///< density of the origin (per area; 1 for a point light)
  float pdf_dir = 0;   ///< density of the direction (per solid angle; 1 for a directional light)
  /// The power-weighted radiance l |cos| / (pdf_pos pdf_dir): what a photon carries (before
  /// dividing by the number of photons).
  Rgb beta() const {
    const float c = dot(n, n) > 0.0f ? std::fabs(dot(n, ray.d)) : 1.0f;
    return pdf_pos > 0.0f && pdf_dir > 0.0f ? l * (c / (pdf_pos * pdf_dir)) : Rgb{};
  }
};

/// A light source. Implementations are immutable and thread-safe once `preprocess` has run.
class Light {
 public:
  virtual ~Light() = default;
  /// The light's kind.
  virtual LightKind kind() const = 0;
  /// Called once when the scene's bounds are known (infinite and directional lights need them).
  virtual void preprocess(const Bounds3& /*scene_bounds*/) {}
  /// Samples the light as seen from point `p` with the uniform pair `u`.
  virtual LightSample sample_li(Vec3 p, Vec2 u) const = 0;
  /// Solid-angle density with which sample_li from `p` would pick direction `wi`; for area lights
  /// `hit` is the point of this light that the ray along wi reached (ignored by other kinds).
  /// Zero for delta lights.
  virtual float pdf_li(Vec3 p, Vec3 wi, const LightPoint& hit) const = 0;
  /// Radiance an area light emits from its point `hit` towards the unit direction `w` (zero
  /// behind a one-sided emitter; zero for other kinds).
  virtual Rgb l(const LightPoint& /*hit*/, Vec3 /*w*/) const { return {}; }
  /// Radiance an infinite light sends along a ray that left the scene (zero for other kinds).
  virtual Rgb le(const Ray& /*ray*/) const { return {}; }
  /// Samples an emitted ray with two uniform pairs and the time of the ray.
  virtual LightLeSample sample_le(Vec2 u_pos, Vec2 u_dir, float time) const = 0;
  /// Densities of emitting `ray` (origin on the light, normal n there for area lights).
  virtual void pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const = 0;
  /// Total emitted power (W, per channel).
  virtual Rgb power() const = 0;

  /// True for point and directional lights.
  bool is_delta() const {
    return kind() == LightKind::kDeltaPosition || kind() == LightKind::kDeltaDirection;
  }
};

}  // namespace penumbra
