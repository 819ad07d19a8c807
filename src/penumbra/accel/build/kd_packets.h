#pragma once
/// The kd-tree's leaf triangles in packets of four (structure of arrays) and a four-wide filter
/// in front of the scalar triangle test: the edge-function step of the watertight test (Woop,
/// Benthin, Wald 2013, "Watertight Ray/Triangle Intersection", JCGT 2(1)) on four triangles at
/// once (AVX), which rejects a triangle only when the scalar test certainly rejects it. The
/// survivors, usually none or one, go through geometry/triangle.h's test, so hits, t, u and v are
/// exactly the scalar test's whatever the compiler does with fused multiply-adds (which make a
/// straight vector copy of the test differ in the last bits).
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/accel/build/array_allocator.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/prepared_ray.h"
#include "penumbra/geometry/primitive_set.h"
#include "penumbra/geometry/triangle.h"

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace penumbra {

/// Four triangles: v[vertex][axis][lane].
struct alignas(16) KdTriPacket {
  float v[3][3][4];
};

/// Packets of `ids` (a multiple of four; kNoPrim marks padding) from the set's triangles.
std::vector<KdTriPacket, ArrayAllocator<KdTriPacket>> make_kd_packets(
    const PrimitiveSet& prims, std::span<const uint32_t> ids);

/// The per-ray values of the packet test.
struct KdPacketRay {
  const PreparedRay* pr;
#if defined(__AVX__)
  __m128 o[3];        ///< origin, permuted to (kx, ky, kz)
  __m128 sx, sy, sz;  ///< shear constants
  __m128 tmin;
#endif
  explicit KdPacketRay(const PreparedRay& r) : pr(&r) {
#if defined(__AVX__)
    const int k[3] = {r.kx, r.ky, r.kz};
    for (int a = 0; a < 3; ++a) o[a] = _mm_set1_ps(r.ray.o[k[a]]);
    sx = _mm_set1_ps(r.sx), sy = _mm_set1_ps(r.sy);
#endif
  }
};

/// Lanes of `p` that the scalar watertight test might hit (a superset of them). A lane is
/// dropped when one edge function is below -tol and another above tol, where tol bounds how far
/// the scalar test's edge functions can be from these (u = 2^-24): its sheared coordinates, with
/// or without fused multiply-adds, are within 3u (|P_k| + |s P_z|) of these; an edge function,
/// whether the scalar test evaluates it in double or in float, then differs by at most 20u Sx Sy,
/// Sx and Sy bounding those sums over the three vertices; tol = 32u Sx Sy.
inline unsigned kd_packet_candidates(const KdTriPacket& p, const KdPacketRay& r) {
#if defined(__AVX__)
  const PreparedRay& pr = *r.pr;
  const int kx = pr.kx, ky = pr.ky, kz = pr.kz;
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  __m128 x[3], y[3], bound_x = _mm_setzero_ps(), bound_y = _mm_setzero_ps();
  for (int k = 0; k < 3; ++k) {
    const __m128 X = _mm_sub_ps(_mm_load_ps(p.v[k][kx]), r.o[0]);
    const __m128 Y = _mm_sub_ps(_mm_load_ps(p.v[k][ky]), r.o[1]);
    const __m128 Z = _mm_sub_ps(_mm_load_ps(p.v[k][kz]), r.o[2]);
    const __m128 zx = _mm_mul_ps(r.sx, Z), zy = _mm_mul_ps(r.sy, Z);
    x[k] = _mm_sub_ps(X, zx);
    y[k] = _mm_sub_ps(Y, zy);
    bound_x = _mm_max_ps(bound_x, _mm_add_ps(_mm_and_ps(X, abs_mask), _mm_and_ps(zx, abs_mask)));
    bound_y = _mm_max_ps(bound_y, _mm_add_ps(_mm_and_ps(Y, abs_mask), _mm_and_ps(zy, abs_mask)));
  }
  // Edge functions in double, as the scalar test computes them.
  const auto edge = [](__m128 px, __m128 py, __m128 qx, __m128 qy) {
    const __m256d a = _mm256_mul_pd(_mm256_cvtps_pd(px), _mm256_cvtps_pd(qy));
    const __m256d b = _mm256_mul_pd(_mm256_cvtps_pd(py), _mm256_cvtps_pd(qx));
    return _mm256_cvtpd_ps(_mm256_sub_pd(a, b));
  };
  const __m128 U = edge(x[2], y[2], x[1], y[1]);  // cx by - cy bx
  const __m128 V = edge(x[0], y[0], x[2], y[2]);  // ax cy - ay cx
  const __m128 W = edge(x[1], y[1], x[0], y[0]);  // bx ay - by ax
  // (1e-30 keeps tol above the spacing of subnormal edge functions from tiny coordinates.)
  const __m128 tol =
      _mm_add_ps(_mm_mul_ps(_mm_set1_ps(32.0f * kMachineEpsilon), _mm_mul_ps(bound_x, bound_y)),
                 _mm_set1_ps(1e-30f));
  const __m128 neg_tol = _mm_sub_ps(_mm_setzero_ps(), tol);
  const __m128 below = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(U, neg_tol), _mm_cmplt_ps(V, neg_tol)),
                                 _mm_cmplt_ps(W, neg_tol));
  const __m128 above =
      _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(U, tol), _mm_cmpgt_ps(V, tol)), _mm_cmpgt_ps(W, tol));
  return ~unsigned(_mm_movemask_ps(_mm_and_ps(below, above))) & 15u;
#else
  (void)p, (void)r;
  return 15u;
#endif
}

/// Vertex `k` of lane `lane`.
inline Vec3 kd_packet_vertex(const KdTriPacket& p, int k, int lane) {
  return {p.v[k][0][lane], p.v[k][1][lane], p.v[k][2][lane]};
}

}  // namespace penumbra
