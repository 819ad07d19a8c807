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

/// Whether triangles a and b (vertices in their winding order, unit front normals na, nb) form a
/// parallelogram: two shared vertices s0, s1 and the others x (of a) and y (of b) mirror images
/// through the shared edge's midpoint, x + y = s0 + s1, within rounding, with the same front
/// side. Then the parallelogram is x + s (s0 - x) + t (s1 - x), s, t in [0, 1].
bool parallelogram_pair(const Vec3* a, const Vec3* b, Vec3 na, Vec3 nb, Vec3& o, Vec3& e1,
                        Vec3& e2) {
  int shared = 0, x = -1, y = -1;
  bool in_b[3] = {false, false, false};
  for (int i = 0; i < 3; ++i) {
    bool found = false;
    for (int j = 0; j < 3; ++j)
      if (!in_b[j] && a[i] == b[j]) in_b[j] = found = true;
    if (found)
      ++shared;
    else
      x = i;
  }
  if (shared != 2) return false;
  for (int j = 0; j < 3; ++j)
    if (!in_b[j]) y = j;
  const Vec3 s0 = a[(x + 1) % 3], s1 = a[(x + 2) % 3];
  e1 = s0 - a[x], e2 = s1 - a[x], o = a[x];
  // Rounding of the vertices of a quad far from the origin can leave x + y a few ulps from
  // s0 + s1; a larger gap is a different shape (then the triangles stay apart).
  const Vec3 gap = a[x] + b[y] - s0 - s1;
  const float tol = 1e-6f * (length(e1) + length(e2));
  return length(gap) <= tol && dot(na, nb) > 0.99999f;
}

}  // namespace

AreaLight::AreaLight(const World& world, const Emitter& e)
    : first_prim_(e.first_prim), radiance_(e.radiance), two_sided_(e.two_sided) {
  const PrimitiveSet& prims = world.primitives();
  const uint32_t count = uint32_t(e.prim_count);
  std::vector<float> prim_area(count, 0.0f);
  std::vector<Vec3> prim_normal(count);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t id = first_prim_ + i;
    float a = 0;
    if (prims.kind(id) == PrimKind::kSphere) {
      a = 4.0f * kPi * prims.sphere(id).radius * prims.sphere(id).radius;
    } else {
      a = length(world.area_normal(id));
      if (a > 0.0f) prim_normal[i] = normalize(world.area_normal(id));
    }
    prim_area[i] = a > 0.0f && std::isfinite(a) ? a : 0.0f;  // degenerate: emits nothing
  }
  prim_unit_.assign(count, 0);
  prim_fraction_.assign(count, 1.0f);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t id = first_prim_ + i;
    Unit u;
    u.area = prim_area[i];
    u.n = prim_normal[i];
    switch (prims.kind(id)) {
      case PrimKind::kTriangle: {
        const Vec3* v = prims.triangle(id);
        u.o = v[0], u.e1 = v[1] - v[0], u.e2 = v[2] - v[0];
        Vec3 o, e1, e2;
        if (i + 1 < count && prims.kind(id + 1) == PrimKind::kTriangle && u.area > 0.0f &&
            prim_area[i + 1] > 0.0f &&
            parallelogram_pair(v, prims.triangle(id + 1), prim_normal[i], prim_normal[i + 1], o, e1,
                               e2)) {
          u.kind = UnitKind::kParallelogram;
          u.o = o, u.e1 = e1, u.e2 = e2;
          u.area = prim_area[i] + prim_area[i + 1];
          prim_unit_[i] = prim_unit_[i + 1] = uint32_t(units_.size());
          prim_fraction_[i] = prim_area[i] / u.area;
          prim_fraction_[i + 1] = prim_area[i + 1] / u.area;
          units_.push_back(u);
          ++i;
          continue;
        }
        break;
      }
      case PrimKind::kQuad: {
        const QuadData& q = prims.quad(id);
        u.o = q.p, u.e1 = q.e1, u.e2 = q.e2;
        const bool rect = std::fabs(dot(q.e1, q.e2)) <= 1e-4f * length(q.e1) * length(q.e2);
        u.kind = rect ? UnitKind::kRectangle : UnitKind::kParallelogram;
        break;
      }
      case PrimKind::kSphere: {
        const SphereData& sd = prims.sphere(id);
        u.o = sd.center, u.e1 = {sd.radius, 0, 0};
        u.kind = UnitKind::kSphere;
        break;
      }
    }
    prim_unit_[i] = uint32_t(units_.size());
    units_.push_back(u);
  }
  double sum = 0;
  std::vector<double> sums;
  for (const Unit& u : units_) sums.push_back(sum += u.area);
  area_ = float(sum);
  if (!(sum > 0.0)) {
    units_.clear(), prim_unit_.clear(), prim_fraction_.clear();  // nothing to sample
    return;
  }
  // Exactly 1 from the last unit of non-zero area on: degenerate ones never get a step.
  for (double c : sums) cdf_.push_back(c == sum ? 1.0f : float(c / sum));
  // P(unit) as the CDF's steps, so that pick() and pdf_li() agree to the bit.
  for (size_t i = 0; i < cdf_.size(); ++i) pmf_.push_back(cdf_[i] - (i ? cdf_[i - 1] : 0.0f));
  for (float p : pmf_) inv_pmf_.push_back(p > 0.0f ? 1.0f / p : 0.0f);
  for (size_t i = 0; i < cdf_.size(); ++i) cdf_lo_.push_back(i ? cdf_[i - 1] : 0.0f);
}

float AreaLight::prim_pmf(uint32_t prim) const {
  const uint32_t i = prim - first_prim_;  // wraps for prim < first_prim_
  return i < prim_unit_.size() ? pmf_[prim_unit_[i]] * prim_fraction_[i] : 0.0f;
}

