#include "penumbra/render/light/area_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/core/dvec3.h"
#include "penumbra/render/sampling.h"

namespace penumbra {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// The spherical rectangle's set-up is in double: its solid angle is a difference of angles that
// sum to about 2 pi, and float would leave too few digits at small solid angles.
/// A rectangle o + s ex + t ey (s in [0, |e1|], t in [0, |e2|]) seen from a point, set up for
/// uniform solid-angle sampling (Urena, Fajardo, King 2013, "An Area-Preserving Parametrization for
/// Spherical Rectangles"). In the local frame (ex, ey, ez) centred at the receiver the rectangle
/// spans [x0, x1] x [y0, y1] at height z0 < 0 (ez flipped as needed).
struct SphericalRect {
  SphericalRect(Vec3 p, const QuadData& q) : o(DVec3(p)) {
    ex = normalize(DVec3(q.e1));
    const DVec3 e2 = DVec3(q.e2);
    ey = e2 - ex * dot(e2, ex);  // Gram-Schmidt: exact for a rectangle up to rounding
    const double eyl = std::sqrt(dot(ey, ey));
    ey = ey * (1.0 / eyl);
    ez = cross(ex, ey);
    const DVec3 d = DVec3(q.p) - o;
    x0 = dot(d, ex), y0 = dot(d, ey), z0 = dot(d, ez);
    if (z0 > 0) ez = ez * -1.0, z0 = -z0;
    x1 = x0 + std::sqrt(dot(DVec3(q.e1), DVec3(q.e1))), y1 = y0 + eyl;
    if (!(z0 < 0)) return;  // in the rectangle's plane: no solid angle
    // Interior angles at the corners, as atan2(|sin|, cos) of the edge planes' normals, which
    // keeps full precision for angles near 0 and pi (where acos would not).
    const double az = -z0, z2 = z0 * z0;
    const auto len = [&](double a, double b) { return std::sqrt(a * a + b * b + z2); };
    const double g0 = std::atan2(az * len(x1, y0), y0 * x1);
    const double g1 = std::atan2(az * len(x1, y1), -x1 * y1);
    const double g2 = std::atan2(az * len(x0, y1), x0 * y1);
    const double g3 = std::atan2(az * len(x0, y0), -x0 * y0);
    b0 = -y0 / std::sqrt(y0 * y0 + z2);
    b1 = y1 / std::sqrt(y1 * y1 + z2);
    k = 2.0 * std::numbers::pi - g2 - g3;
    solid_angle = g0 + g1 - k;
  }

  /// The point of the rectangle in the direction that maps to u (uniform in solid angle).
  Vec3 sample(Vec2 u) const {
    // The x coordinate from the first number: the sub-rectangle [x0, xu] has solid angle u Omega.
    const double au = double(u.x) * solid_angle + k;
    const double fu = (std::cos(au) * b0 - b1) / std::sin(au);
    const double cu = std::clamp(std::copysign(1.0 / std::sqrt(fu * fu + b0 * b0), fu), -1.0, 1.0);
    double xu = -(cu * z0) / std::sqrt(std::fmax(0.0, 1.0 - cu * cu));
    xu = xu >= x0 ? (xu <= x1 ? xu : x1) : x0;  // also catches a NaN
    // The y coordinate from the second number, uniform in the height of the projected segment.
    const double dd = std::sqrt(xu * xu + z0 * z0);
    const double h0 = y0 / std::sqrt(dd * dd + y0 * y0), h1 = y1 / std::sqrt(dd * dd + y1 * y1);
    const double hv = h0 + double(u.y) * (h1 - h0), hv2 = hv * hv;
    const double yv = hv2 < 1.0 - 1e-12 ? hv * dd / std::sqrt(1.0 - hv2) : y1;
    const DVec3 q = {o.x + ex.x * xu + ey.x * yv + ez.x * z0,
                     o.y + ex.y * xu + ey.y * yv + ez.y * z0,
                     o.z + ex.z * xu + ey.z * yv + ez.z * z0};
    return {float(q.x), float(q.y), float(q.z)};
  }

