#pragma once
/// The ray-box tests of the binary BVH: per-ray values computed once, a scalar test of one node
/// and a test of a node's two children at once (AVX when available, scalar otherwise).
#include "penumbra/accel/build/bvh_node.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/prepared_ray.h"

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace penumbra {

/// Per-ray values of the slab test (Williams et al. 2005, "An Efficient and Robust Ray-Box
/// Intersection Algorithm": near and far planes chosen once per ray from the direction signs).
struct BvhRay {
  float o[3];        ///< origin
  float inv[3];      ///< 1 / d (+-inf for a zero component)
  float inv_far[3];  ///< 1 / d scaled by 1 + 2 gamma(3), for conservative exit distances
  int near[3];       ///< index of each axis' near plane in BvhNode::box
  int far[3];        ///< index of each axis' far plane
#if defined(__AVX__)
  __m256i perm;  ///< reorders a node to (near x, far x, near y, far y, near z, far z, index, count)
  __m256 org;    ///< (ox, ox, oy, oy, oz, oz, 0, 0)
  __m256 scale;  ///< (1/dx, 1/dx', 1/dy, 1/dy', 1/dz, 1/dz', -inf, +inf); ' = inv_far
#endif

  explicit BvhRay(const PreparedRay& pr) {
    // Robust exit distances (Pharr, Jakob, Humphreys, "Physically Based Rendering", 3rd ed.,
    // section 3.9.2): scaling 1/d up by 1 + 2 gamma(3) covers the rounding of the subtraction,
    // the division and the products, so a grazing ray never misses a box it touches.
    constexpr float kFarScale = 1.0f + 2.0f * gamma(3);
    for (int a = 0; a < 3; ++a) {
      o[a] = pr.ray.o[a];
      inv[a] = pr.inv_dir[a];
      inv_far[a] = pr.inv_dir[a] * kFarScale;
      near[a] = 2 * a + pr.neg[a];
      far[a] = 2 * a + 1 - pr.neg[a];
    }
#if defined(__AVX__)
    // permutevar_ps selects within 128-bit halves: (x, y) planes in the low half, (z, index,
    // count) in the high half, so every index is relative to its half.
    perm = _mm256_setr_epi32(near[0], far[0], near[1], far[1], near[2] - 4, far[2] - 4, 2, 3);
    org = _mm256_setr_ps(o[0], o[0], o[1], o[1], o[2], o[2], 0.0f, 0.0f);
    // The index and count lanes become -inf or +inf (non-zero) or NaN (zero), all of which the
    // reductions below ignore.
    scale = _mm256_setr_ps(inv[0], inv_far[0], inv[1], inv_far[1], inv[2], inv_far[2], -kInfinity,
                           kInfinity);
#endif
  }
};

/// Slab test of one node against [t0, t1]; on a hit returns true and sets `entry`. With a zero
/// direction component and the origin on a plane of that axis, (plane - o) * inv is 0 * inf =
/// NaN; every comparison with NaN is false, so such a term keeps the running bound and the box is
/// not rejected on that axis (the ray lies in the closed slab).
inline bool hit_node(const BvhNode& n, const BvhRay& r, float t0, float t1, float& entry) {
  const float nx = (n.box[r.near[0]] - r.o[0]) * r.inv[0];
  const float ny = (n.box[r.near[1]] - r.o[1]) * r.inv[1];
  const float nz = (n.box[r.near[2]] - r.o[2]) * r.inv[2];
  const float fx = (n.box[r.far[0]] - r.o[0]) * r.inv_far[0];
  const float fy = (n.box[r.far[1]] - r.o[1]) * r.inv_far[1];
  const float fz = (n.box[r.far[2]] - r.o[2]) * r.inv_far[2];
  t0 = nx > t0 ? nx : t0;
  t0 = ny > t0 ? ny : t0;
  t0 = nz > t0 ? nz : t0;
  t1 = fx < t1 ? fx : t1;
  t1 = fy < t1 ? fy : t1;
  t1 = fz < t1 ? fz : t1;
  entry = t0;
  return t0 <= t1;
}

/// Tests the two adjacent children at `pair` against [t0, t1]. Returns a mask (bit 0: first
/// child hit, bit 1: second) and the entry distances, +inf for a child that is missed.
inline unsigned hit_pair(const BvhNode* pair, const BvhRay& r, float t0, float t1, float& ta,
                         float& tb) {
#if defined(__AVX__)
  // Both nodes (one cache line) to plane distances, near and far planes interleaved per axis.
  const __m256 da = _mm256_mul_ps(
      _mm256_sub_ps(_mm256_permutevar_ps(_mm256_load_ps(pair[0].box), r.perm), r.org), r.scale);
  const __m256 db = _mm256_mul_ps(
      _mm256_sub_ps(_mm256_permutevar_ps(_mm256_load_ps(pair[1].box), r.perm), r.org), r.scale);
  // near = (nx_a, ny_a, nx_b, ny_b | nz_a, -, nz_b, -), far likewise.
  const __m256 n8 = _mm256_shuffle_ps(da, db, _MM_SHUFFLE(2, 0, 2, 0));
  const __m256 f8 = _mm256_shuffle_ps(da, db, _MM_SHUFFLE(3, 1, 3, 1));
  // max_ps(x, acc) returns acc when x is NaN (and min_ps likewise): NaN terms are ignored.
  __m128 n = _mm_max_ps(_mm256_castps256_ps128(n8), _mm_set1_ps(t0));
  n = _mm_max_ps(_mm256_extractf128_ps(n8, 1), n);
  n = _mm_max_ps(n, _mm_shuffle_ps(n, n, _MM_SHUFFLE(2, 3, 0, 1)));
  __m128 f = _mm_min_ps(_mm256_castps256_ps128(f8), _mm_set1_ps(t1));
  f = _mm_min_ps(_mm256_extractf128_ps(f8, 1), f);
  f = _mm_min_ps(f, _mm_shuffle_ps(f, f, _MM_SHUFFLE(2, 3, 0, 1)));
  const __m128 hit = _mm_cmple_ps(n, f);
  n = _mm_blendv_ps(_mm_set1_ps(kInfinity), n, hit);
  ta = _mm_cvtss_f32(n);
  tb = _mm_cvtss_f32(_mm_movehl_ps(n, n));
  const auto m = unsigned(_mm_movemask_ps(hit));
  return (m & 1u) | ((m >> 1) & 2u);
#else
  const bool ha = hit_node(pair[0], r, t0, t1, ta), hb = hit_node(pair[1], r, t0, t1, tb);
  ta = ha ? ta : kInfinity;
  tb = hb ? tb : kInfinity;
  return unsigned(ha) | (unsigned(hb) << 1);
#endif
}

}  // namespace penumbra