// Inline (only this file calls it): out of line, q and n came back through memory, stored
// float by float and loaded in pairs, which the store buffer cannot forward.
[[gnu::always_inline]] inline void AreaLight::sample_area(const Unit& unit, Vec2 u, Vec3& q,
                                                          Vec3& n) const {
  switch (unit.kind) {
    case UnitKind::kTriangle: {
      // Uniform barycentrics (Shirley 1990 / pbrt's square-root mapping).
      const float s = std::sqrt(u.x);
      q = unit.o + unit.e1 * (1.0f - s) + unit.e2 * (u.y * s);
      n = unit.n;
      break;
    }
    case UnitKind::kParallelogram:
    case UnitKind::kRectangle:
      q = unit.o + unit.e1 * u.x + unit.e2 * u.y;
      n = unit.n;
      break;
    case UnitKind::kSphere:
      n = sample_uniform_sphere(u);
      q = unit.o + n * unit.e1.x;
      break;
  }
}

bool AreaLight::solid_angle_sampled(const Unit& unit, Vec3 p, float* pdf) const {
  if (unit.kind == UnitKind::kSphere) {
    const SphereCone cone(p, {unit.o, unit.e1.x});
    if (cone.outside) *pdf = cone.pdf();
    return cone.outside;
  }
  if (unit.kind != UnitKind::kRectangle) return false;
  const SphericalRect rect(p, {unit.o, unit.e1, unit.e2});
  const bool use =
      rect.solid_angle >= kMinSphericalSolidAngle && rect.solid_angle <= kMaxSphericalSolidAngle;
  if (use) *pdf = float(1.0 / rect.solid_angle);
  return use;
}

float AreaLight::area_density(const Unit& unit, Vec3 p, Vec3 q, Vec3 n) {
  const Vec3 d = q - p;
  const float dist2 = dot(d, d);
  return area_density(unit, dist2, dot(n, d) / std::sqrt(dist2));
}

float AreaLight::area_density(const Unit& unit, float dist2, float cos_l) {
  const float c = std::fabs(cos_l);
  return c > 0.0f ? dist2 / (c * unit.area) : 0.0f;
}

LightSample AreaLight::sample_li(Vec3 p, Vec2 u) const {
  if (pmf_.empty()) return {};
  // The unit by area, then a point of it by its own strategy.
  const Picked pk = pick(u.x);
  const Unit& unit = units_[pk.unit];
  const Vec2 v{pk.u, u.y};
  LightSample ls;
  Vec3 q, n;
  float pdf = 0;
  if (unit.kind == UnitKind::kSphere) {
    const SphereCone cone(p, {unit.o, unit.e1.x});
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
      if (!(pdf > 0.0f) || !std::isfinite(pdf)) return {};
      ls.li = radiance_;
      ls.pdf = pmf_[pk.unit] * pdf;
      return ls;
    }
  } else if (unit.kind == UnitKind::kRectangle) {
    const SphericalRect rect(p, {unit.o, unit.e1, unit.e2});
    if (rect.solid_angle >= kMinSphericalSolidAngle &&
        rect.solid_angle <= kMaxSphericalSolidAngle) {
      q = rect.sample(v);
      n = unit.n;
      pdf = float(1.0 / rect.solid_angle);
    }
  }
  if (!(pdf > 0.0f)) sample_area(unit, v, q, n);
  const Vec3 d = q - p;
  const float dist2 = dot(d, d);
  ls.distance = std::sqrt(dist2);
  if (!(ls.distance > 0.0f)) return {};
  ls.wi = d * (1.0f / ls.distance);
  // Only the emitting side: a one-sided light seen from behind gives nothing.
  const float cos_l = dot(n, -ls.wi);
  if (!(two_sided_ ? cos_l != 0.0f : cos_l > 0.0f)) return {};
  if (!(pdf > 0.0f)) pdf = area_density(unit, dist2, cos_l);  // the distance and cosine at hand
  if (!(pdf > 0.0f) || !std::isfinite(pdf)) return {};
  ls.li = radiance_;
  ls.pdf = pmf_[pk.unit] * pdf;
  return ls;
}

float AreaLight::pdf_li(Vec3 p, Vec3, const LightPoint& hit) const {
  const uint32_t i = hit.prim - first_prim_;  // wraps for prim < first_prim_
  if (!(i < prim_unit_.size())) return 0.0f;
  const uint32_t k = prim_unit_[i];
  const float pmf = pmf_[k];
  if (!(pmf > 0.0f)) return 0.0f;
  const Unit& unit = units_[k];
  float pdf = 0;
  if (unit.kind == UnitKind::kSphere && solid_angle_sampled(unit, p, &pdf))
    return pmf * pdf;  // seen from outside: the near cap, always its front
  // Planar primitives and spheres seen from inside: only the emitting side is ever sampled.
  if (!two_sided_ && !(dot(hit.n, p - hit.p) > 0.0f)) return 0.0f;
  if (!solid_angle_sampled(unit, p, &pdf)) pdf = area_density(unit, p, hit.p, hit.n);
  return pmf * pdf;
}

Rgb AreaLight::l(const LightPoint& hit, Vec3 w) const {
  return two_sided_ || dot(hit.n, w) > 0.0f ? radiance_ : Rgb{};
}

LightLeSample AreaLight::sample_le(Vec2 u_pos, Vec2 u_dir, float time) const {
  LightLeSample s;
  if (pmf_.empty()) return s;
  const Picked pk = pick(u_pos.x);
  const Vec2 v{pk.u, u_pos.y};
  Vec3 q, n;
  sample_area(units_[pk.unit], v, q, n);
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
