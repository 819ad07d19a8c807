#include "penumbra/render/light/emitter_point_light.h"

#include <cmath>
#include <numbers>

namespace penumbra {

EmitterPointLight::EmitterPointLight(const World& world, const Emitter& e)
    : radiance_(e.radiance), two_sided_(e.two_sided) {
  const PrimitiveSet& prims = world.primitives();
  Vec3 weighted;
  for (uint32_t id = e.first_prim; id < e.first_prim + e.prim_count; ++id) {
    if (prims.kind(id) == PrimKind::kSphere) {
      spheres_.push_back(prims.sphere(id));
      continue;
    }
    const Vec3 an = world.area_normal(id);
    const float a = length(an);
    if (!(a > 0.0f)) continue;  // degenerate primitives emit nothing
    Vec3 c;
    if (prims.kind(id) == PrimKind::kTriangle) {
      const Vec3* v = prims.triangle(id);
      c = (v[0] + v[1] + v[2]) / 3.0f;
    } else {
      const QuadData& q = prims.quad(id);
      c = q.p + (q.e1 + q.e2) * 0.5f;
    }
    weighted += c * a;
    area_ += a;
    area_normals_.push_back(an);
  }
  centroid_ = area_ > 0.0f ? weighted / area_ : Vec3{};
}

Rgb EmitterPointLight::intensity(Vec3 w) const {
  float projected = 0.0f;
  for (const Vec3& an : area_normals_) {
    const float c = dot(an, w);
    projected += two_sided_ ? std::fabs(c) : std::fmax(c, 0.0f);
  }
  for (const SphereData& s : spheres_) projected += std::numbers::pi_v<float> * s.radius * s.radius;
  return radiance_ * projected;
}

LightSample EmitterPointLight::sample_li(Vec3 p, Vec2) const {
  // Nearest sphere surface point for a pure-sphere emitter; otherwise the planar centroid.
  Vec3 pos = centroid_, center = centroid_;
  if (area_normals_.empty() && !spheres_.empty()) {
    const SphereData& s = spheres_.front();
    center = s.center;
    const Vec3 to_p = p - s.center;
    const float len = length(to_p);
    pos = len > s.radius ? s.center + to_p * (s.radius / len) : s.center;
  }
  const Vec3 d = pos - p;
  const float dist = length(d);
  const Vec3 from_center = p - center;
  const float d2 = dot(from_center, from_center);
  if (!(dist > 0.0f) || !(d2 > 0.0f)) return {};
  return {d / dist, dist, intensity(from_center / std::sqrt(d2)) / d2, 1.0f, true};
}

Rgb EmitterPointLight::power() const {
  // One-sided flat emitter: pi A L; two-sided: 2 pi A L; sphere: 4 pi^2 r^2 L.
  float p = std::numbers::pi_v<float> * area_ * (two_sided_ ? 2.0f : 1.0f);
  for (const SphereData& s : spheres_)
    p += 4.0f * std::numbers::pi_v<float> * std::numbers::pi_v<float> * s.radius * s.radius;
  return radiance_ * p;
}

}  // namespace penumbra
