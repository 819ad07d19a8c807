#include "penumbra/app/bench_rays.h"

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

double time_chunks(size_t n, const std::function<void(size_t, size_t)>& trace) {
  const Timer timer;
  parallel_for_range(n, trace, kChunk);
  return timer.elapsed_s();
}

}  // namespace penumbra::app
