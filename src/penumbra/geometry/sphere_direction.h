#pragma once
/// Uniform directions on the unit sphere, for the layers below render (test scenes, benchmark
/// rays) as for the renderer's samplers (render/sampling.h).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/core/vec.h"

namespace penumbra {

/// Uniform direction on the unit sphere from u in [0,1)^2 (z = 1 - 2 u.x, azimuth 2 pi u.y);
/// pdf = 1 / (4 pi).
inline Vec3 sample_uniform_sphere(Vec2 u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * std::numbers::pi_v<float> * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace penumbra
