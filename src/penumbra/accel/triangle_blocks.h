#pragma once
/// The triangles of a tree's leaves (BVH, kd-tree) in blocks of four, stored as structure of
/// arrays, so one leaf's triangles are tested together with 4-lane vector arithmetic (as Embree's
/// "triangle4" leaves are: Wald et al. 2014, "Embree: A Kernel Framework for Efficient CPU Ray
/// Tracing").
///
/// The test is the watertight one of geometry/triangle.h (Woop, Benthin, Wald 2013), written
/// lane-wise with the same operations in the same order: with the project's -ffp-contract=off
/// every lane computes exactly the bits the scalar test computes, so a structure using blocks
/// returns the same hits as `brute`. Written with GCC/Clang vector extensions, which become SSE,
/// AVX or AVX-512 instructions where the target has them and scalar code where it has not.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/prefetch.h"
#include "penumbra/accel/traversal_cost.h"
#include "penumbra/core/array_allocator.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/geometry/primitive_set.h"
#include "penumbra/geometry/triangle.h"

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace penumbra {

namespace block_detail {

using F4 = float __attribute__((vector_size(16)));
using F8 = float __attribute__((vector_size(32)));
using D4 = double __attribute__((vector_size(32)));
using D8 = double __attribute__((vector_size(64)));

/// The integer vector of a float vector's comparisons, and the double vector of its lanes.
template <class F>
using IntOf = decltype(F{} < F{});
template <class F>
using DoubleOf = std::conditional_t<sizeof(F) == 16, D4, D8>;

/// Lanes of the first four of an eight-lane vector (free: the low half of the register).
inline F4 low(F8 a) {
  return __builtin_shufflevector(a, a, 0, 1, 2, 3);
}
inline F8 splat8(float x) {
  return F8{x, x, x, x, x, x, x, x};
}
/// `x` in every lane of an F (4 or 8 lanes).
template <class F>
inline F splat(float x) {
  if constexpr (sizeof(F) == 16)
    return F4{x, x, x, x};
  else
    return splat8(x);
}

/// std::min and std::max lane-wise, with their operand order (so NaN behaves the same).
template <class F>
inline F vmin(F a, F b) {
  return b < a ? b : a;
}
template <class F>
inline F vmax(F a, F b) {
  return a < b ? b : a;
}
template <class F>
inline F vabs(F a) {
  using I = IntOf<F>;
  return (F)((I)a & (I{} + 0x7fffffff));
}
/// fmax as the scalar test uses it (no NaN can reach it: such lanes were rejected).
template <class F>
inline F vfmax(F a, F b) {
  return a < b ? b : a;
}

/// fmax(|a|, fmax(|b|, |c|)) lane-wise, to the same bits for lanes without NaN (a lane with a
/// NaN is rejected before its value is used). With AVX-512 DQ and VL, two `vrangeps` (the larger
/// magnitude, its sign cleared) instead of three absolute values and two maxima.
template <class F>
inline F max_abs3(F a, F b, F c) {
#if defined(__AVX512DQ__) && defined(__AVX512VL__)
  if constexpr (sizeof(F) == 32)
    return (F)_mm256_range_ps((__m256)a, _mm256_range_ps((__m256)b, (__m256)c, 0x0b), 0x0b);
  else
    return (F)_mm_range_ps((__m128)a, _mm_range_ps((__m128)b, (__m128)c, 0x0b), 0x0b);
#else
  return vfmax(vabs(a), vfmax(vabs(b), vabs(c)));
#endif
}

/// Bit i set where lane i of `m` is true (all ones).
template <class I>
inline unsigned mask_bits(I m) {
#if defined(__AVX__)
  if constexpr (sizeof(I) == 32) return unsigned(_mm256_movemask_ps((__m256)m));
#endif
#if defined(__SSE__)
  if constexpr (sizeof(I) == 16) return unsigned(_mm_movemask_ps((__m128)m));
#endif
  unsigned bits = 0;
  for (int i = 0; i < int(sizeof(I) / 4); ++i) bits |= unsigned(m[i] & 1) << i;
  return bits;
}

/// a * b - c * d in double, rounded once to float (exact products).
template <class F>
inline F edge_exact(F a, F b, F c, F d) {
  using D = DoubleOf<F>;
  const D r = __builtin_convertvector(a, D) * __builtin_convertvector(b, D) -
              __builtin_convertvector(c, D) * __builtin_convertvector(d, D);
  return __builtin_convertvector(r, F);
}

}  // namespace block_detail

/// A ray's values for the block test, prepared once per ray (a traversal may test many leaves).
struct BlockRay {
  int kx, ky, kz;                           ///< the watertight test's axis permutation
  block_detail::F8 ox, oy, oz, sx, sy, sz;  ///< permuted origin and shear, in every lane
  block_detail::F8 tmin;                    ///< ray.tmin in every lane

  // Always inlined: with the tie order's longer block test, GCC 12 made it a call at every leaf
  // of the BVH's any-hit rays (AVX2, where it is made per leaf), 7 % more of their instructions.
  [[gnu::always_inline]] explicit BlockRay(const PreparedRay& r)
      : kx(r.kx),
        ky(r.ky),
        kz(r.kz),
        ox(block_detail::splat8(r.ray.o[r.kx])),
        oy(block_detail::splat8(r.ray.o[r.ky])),
        oz(block_detail::splat8(r.ray.o[r.kz])),
        sx(block_detail::splat8(r.sx)),
        sy(block_detail::splat8(r.sy)),
        sz(block_detail::splat8(r.sz)),
        tmin(block_detail::splat8(r.ray.tmin)) {}
};

/// The ray's block values when a traversal tests blocks (kBlocks), nothing otherwise: the
/// per-primitive path does not pay for them.
template <bool kBlocks>
using MaybeBlockRay = std::conditional_t<kBlocks, BlockRay, const PreparedRay&>;

/// Four triangles: vertex coordinates by vertex and axis, one lane per triangle. Unused lanes
/// carry NaN vertices (never hit) and id 0xffffffff. Where eight-lane vectors are native (AVX),
/// a leaf's blocks go in pairs, and a pair holds eight triangles in the same form with rows of
/// eight ([vertex][axis][8 lanes], then the eight ids): each row is one aligned 32-byte load
/// (the pair starts 32-byte aligned, as every block does) instead of two loads and a shuffle.
struct alignas(32) TriangleBlock {
  float v[3][3][4];  ///< [vertex][axis][lane]
  uint32_t id[4];    ///< primitive id of each lane
};
static_assert(sizeof(TriangleBlock) == 160 && sizeof(TriangleBlock) % 32 == 0);

/// The blocks of every leaf, in the order the leaves were added.
class TriangleBlocks {
 public:
  /// Triangles per block.
  static constexpr int kLanes = 4;
  /// True where a leaf's blocks are stored and tested in pairs of eight lanes.
#if defined(__AVX__)
  static constexpr bool kPairs = true;
#else
  static constexpr bool kPairs = false;
#endif
  /// Blocks a leaf of `count` triangles takes.
  static constexpr uint32_t blocks_for(uint32_t count) { return (count + kLanes - 1) / kLanes; }

  /// Makes room for `blocks` blocks, unwritten (the caller fills them all); forgets earlier
  /// contents.
  void resize(size_t blocks);
  /// Writes one leaf: the triangles of `refs` (in order) into the blocks_for(size) blocks from
  /// `first` on (pairs as eight-lane blocks where kPairs), padding the last one. Leaves fill
  /// disjoint blocks, so they may be filled concurrently.
  void fill(uint32_t first, const PrimitiveSet& prims, std::span<const PrimRef> refs);
  /// The same with primitive ids (kNoPrim marks a padding lane).
  void fill(uint32_t first, const PrimitiveSet& prims, std::span<const uint32_t> ids);
  /// Memory held.
  size_t bytes() const { return blocks_.capacity() * sizeof(TriangleBlock); }
  /// Number of blocks.
  size_t size() const { return blocks_.size(); }
  /// Block `i` (for prefetching).
  const TriangleBlock* block(uint32_t i) const { return &blocks_[i]; }
  /// Starts loading the blocks of the leaf of `count` triangles at block `first` (up to the
  /// lines of kPrefetchTriangles triangles: a larger leaf's rest is left to the hardware).
  void prefetch(uint32_t first, uint32_t count) const {
    prefetch_bytes<kPrefetchLines>(block(first), blocks_for(count) * sizeof(TriangleBlock));
  }
  /// The largest leaf whose blocks prefetch() loads whole (the 16-wide BVH's largest leaf).
  static constexpr uint32_t kPrefetchTriangles = 16;

  /// Tests the leaf of `count` triangles starting at block `first` on (tmin, hit.t); updates
  /// `hit` exactly as testing them one by one with the scalar test would (in any order: the
  /// closest hit is the least (t, id), hit.h).
  /// kAnyHit: returns true as soon as one block has a hit, leaving `hit` unspecified. `cost`
  /// counts the triangles of the blocks tested (all `count` unless an any-hit test stops early).
  template <bool kAnyHit, class Cost = NoCost>
  bool intersect(const BlockRay& r, uint32_t first, uint32_t count, Hit& hit, Cost cost = {}) const;

 private:
  // Not zeroed when sized: the callers fill() every leaf, which writes every block (a zeroing pass over the tens
  // of megabytes of a million triangles' blocks took a tenth of the BVH build, serially).
  std::vector<TriangleBlock, NoInitArrayAllocator<TriangleBlock>> blocks_;
  /// Lines of kPrefetchTriangles triangles' blocks, one more where they start half-way through
  /// a line.
  static constexpr int kPrefetchLines = int(
      ((kPrefetchTriangles + kLanes - 1) / kLanes * sizeof(TriangleBlock) + 32 + kCacheLine - 1) /
      kCacheLine);

  /// The words of block `b` on: one block's 40 (36 coordinates, 4 ids), or a pair's 80.
  const float* words(uint32_t b) const { return blocks_.data()[b].v[0][0]; }
  /// Writes `lanes` (4 or 8) triangles id(0), id(1), ... from block `b` on.
  template <class IdAt>
  void write(uint32_t b, int lanes, const PrimitiveSet& prims, IdAt id);
  /// Writes a leaf of `n` triangles id(0) .. id(n - 1) from block `first` on.
  template <class IdAt>
  void write_leaf(uint32_t first, uint32_t n, const PrimitiveSet& prims, IdAt id);
};

namespace block_detail {

/// Coordinate `axis` of vertex `k` of the lanes whose words start at `w`: one block's four
/// lanes (F4) or a pair's eight (F8), each a row of the block.
template <class F>
inline F lanes(const float* w, int k, int axis) {
  // A plain vector load (the rows are aligned to their size): through memcpy, GCC stored one
  // row to the stack and loaded it back in the eight-lane test.
  using Row [[gnu::may_alias]] = F;
  return *reinterpret_cast<const Row*>(w + (3 * k + axis) * int(sizeof(F) / 4));
}
/// Primitive id of lane i of the lanes whose words start at `w`.
template <class F>
inline uint32_t lane_id(const float* w, int i) {
  uint32_t id;
  __builtin_memcpy(&id, w + 9 * int(sizeof(F) / 4) + i, sizeof id);
  return id;
}
/// A ray value at the lane count of F.
template <class F>
inline F ray_lanes(F8 x) {
  if constexpr (sizeof(F) == 16)
    return low(x);
  else
    return x;
}

/// Tests the lanes of F (one block, or a pair, whose words start at `blk`) against `r` on
/// (tmin, hit.t) and accepts their hits by (t, id), as the scalar loop would; returns whether
/// one was found (kAnyHit: as soon as one is, leaving `hit` unspecified).
template <bool kAnyHit, class F>
[[gnu::always_inline]] inline bool test_lanes(const BlockRay& r, const float* blk, Hit& hit) {
  using I = IntOf<F>;
  const int kx = r.kx, ky = r.ky, kz = r.kz;
  const F ox = ray_lanes<F>(r.ox), oy = ray_lanes<F>(r.oy), oz = ray_lanes<F>(r.oz);
  const F sx = ray_lanes<F>(r.sx), sy = ray_lanes<F>(r.sy), sz = ray_lanes<F>(r.sz);
  const F tmin = ray_lanes<F>(r.tmin);
  const F zero = splat<F>(0.0f);
  // Vertices relative to the origin, sheared so that the ray runs along +z.
  const F Az = lanes<F>(blk, 0, kz) - oz, Bz = lanes<F>(blk, 1, kz) - oz,
          Cz = lanes<F>(blk, 2, kz) - oz;
  const F ax = (lanes<F>(blk, 0, kx) - ox) - sx * Az, ay = (lanes<F>(blk, 0, ky) - oy) - sy * Az;
  const F bx = (lanes<F>(blk, 1, kx) - ox) - sx * Bz, by = (lanes<F>(blk, 1, ky) - oy) - sy * Bz;
  const F cx = (lanes<F>(blk, 2, kx) - ox) - sx * Cz, cy = (lanes<F>(blk, 2, ky) - oy) - sy * Cz;
  // Edge functions in float; lanes where one is zero take all three from double (as the
  // scalar test does: triangle.h).
  F U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
  const I exact = (U == zero) | (V == zero) | (W == zero);
  if (mask_bits(exact)) [[unlikely]] {
    U = exact ? edge_exact(cx, by, cy, bx) : U;
    V = exact ? edge_exact(ax, cy, ay, cx) : V;
    W = exact ? edge_exact(bx, ay, by, ax) : W;
  }
  // Inside: edge functions of one sign. Most lanes are missed here.
  I ok = ~((vmin(U, vmin(V, W)) < zero) & (vmax(U, vmax(V, W)) > zero));
  if (!mask_bits(ok)) return false;
  const F det = (U + V) + W;
  const F adet = vabs(det);
  ok &= adet > zero;  // not degenerate (false for NaN)
  const F az = sz * Az, bz = sz * Bz, cz = sz * Cz;
  const F T = ((U * az) + (V * bz)) + (W * cz);
  const F sT = (F)((I)T ^ ((I)det & (I{} + INT32_MIN)));
  // Up to the hit so far, inclusive when there is one (a positive t: one ulp up is the next
  // bit pattern): a lane at its very t may have a lower id (hit.h, tie_bound), which the loop
  // below decides. The range check before the division as triangle.h's, by its widened limit.
  // (Any-hit queries have no hit so far: their bound is the ray's tmax.)
  const float bound =
      kAnyHit ? hit.t
              : std::bit_cast<float>(std::bit_cast<uint32_t>(hit.t) + uint32_t(hit.valid()));
  const F limit = splat<F>(bound * kRangeWiden) * adet;
  ok &= ~(sT <= tmin * adet) & ~((sT > limit) & (limit > splat<F>(kRangeTiny)));
  if (!mask_bits(ok)) return false;
  const F inv = 1.0f / det;
  const F t = T * inv;
  // The conservative bound on the error of t (pbrt-v3 section 3.9.6), as in triangle.h.
  const F max_zt = max_abs3(az, bz, cz);
  const F max_xt = max_abs3(ax, bx, cx);
  const F max_yt = max_abs3(ay, by, cy);
  const F max_e = max_abs3(U, V, W);
  const F delta_t = triangle_t_error(max_e, max_xt, max_yt, max_zt) * vabs(inv);
  ok &= (t > delta_t) & (t > tmin) & (t < splat<F>(bound));
  unsigned hits = mask_bits(ok);
  if (!hits) return false;
  if constexpr (kAnyHit) return true;
  // Accept the candidates by (t, id), as the scalar loop would: each hit shrinks the interval.
  bool accepted = false;
  for (; hits; hits &= hits - 1) {
    const int i = std::countr_zero(hits);
    const uint32_t id = lane_id<F>(blk, i);
    if (!(t[i] < hit.t || (t[i] == hit.t && id < hit.prim))) continue;
    hit.t = t[i];
    hit.u = V[i] * inv[i];
    hit.v = W[i] * inv[i];
    hit.prim = id;
    accepted = true;
  }
  return accepted;
}

}  // namespace block_detail

template <bool kAnyHit, class Cost>
[[gnu::always_inline]] inline bool TriangleBlocks::intersect(const BlockRay& r, uint32_t first,
                                                             uint32_t count, Hit& hit,
                                                             Cost cost) const {
  using namespace block_detail;
  bool found = false;
  uint32_t b = first;
  const uint32_t end = first + blocks_for(count);
  // Counted: the triangles (not the padding lanes) of each block or pair tested.
  if constexpr (kPairs) {
    // A pair of blocks at a time, as eight lanes (the layout write_leaf gave them).
    for (; b + 1 < end; b += 2) {
      if constexpr (Cost::kCounts)
        cost.prims(std::min<uint32_t>(count - (b - first) * kLanes, 2 * kLanes));
      if (test_lanes<kAnyHit, F8>(r, words(b), hit)) {
        if constexpr (kAnyHit) return true;
        found = true;
      }
    }
  }
  for (; b < end; ++b) {
    if constexpr (Cost::kCounts)
      cost.prims(std::min<uint32_t>(count - (b - first) * kLanes, kLanes));
    if (test_lanes<kAnyHit, F4>(r, words(b), hit)) {
      if constexpr (kAnyHit) return true;
      found = true;
    }
  }
  return found;
}

}  // namespace penumbra
