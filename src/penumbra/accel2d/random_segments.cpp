#include "penumbra/accel2d/random_segments.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"

namespace penumbra::lab2d {

Scene2D random_segments(size_t n, uint64_t seed) {
  Scene2D scene;
  scene.source = fmt::format("random(n={},seed={})", n, seed);
  const double side = std::max(1.0, std::sqrt(double(n)));
  const double eps = kTolerance * side;
  // Unit buckets: a segment of length <= 1 covers at most 2 x 2 of them.
  const int res = int(std::ceil(side));
  std::vector<std::vector<uint32_t>> buckets(size_t(res) * res);
  auto bucket = [&](double v) { return std::clamp(int(v), 0, res - 1); };
  Pcg32 rng(seed, 0x5e9);
  const size_t max_tries = 100 * n + 1000;
  for (size_t tries = 0; scene.shapes.size() < n; ++tries) {
    if (tries == max_tries)
      throw Error(fmt::format("random segments: gave up after {} candidates", max_tries));
    const Vec2d c{rng.next_double() * side, rng.next_double() * side};
    const double len = 0.25 + 0.75 * rng.next_double();
    const double angle = 2 * std::numbers::pi * rng.next_double();
    const Vec2d h{0.5 * len * std::cos(angle), 0.5 * len * std::sin(angle)};
    const Segment2 s{c - h, c + h};
    const int x0 = bucket(std::min(s.a.x, s.b.x)), x1 = bucket(std::max(s.a.x, s.b.x));
    const int y0 = bucket(std::min(s.a.y, s.b.y)), y1 = bucket(std::max(s.a.y, s.b.y));
    bool free = true;
    for (int y = y0; y <= y1 && free; ++y)
      for (int x = x0; x <= x1 && free; ++x)
        for (uint32_t k : buckets[size_t(y) * res + x]) {
          bool collinear;
          if (segments_meet(s, scene.shapes[k].segment(), 4 * eps, collinear)) {
            free = false;
            break;
          }
        }
    if (!free) continue;
    const auto id = uint32_t(scene.shapes.size());
    scene.shapes.push_back({{s.a, s.b}, 0});
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) buckets[size_t(y) * res + x].push_back(id);
  }
  return scene;
}

Scene2D comb_segments(size_t n) {
  Scene2D scene;
  scene.source = fmt::format("comb(n={})", n);
  const double scale = std::max<double>(1, double(n));
  // The tangent of y = x²/n at p: y = (2 p x − p²)/n.
  auto on_tangent = [&](double p, double x) { return Vec2d{x, (2 * p * x - p * p) / scale}; };
  const double p1 = double(n) - 1;
  for (size_t k = 1; k <= n; ++k) {
    const double p = double(n) - double(k);
    const double x0 = p - 0.25, x1 = k == 1 ? p + 0.25 : 0.5 * (p1 + p) + 0.25;
    scene.shapes.push_back({{on_tangent(p, x0), on_tangent(p, x1)}, 0});
  }
  return scene;
}

}  // namespace penumbra::lab2d