  DVec3 o, ex, ey, ez;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0, z0 = 0, b0 = 0, b1 = 0, k = 0;
  double solid_angle = 0;
};

/// The cone from `p` around a sphere that p is clearly outside of: its axis, sin^2 and 1 - cos of
/// its half-angle (the latter as sin^2 / (1 + cos), free of cancellation for small spheres).
struct SphereCone {
  SphereCone(Vec3 p, const SphereData& s) {
    const Vec3 d = s.center - p;
    dist2 = dot(d, d);
    r2 = s.radius * s.radius;
    // Only points clearly outside: on the surface (a receiver on the emitter itself, its position
    // rounded to either side) the near cap would shrink to the point itself; area sampling is
    // right there. The slack covers the rounding of points far from the origin.
    const float rs = s.radius * 1.001f + 1e-5f * max_component(abs(s.center));
    if (!(dist2 > rs * rs)) return;
    axis = d / std::sqrt(dist2);
    const float sin2_max = r2 / dist2;
    one_minus_cos_max = sin2_max / (1.0f + std::sqrt(std::fmax(0.0f, 1.0f - sin2_max)));
    outside = one_minus_cos_max > 0.0f;
  }
  /// Uniform density in the cone.
  float pdf() const { return 1.0f / (2.0f * kPi * one_minus_cos_max); }

  Vec3 axis;
  float dist2 = 0, r2 = 0, one_minus_cos_max = 0;
  bool outside = false;
};

}  // namespace

AreaLight::AreaLight(const World& world, const Emitter& e)
    : world_(world), first_prim_(e.first_prim), radiance_(e.radiance), two_sided_(e.two_sided) {
  const PrimitiveSet& prims = world.primitives();
  std::vector<double> sums;
  double sum = 0;
  for (uint32_t id = e.first_prim; id < e.first_prim + e.prim_count; ++id) {
    float a = 0;
    bool rect = false;
    if (prims.kind(id) == PrimKind::kSphere) {
      a = 4.0f * kPi * prims.sphere(id).radius * prims.sphere(id).radius;
    } else {
      a = length(world.area_normal(id));
      if (prims.kind(id) == PrimKind::kQuad) {
        const QuadData& q = prims.quad(id);
        rect = std::fabs(dot(q.e1, q.e2)) <= 1e-4f * length(q.e1) * length(q.e2);
      }
    }
    if (!(a > 0.0f) || !std::isfinite(a)) a = 0.0f;  // degenerate primitives emit nothing
    sum += a;
    areas_.push_back(a);
    normals_.push_back(a > 0.0f && prims.kind(id) != PrimKind::kSphere
                           ? normalize(world.area_normal(id))
                           : Vec3{});
    rects_.push_back(rect);
    sums.push_back(sum);
  }
  area_ = float(sum);
  if (!(sum > 0.0)) {
    areas_.clear(), rects_.clear(), normals_.clear();  // nothing to sample
    return;
  }
  // Exactly 1 from the last primitive of non-zero area on: degenerate ones never get a step.
  for (double c : sums) cdf_.push_back(c == sum ? 1.0f : float(c / sum));
  // P(primitive) as the CDF's steps, so that pick() and prim_pmf() agree to the bit.
  for (size_t i = 0; i < cdf_.size(); ++i) pmf_.push_back(cdf_[i] - (i ? cdf_[i - 1] : 0.0f));
}

float AreaLight::prim_pmf(uint32_t prim) const {
  const uint32_t i = prim - first_prim_;  // wraps for prim < first_prim_
  return i < pmf_.size() ? pmf_[i] : 0.0f;
}

