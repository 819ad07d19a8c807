#include "penumbra/app/bench_rays.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/timer.h"
#include "penumbra/geometry/sphere_direction.h"

namespace penumbra::app {

namespace {
/// Rays per generation or tracing task: large enough to amortise scheduling, small enough to
/// balance two or sixty-four threads.
constexpr size_t kChunk = 1024;
}  // namespace

std::vector<Ray> primary_rays(const Bounds3& bounds, int width, int height) {
  const Vec3 centre = bounds.center();
  const float radius = std::max(0.5f * length(bounds.diagonal()), 1e-6f);
  const float half_fov = 20.0f * std::numbers::pi_v<float> / 180.0f;
  // Camera on an oblique direction (no axis-aligned view), far enough to see the whole sphere.
  const Vec3 back = normalize(Vec3(0.55f, 0.45f, 1.0f));
  const Vec3 eye = centre + back * (radius / std::sin(half_fov));
  const Vec3 forward = -back;
  const Vec3 right = normalize(cross(forward, Vec3(0, 1, 0)));
  const Vec3 up = cross(right, forward);
  const float tan_half = std::tan(half_fov);
  const float aspect = float(width) / float(height);
  std::vector<Ray> rays(size_t(width) * size_t(height));
  parallel_for(size_t(height), [&](size_t y) {
    for (int x = 0; x < width; ++x) {
      const float sx = (2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * tan_half * aspect;
      const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height)) * tan_half;
      rays[y * size_t(width) + size_t(x)] = {eye, normalize(forward + right * sx + up * sy)};
    }
  });
  return rays;
}

std::vector<Ray> incoherent_rays(const Bounds3& bounds, size_t n, uint64_t seed) {
  std::vector<Ray> rays(n);
  const Vec3 lo = bounds.lo, extent = bounds.diagonal();
  parallel_for((n + kChunk - 1) / kChunk, [&](size_t c) {
    Pcg32 rng(seed, c);  // one stream per chunk: independent of the thread count
    for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
      const Vec3 o = lo + extent * Vec3(rng.next_float(), rng.next_float(), rng.next_float());
      rays[i] = {o, sample_uniform_sphere({rng.next_float(), rng.next_float()})};
    }
  });
  return rays;
}

PathRays path_rays(const PrimitiveSet& prims, const std::vector<Ray>& camera,
                   const std::vector<Hit>& hits, uint64_t seed,
                   const std::vector<uint32_t>& lights) {
  const Bounds3& b = prims.bounds();
  const float diag = std::max(length(b.diagonal()), 1e-6f);
  const float offset = 1e-5f * diag;
  const Vec3 light_centre(b.center().x, b.hi.y + 0.25f * diag, b.center().z);
  const float light_side = 0.5f * diag;
  // The emitters' cumulative areas, to pick one in proportion to its area.
  std::vector<double> cdf;
  double total = 0;
  for (const uint32_t id : lights) {
    const Vec3* v = prims.triangle(id);
    total += 0.5 * double(length(cross(v[1] - v[0], v[2] - v[0])));
    cdf.push_back(total);
  }
  const auto light_point = [&](Pcg32& rng) {
    const float u = rng.next_float(), v = rng.next_float();
    if (cdf.empty() || !(total > 0))
      return light_centre + Vec3((u - 0.5f) * light_side, 0, (v - 0.5f) * light_side);
    const double x = double(rng.next_float()) * total;
    const size_t k =
        std::min(size_t(std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin()), cdf.size() - 1);
    const Vec3* t = prims.triangle(lights[k]);
    const float su = std::sqrt(u);  // uniform on the triangle
    return t[0] * (1 - su) + t[1] * (su * (1 - v)) + t[2] * (su * v);
  };
  // Each camera ray gets its slots (empty ones have tmax < 0), compacted in order afterwards, so
  // the sets do not depend on the thread count.
  const size_t n = camera.size();
  std::vector<Ray> bounce(n), shadow(n);
  parallel_for((n + kChunk - 1) / kChunk, [&](size_t c) {
    Pcg32 rng(seed, c);
    for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
      bounce[i].tmax = shadow[i].tmax = -1;
      if (!hits[i].valid()) continue;
      const Vec3* v = prims.triangle(hits[i].prim);
      Vec3 nrm = cross(v[1] - v[0], v[2] - v[0]);
      const float len = length(nrm);
      if (!(len > 0)) continue;
      nrm = nrm / len;
      if (dot(nrm, camera[i].d) > 0) nrm = -nrm;
      const Vec3 p = camera[i].at(hits[i].t) + nrm * offset;
      // Cosine-distributed about nrm: a uniform disc point lifted to the hemisphere.
      const float r = std::sqrt(rng.next_float()),
                  phi = 2 * std::numbers::pi_v<float> * rng.next_float();
      Vec3 t, bt;
      orthonormal_basis(nrm, t, bt);
      const float x = r * std::cos(phi), y = r * std::sin(phi);
      const float z = std::sqrt(std::max(0.0f, 1 - x * x - y * y));
      bounce[i] = {p, normalize(t * x + bt * y + nrm * z)};
      const Vec3 q = light_point(rng);
      const Vec3 to = q - p;
      const float dist = length(to);
      if (dot(to, nrm) <= 0 || !(dist > 0)) continue;  // the light is behind the surface
      shadow[i] = {p, to / dist, 0.0f, dist * (1 - 1e-4f)};
    }
  });
  const auto compact = [](std::vector<Ray>& rays) {
    std::erase_if(rays, [](const Ray& r) { return r.tmax < 0; });
  };
  compact(bounce);
  compact(shadow);
  return {std::move(bounce), std::move(shadow)};
}

double time_chunks(size_t n, const std::function<void(size_t, size_t)>& trace) {
  const Timer timer;
  parallel_for_range(n, trace, kChunk);
  return timer.elapsed_s();
}

}  // namespace penumbra::app
