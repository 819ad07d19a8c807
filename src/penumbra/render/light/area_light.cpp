#include "penumbra/render/light/area_light.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/render/sampling.h"

namespace penumbra {

namespace {
/// Area of primitive `id` (spheres: the whole surface).
float prim_area(const World& world, uint32_t id) {
  const PrimitiveSet& prims = world.primitives();
  if (prims.kind(id) == PrimKind::kSphere) {
    const float r = prims.sphere(id).radius;
    return 4.0f * std::numbers::pi_v<float> * r * r;
  }
  return length(world.area_normal(id));
}
}  // namespace

AreaLight::AreaLight(const World& world, const Emitter& e)
    : world_(world), radiance_(e.radiance), two_sided_(e.two_sided) {
  double sum = 0;
  for (uint32_t id = e.first_prim; id < e.first_prim + e.prim_count; ++id) {
    const float a = prim_area(world, id);
    if (!(a > 0.0f) || !std::isfinite(a)) continue;  // degenerate primitives emit nothing
    sum += a;
    prims_.push_back(id);
    cdf_.push_back(float(sum));
  }
  area_ = float(sum);
  for (float& c : cdf_) c = float(c / sum);
  if (!cdf_.empty()) cdf_.back() = 1.0f;
}

void AreaLight::sample_point(Vec2 u, Vec3& q, Vec3& n) const {
  // Pick the primitive by area with u.x, then reuse the remainder of u.x as a fresh uniform number
  // so the mapping from [0,1)^2 to the surface stays continuous and area-preserving.
  const size_t i = std::min(size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u.x) - cdf_.begin()),
                            cdf_.size() - 1);
  const float lo = i ? cdf_[i - 1] : 0.0f;
  const float ux = std::clamp((u.x - lo) / (cdf_[i] - lo), 0.0f, 0x1.fffffep-1f);
  const uint32_t id = prims_[i];
  const PrimitiveSet& prims = world_.primitives();
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      // Uniform barycentrics (Shirley 1990 / pbrt's square-root mapping).
      const Vec3* v = prims.triangle(id);
      const float s = std::sqrt(ux);
      const float b1 = 1.0f - s, b2 = u.y * s;
      q = v[0] * (1.0f - b1 - b2) + v[1] * b1 + v[2] * b2;
      n = normalize(world_.area_normal(id));
      break;
    }
    case PrimKind::kQuad: {
      const QuadData& d = prims.quad(id);
      q = d.p + d.e1 * ux + d.e2 * u.y;
      n = normalize(world_.area_normal(id));
      break;
    }
    case PrimKind::kSphere: {
      const SphereData& s = prims.sphere(id);
      n = sample_uniform_sphere({ux, u.y});
      q = s.center + n * s.radius;
      break;
    }
  }
}

LightSample AreaLight::sample_li(Vec3 p, Vec2 u) const {
  if (prims_.empty()) return {};
  Vec3 q, n;
  sample_point(u, q, n);
  const Vec3 d = q - p;
  const float dist2 = dot(d, d);
  const float dist = std::sqrt(dist2);
  if (!(dist > 0.0f)) return {};
  const Vec3 wi = d / dist;
  const float cos_l = dot(n, -wi);  // > 0: the receiver sees the front side
  if (!(two_sided_ ? cos_l != 0.0f : cos_l > 0.0f)) return {};
  LightSample ls;
  ls.wi = wi;
  ls.distance = dist;
  ls.li = radiance_;
  ls.pdf = dist2 / (std::fabs(cos_l) * area_);
  return ls;
}

float AreaLight::pdf_li(Vec3 p, Vec3 q, Vec3 n) const {
  const Vec3 d = q - p;
  const float dist2 = dot(d, d);
  const float cos_l = std::fabs(dot(n, normalize(d)));
  if (!(cos_l > 0.0f) || !(area_ > 0.0f)) return 0.0f;
  return dist2 / (cos_l * area_);
}

Rgb AreaLight::power() const {
  return radiance_ * (std::numbers::pi_v<float> * area_ * (two_sided_ ? 2.0f : 1.0f));
}

}  // namespace penumbra