void AreaLight::sample_area(uint32_t local, Vec2 u, Vec3& q, Vec3& n) const {
  const uint32_t id = first_prim_ + local;
  const PrimitiveSet& prims = world_.primitives();
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      // Uniform barycentrics (Shirley 1990 / pbrt's square-root mapping).
      const Vec3* v = prims.triangle(id);
      const float s = std::sqrt(u.x);
      const float b1 = 1.0f - s, b2 = u.y * s;
      q = v[0] * (1.0f - b1 - b2) + v[1] * b1 + v[2] * b2;
      n = normals_[local];
      break;
    }
    case PrimKind::kQuad: {
      const QuadData& d = prims.quad(id);
      q = d.p + d.e1 * u.x + d.e2 * u.y;
      n = normals_[local];
      break;
    }
    case PrimKind::kSphere: {
      const SphereData& s = prims.sphere(id);
      n = sample_uniform_sphere(u);
      q = s.center + n * s.radius;
      break;
    }
  }
}

bool AreaLight::solid_angle_sampled(uint32_t local, Vec3 p, float* pdf) const {
  const uint32_t id = first_prim_ + local;
  const PrimitiveSet& prims = world_.primitives();
  if (prims.kind(id) == PrimKind::kSphere) {
    const SphereCone cone(p, prims.sphere(id));
    if (cone.outside) *pdf = cone.pdf();
    return cone.outside;
  }
  if (!rects_[local]) return false;
  const SphericalRect rect(p, prims.quad(id));
  const bool use =
      rect.solid_angle >= kMinSphericalSolidAngle && rect.solid_angle <= kMaxSphericalSolidAngle;
  if (use) *pdf = float(1.0 / rect.solid_angle);
  return use;
}

float AreaLight::area_density(uint32_t local, Vec3 p, Vec3 q, Vec3 n) const {
  const Vec3 d = q - p;
  const float dist2 = dot(d, d);
  const float cos_l = std::fabs(dot(n, d)) / std::sqrt(dist2);
  if (!(cos_l > 0.0f)) return 0.0f;
  return dist2 / (cos_l * areas_[local]);
}

LightSample AreaLight::sample_li(Vec3 p, Vec2 u) const {
  if (pmf_.empty()) return {};
  // The primitive by area, then a point of it by its own strategy.
  const Picked pk = pick(u.x);
  const uint32_t local = pk.local;
  const Vec2 v{pk.u, u.y};
  const uint32_t id = first_prim_ + local;
  const PrimitiveSet& prims = world_.primitives();
  LightSample ls;
  Vec3 q, n;
  float pdf = 0;
  bool sphere_cone = false;
  if (prims.kind(id) == PrimKind::kSphere) {
    const SphereCone cone(p, prims.sphere(id));
    if (cone.outside) {
      // A direction uniform in the cone, then the near intersection with the sphere, in the
      // form (d^2 - r^2) / (d cos + sqrt(r^2 - d^2 sin^2)) that does not cancel.
      const float one_minus_cos = v.x * cone.one_minus_cos_max;
      const float cos_t = 1.0f - one_minus_cos;
      const float sin2_t = one_minus_cos * (2.0f - one_minus_cos);
      const float sin_t = std::sqrt(sin2_t), phi = 2.0f * kPi * v.y;
      Vec3 t, b;
      orthonormal_basis(cone.axis, t, b);
      ls.wi = t * (sin_t * std::cos(phi)) + b * (sin_t * std::sin(phi)) + cone.axis * cos_t;
      const float dist = std::sqrt(cone.dist2);
      ls.distance = (cone.dist2 - cone.r2) /
                    (dist * cos_t + std::sqrt(std::fmax(0.0f, cone.r2 - cone.dist2 * sin2_t)));
      pdf = cone.pdf();
      sphere_cone = true;
    }
  } else if (rects_[local]) {
    const SphericalRect rect(p, prims.quad(id));
    if (rect.solid_angle >= kMinSphericalSolidAngle &&
        rect.solid_angle <= kMaxSphericalSolidAngle) {
      q = rect.sample(v);
      n = normals_[local];
      pdf = float(1.0 / rect.solid_angle);
    }
  }
  if (!sphere_cone) {
    if (!(pdf > 0.0f)) sample_area(local, v, q, n);
    const Vec3 d = q - p;
    ls.distance = length(d);
    if (!(ls.distance > 0.0f)) return {};
    ls.wi = d / ls.distance;
    // Only the emitting side: a one-sided light seen from behind gives nothing.
    const float cos_l = dot(n, -ls.wi);
    if (!(two_sided_ ? cos_l != 0.0f : cos_l > 0.0f)) return {};
    if (!(pdf > 0.0f)) pdf = area_density(local, p, q, n);
  }
  if (!(pdf > 0.0f) || !std::isfinite(pdf)) return {};
  ls.li = radiance_;
  ls.pdf = pmf_[local] * pdf;
  return ls;
}

