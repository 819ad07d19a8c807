#pragma once
/// The benchmark terrain of issue #19: an n x n-vertex height field over the unit square with
/// ridges (ridged sinusoids at six frequencies and directions), two triangles per cell. The same
/// function as bench/make_terrain.py, which writes it as a PLY file for accel-bench.
#include <cmath>
#include <cstdint>

#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra::bench {

/// Height at (x, z) in [0, 1]^2: sum over k of 0.5^k (1 - |sin(f_k (x cos a_k + z sin a_k) +
/// p_k)|)^2 with f_k = 6 * 2^k, a_k = 0.7 k, p_k = 1.3 k, scaled by 0.08.
inline float terrain_height(double x, double z) {
  double h = 0, amplitude = 1, frequency = 6;
  for (int k = 0; k < 6; ++k) {
    const double a = 0.7 * k,
                 s = std::sin(frequency * (x * std::cos(a) + z * std::sin(a)) + 1.3 * k);
    h += amplitude * (1 - std::abs(s)) * (1 - std::abs(s));
    amplitude *= 0.5, frequency *= 2;
  }
  return float(0.08 * h);
}

/// The terrain of n x n vertices: 2 (n - 1)^2 triangles, facing +y.
inline TriangleMesh terrain(int n) {
  TriangleMesh m;
  m.positions.reserve(size_t(n) * size_t(n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = double(i) / (n - 1), z = double(j) / (n - 1);
      m.positions.push_back({float(x), terrain_height(x, z), float(z)});
    }
  m.indices.reserve(6 * size_t(n - 1) * size_t(n - 1));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = uint32_t(j * n + i), b = a + 1, c = a + uint32_t(n), d = c + 1;
      for (uint32_t v : {a, c, b, b, c, d}) m.indices.push_back(v);
    }
  return m;
}

}  // namespace penumbra::bench
