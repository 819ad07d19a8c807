#pragma once
/// The equal-area octahedral mapping between the unit square and the unit sphere (Clarberg 2008,
/// "Fast Equal-Area Mapping of the (Hemi)Sphere using SIMD"): the layout of pbrt-v4's image
/// infinite lights. Areas are preserved up to the constant 4 pi, so a density p on the square is
/// the density p / (4 pi) per solid angle.
///
/// Layout, in the square's [-1, 1]^2 coordinates (U, V) = (2u - 1, 2v - 1): the diamond
/// |U| + |V| <= 1 is the hemisphere z >= 0 with +z at its centre, the four corner triangles the
/// hemisphere z < 0 (each corner is -z); r = 1 - |1 - |U| - |V|| is the distance from the square's
/// diagonal ring |U| + |V| = 1 (the equator z = 0) and z = +-(1 - r^2): the diamond |U| + |V| <= r
/// has area 2 r^2 and the cap z >= 1 - r^2 the solid angle 2 pi r^2, in the ratio 4 : 4 pi of the
/// whole square to the whole sphere; the azimuth is linear in the position along the ring. The
/// square's edges fold at their midpoints: (U = -1, V) and (U = -1, -V) are the same direction, and
/// likewise on the other edges.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/core/vec.h"

namespace penumbra {

/// The unit direction of point p in [0, 1]^2 of the equal-area octahedral square.
inline Vec3 equal_area_square_to_sphere(Vec2 p) {
  const double u = 2.0 * p.x - 1.0, v = 2.0 * p.y - 1.0;
  const double au = std::fabs(u), av = std::fabs(v);
  // Signed distance from the diagonal ring (positive inside the diamond: the upper hemisphere).
  const double signed_distance = 1.0 - (au + av);
  const double r = 1.0 - std::fabs(signed_distance);
  // Azimuth within the quadrant, linear along the ring: 0 on the U axis, pi/2 on the V axis.
  const double phi = (r == 0.0 ? 1.0 : (av - au) / r + 1.0) * (std::numbers::pi / 4.0);
  const double z = std::copysign(1.0 - r * r, signed_distance);
  const double s = r * std::sqrt(std::fmax(0.0, 2.0 - r * r));
  const double x = std::copysign(std::cos(phi), u) * s, y = std::copysign(std::sin(phi), v) * s;
  return normalize(Vec3(float(x), float(y), float(z)));
}

/// The point in [0, 1]^2 of the equal-area octahedral square for the unit direction d (the
/// inverse of equal_area_square_to_sphere).
inline Vec2 equal_area_sphere_to_square(Vec3 d) {
  const double ax = std::fabs(double(d.x)), ay = std::fabs(double(d.y));
  const double az = std::fabs(double(d.z));
  const double r = std::sqrt(std::fmax(0.0, 1.0 - az));
  // The azimuth within the quadrant as a fraction of pi/2, from the x axis towards y.
  const double a = std::max(ax, ay), b = std::min(ax, ay);
  double phi = a == 0.0 ? 0.0 : std::atan(b / a) * (2.0 / std::numbers::pi);
  if (ax < ay) phi = 1.0 - phi;
  double v = phi * r, u = r - v;
  if (d.z < 0) {  // the lower hemisphere: fold out into the corner triangle
    std::swap(u, v);
    u = 1.0 - u;
    v = 1.0 - v;
  }
  u = std::copysign(u, double(d.x));
  v = std::copysign(v, double(d.y));
  return {std::clamp(float(0.5 * (u + 1.0)), 0.0f, 1.0f),
          std::clamp(float(0.5 * (v + 1.0)), 0.0f, 1.0f)};
}

/// Pixel (x, y) of a w x h equal-area octahedral image, moved back into the image across the
/// folded edges when it lies up to one pixel outside (as pbrt-v4's octahedral wrap mode does):
/// leaving through the left or right edge mirrors the row, through the top or bottom the column.
inline void equal_area_wrap(int& x, int& y, int w, int h) {
  if (x < 0) {
    x = -x - 1;
    y = h - 1 - y;
  } else if (x >= w) {
    x = 2 * w - 1 - x;
    y = h - 1 - y;
  }
  if (y < 0) {
    x = w - 1 - x;
    y = -y - 1;
  } else if (y >= h) {
    x = w - 1 - x;
    y = 2 * h - 1 - y;
  }
  x = std::clamp(x, 0, w - 1);
  y = std::clamp(y, 0, h - 1);
}

}  // namespace penumbra