float AreaLight::pdf_li(Vec3 p, Vec3, const LightPoint& hit) const {
  const float pmf = prim_pmf(hit.prim);
  if (!(pmf > 0.0f)) return 0.0f;
  const uint32_t local = hit.prim - first_prim_;
  float pdf = 0;
  if (world_.primitives().kind(hit.prim) == PrimKind::kSphere &&
      solid_angle_sampled(local, p, &pdf))
    return pmf * pdf;  // seen from outside: the near cap, always its front
  // Planar primitives and spheres seen from inside: only the emitting side is ever sampled.
  if (!two_sided_ && !(dot(hit.n, p - hit.p) > 0.0f)) return 0.0f;
  if (!solid_angle_sampled(local, p, &pdf)) pdf = area_density(local, p, hit.p, hit.n);
  return pmf * pdf;
}

Rgb AreaLight::l(const LightPoint& hit, Vec3 w) const {
  return two_sided_ || dot(hit.n, w) > 0.0f ? radiance_ : Rgb{};
}

LightLeSample AreaLight::sample_le(Vec2 u_pos, Vec2 u_dir, float time) const {
  LightLeSample s;
  if (pmf_.empty()) return s;
  const Picked pk = pick(u_pos.x);
  const uint32_t local = pk.local;
  const Vec2 v{pk.u, u_pos.y};
  Vec3 q, n;
  sample_area(local, v, q, n);
  // Two-sided: the side by the first coordinate, reused as a fresh uniform number.
  float ux = u_dir.x;
  if (two_sided_) {
    if (ux < 0.5f) {
      ux = std::fmin(ux * 2.0f, kOneMinusEpsilon);
    } else {
      ux = std::fmin((ux - 0.5f) * 2.0f, kOneMinusEpsilon);
      n = -n;
    }
  }
  const Vec3 local_dir = sample_cosine_hemisphere({ux, u_dir.y});
  Vec3 t, b;
  orthonormal_basis(n, t, b);
  s.ray.o = q;
  s.ray.d = t * local_dir.x + b * local_dir.y + n * local_dir.z;
  s.ray.time = time;
  s.n = n;
  s.l = radiance_;
  s.pdf_pos = 1.0f / area_;
  s.pdf_dir = local_dir.z * std::numbers::inv_pi_v<float> * (two_sided_ ? 0.5f : 1.0f);
  return s;
}

void AreaLight::pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const {
  pdf_pos = area_ > 0.0f ? 1.0f / area_ : 0.0f;
  const float c = dot(n, normalize(ray.d));
  if (two_sided_)
    pdf_dir = std::fabs(c) * std::numbers::inv_pi_v<float> * 0.5f;
  else
    pdf_dir = c > 0.0f ? c * std::numbers::inv_pi_v<float> : 0.0f;
}

Rgb AreaLight::power() const {
  return radiance_ * (kPi * area_ * (two_sided_ ? 2.0f : 1.0f));
}

}  // namespace penumbra
