#pragma once
/// Watertight ray-triangle intersection (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle
/// Intersection", JCGT 2(1)): no ray passes between two triangles sharing an edge, and a ray
/// through a shared edge or vertex hits at least one of them. Degenerate (zero-area) and
/// non-finite triangles are never hit.
#include <algorithm>
#include <bit>
#include <cmath>

#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/prepared_ray.h"

namespace penumbra {

/// The bound on the rounding error of the watertight test's t, before its factor |1 / det|
/// (Pharr, Jakob, Humphreys, "Physically Based Rendering", 3rd ed., section 3.9.6), from the
/// largest magnitudes of the edge functions (max_e) and of the sheared vertex coordinates
/// (max_x, max_y, max_z). pbrt writes it as 3 (gamma3 E Z + de Z + dz E) with dz = gamma3 Z,
/// dx = gamma5 (X + Z), dy = gamma5 (Y + Z) and de = 2 (gamma2 X Y + dy X + dx Y); expanded,
/// that is Z (6 gamma3 E + (6 gamma2 + 12 gamma5) X Y + 6 gamma5 Z (X + Y)), the same bound in
/// exact arithmetic (its own rounding, a few ulps, is as negligible as pbrt takes it), in half
/// the dependent operations and about half the instructions. A template so that the block test
/// (accel/triangle_blocks.h) evaluates it lane-wise in the same order, to the same bits.
template <class T>
inline T triangle_t_error(T max_e, T max_x, T max_y, T max_z) {
  constexpr float kE = 6.0f * gamma(3), kXY = 6.0f * gamma(2) + 12.0f * gamma(5),
                  kZ = 6.0f * gamma(5);
  return ((kE * max_e + kXY * (max_x * max_y)) + (kZ * max_z) * (max_x + max_y)) * max_z;
}

/// The range check before the division compares the scaled distance with tmax widened by this
/// factor, so that it never rejects a t below tmax: t = fl(T fl(1 / det)) and the limit
/// fl(fl(tmax k) |det|) round four times by at most 2^-24 each, less than the widening. Whether
/// a hit replaces the closest so far then depends on t alone (the same t decides the same way
/// in any order of tests: hit.h, tie_bound). A limit below kRangeTiny (where the product may be
/// subnormal, its relative error unbounded) skips the check.
inline constexpr float kRangeWiden = 1.0f + 0x1p-21f;
inline constexpr float kRangeTiny = 0x1p-100f;

/// Tests triangle (a, b, c) against `pr` on (tmin, tmax). On a hit sets t and the barycentrics
/// (u, v) of b and c and returns true.
inline bool intersect_triangle(const PreparedRay& pr, Vec3 a, Vec3 b, Vec3 c, float tmin,
                               float tmax, float& t, float& u, float& v) {
  const Vec3 o = pr.ray.o;
  // Vertices relative to the ray origin, sheared so the ray runs along +z.
  const Vec3 A = a - o, B = b - o, C = c - o;
  const float ax = A[pr.kx] - pr.sx * A[pr.kz], ay = A[pr.ky] - pr.sy * A[pr.kz];
  const float bx = B[pr.kx] - pr.sx * B[pr.kz], by = B[pr.ky] - pr.sy * B[pr.kz];
  const float cx = C[pr.kx] - pr.sx * C[pr.kz], cy = C[pr.ky] - pr.sy * C[pr.kz];
  // Scaled barycentrics as 2D edge functions. In float, fl(fl(p q) - fl(r s)) is exactly the
  // negative of the same edge seen from the neighbouring triangle (the project builds with
  // -ffp-contract=off: an FMA would round the two products differently and break that
  // symmetry). Where one is zero the sign is undecided, and all three are recomputed in double
  // (products of floats are exact there), as the paper prescribes.
  float U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
  if (U == 0.0f || V == 0.0f || W == 0.0f) [[unlikely]] {
    U = float(double(cx) * by - double(cy) * bx);
    V = float(double(ax) * cy - double(ay) * cx);
    W = float(double(bx) * ay - double(by) * ax);
  }
  // Outside when the edge functions have mixed signs (one test on their min and max, fewer
  // branches for incoherent rays to mispredict).
  if (std::min(U, std::min(V, W)) < 0.0f && std::max(U, std::max(V, W)) > 0.0f) return false;
  const float det = U + V + W;
  if (!(std::fabs(det) > 0.0f)) return false;  // degenerate, or NaN
  const float az = pr.sz * A[pr.kz], bz = pr.sz * B[pr.kz], cz = pr.sz * C[pr.kz];
  const float T = U * az + V * bz + W * cz;
  // Range test on the scaled distance, without dividing yet; with the sign of det moved onto T
  // (exact), one comparison pair serves both orientations. tmax only by its widened limit
  // (kRangeWiden): t itself decides below.
  const float adet = std::fabs(det), sT = std::signbit(det) ? -T : T;
  const float limit = (tmax * kRangeWiden) * adet;
  if (sT <= tmin * adet || (sT > limit && limit > kRangeTiny)) return false;
  const float inv = 1.0f / det;
  t = T * inv;
  // Reject a hit closer to the origin than the rounding error of t: a ray leaving a surface (its
  // origin exactly on the plane, as happens for axis-aligned walls) must not hit that surface
  // again (conservative bound of pbrt-v3 section 3.9.6).
  const float max_zt = std::fmax(std::fabs(az), std::fmax(std::fabs(bz), std::fabs(cz)));
  const float max_xt = std::fmax(std::fabs(ax), std::fmax(std::fabs(bx), std::fabs(cx)));
  const float max_yt = std::fmax(std::fabs(ay), std::fmax(std::fabs(by), std::fabs(cy)));
  const float max_e = std::fmax(std::fabs(U), std::fmax(std::fabs(V), std::fabs(W)));
  const float delta_t = triangle_t_error(max_e, max_xt, max_yt, max_zt) * std::fabs(inv);
  if (!(t > delta_t)) return false;
  u = V * inv;
  v = W * inv;
  return t > tmin && t < tmax;  // guards against rounding at the interval ends
}

/// True when two vertices of (a, b, c) are the same (bit for bit). intersect_triangle never hits
/// such a triangle: with b = c, say, the edge function U is fl(p q) - fl(q p) = 0 in float and in
/// double, and W = -V exactly (rounding is symmetric), so det = (U + V) + W is exactly zero; a = b
/// and a = c likewise. Structures leave these triangles out of their leaves (a tenth of the
/// triangles of some CAD meshes, whose every test would take the double-precision path).
inline bool repeated_vertex(Vec3 a, Vec3 b, Vec3 c) {
  const auto same = [](Vec3 p, Vec3 q) {
    return std::bit_cast<uint32_t>(p.x) == std::bit_cast<uint32_t>(q.x) &&
           std::bit_cast<uint32_t>(p.y) == std::bit_cast<uint32_t>(q.y) &&
           std::bit_cast<uint32_t>(p.z) == std::bit_cast<uint32_t>(q.z);
  };
  return same(a, b) || same(b, c) || same(a, c);
}

}  // namespace penumbra
