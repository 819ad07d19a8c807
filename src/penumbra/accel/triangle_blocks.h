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
#include <bit>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "penumbra/accel/build/array_allocator.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/hit.h"
#include "penumbra/geometry/primitive_set.h"

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace penumbra {

namespace block_detail {

using F4 = float __attribute__((vector_size(16)));
using I4 = int32_t __attribute__((vector_size(16)));
using D4 = double __attribute__((vector_size(32)));

inline F4 load(const float* p) {
  F4 r;
  __builtin_memcpy(&r, p, sizeof r);
  return r;
}
inline F4 splat(float x) {
  return F4{x, x, x, x};
}
/// std::min and std::max lane-wise, with their operand order (so NaN behaves the same).
inline F4 vmin(F4 a, F4 b) {
  return b < a ? b : a;
}
inline F4 vmax(F4 a, F4 b) {
  return a < b ? b : a;
}
inline F4 vabs(F4 a) {
  return (F4)((I4)a & I4{0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff});
}
/// fmax as the scalar test uses it (no NaN can reach it: such lanes were rejected).
inline F4 vfmax(F4 a, F4 b) {
  return a < b ? b : a;
}
/// Bit i set where lane i of `m` is true (all ones).
inline unsigned mask_bits(I4 m) {
#if defined(__SSE__)
  return unsigned(_mm_movemask_ps((__m128)m));
#else
  return unsigned(m[0] & 1) | unsigned(m[1] & 1) << 1 | unsigned(m[2] & 1) << 2 |
         unsigned(m[3] & 1) << 3;
#endif
}
/// a * b - c * d in double, rounded once to float (exact products).
inline F4 edge_exact(F4 a, F4 b, F4 c, F4 d) {
  const D4 r = __builtin_convertvector(a, D4) * __builtin_convertvector(b, D4) -
               __builtin_convertvector(c, D4) * __builtin_convertvector(d, D4);
  return __builtin_convertvector(r, F4);
}

}  // namespace block_detail

/// A ray's values for the block test, prepared once per ray (a traversal may test many leaves).
struct BlockRay {
  int kx, ky, kz;                           ///< the watertight test's axis permutation
  block_detail::F4 ox, oy, oz, sx, sy, sz;  ///< permuted origin and shear, in every lane
  block_detail::F4 tmin;                    ///< ray.tmin in every lane

  explicit BlockRay(const PreparedRay& r)
      : kx(r.kx),
        ky(r.ky),
        kz(r.kz),
        ox(block_detail::splat(r.ray.o[r.kx])),
        oy(block_detail::splat(r.ray.o[r.ky])),
        oz(block_detail::splat(r.ray.o[r.kz])),
        sx(block_detail::splat(r.sx)),
        sy(block_detail::splat(r.sy)),
        sz(block_detail::splat(r.sz)),
        tmin(block_detail::splat(r.ray.tmin)) {}
};

/// The ray's block values when a traversal tests blocks (kBlocks), nothing otherwise: the
/// per-primitive path does not pay for them.
template <bool kBlocks>
using MaybeBlockRay = std::conditional_t<kBlocks, BlockRay, const PreparedRay&>;

/// Four triangles: vertex coordinates by vertex and axis, one lane per triangle. Unused lanes
/// carry NaN vertices (never hit) and id 0xffffffff.
struct alignas(16) TriangleBlock {
  float v[3][3][4];  ///< [vertex][axis][lane]
  uint32_t id[4];    ///< primitive id of each lane
};

/// The blocks of every leaf, in the order the leaves were added.
class TriangleBlocks {
 public:
  /// Triangles per block.
  static constexpr int kLanes = 4;
  /// Blocks a leaf of `count` triangles takes.
  static constexpr uint32_t blocks_for(uint32_t count) { return (count + kLanes - 1) / kLanes; }

  /// Makes room for `blocks` blocks; forgets earlier contents.
  void resize(size_t blocks);
  /// Writes the triangles of `refs` (in order) into the blocks from `first` on, padding the last
  /// block. Leaves fill disjoint blocks, so they may be filled concurrently.
  void fill(uint32_t first, const PrimitiveSet& prims, std::span<const PrimRef> refs);
  /// Makes one block per four of `ids` (a multiple of four long; kNoPrim marks padding), in
  /// order, in parallel.
  void assign(const PrimitiveSet& prims, std::span<const uint32_t> ids);
  /// Memory held.
  size_t bytes() const { return blocks_.capacity() * sizeof(TriangleBlock); }
  /// Number of blocks.
  size_t size() const { return blocks_.size(); }
  /// Block `i` (for prefetching).
  const TriangleBlock* block(uint32_t i) const { return &blocks_[i]; }

  /// Tests the leaf of `count` triangles starting at block `first` on (tmin, hit.t); updates
  /// `hit` exactly as testing them one by one in order with the scalar test would.
  /// kAnyHit: returns true as soon as one block has a hit, leaving `hit` unspecified.
  template <bool kAnyHit>
  bool intersect(const BlockRay& r, uint32_t first, uint32_t count, Hit& hit) const;

 private:
  std::vector<TriangleBlock, ArrayAllocator<TriangleBlock>> blocks_;
};

template <bool kAnyHit>
bool TriangleBlocks::intersect(const BlockRay& r, uint32_t first, uint32_t count, Hit& hit) const {
  using namespace block_detail;
  const int kx = r.kx, ky = r.ky, kz = r.kz;
  const F4 ox = r.ox, oy = r.oy, oz = r.oz, sx = r.sx, sy = r.sy, sz = r.sz, tmin = r.tmin;
  const F4 zero = splat(0.0f);
  bool found = false;
  const uint32_t end = first + blocks_for(count);
  for (uint32_t b = first; b < end; ++b) {
    const TriangleBlock& blk = blocks_[b];
    // Vertices relative to the origin, sheared so that the ray runs along +z.
    const F4 Az = load(blk.v[0][kz]) - oz, Bz = load(blk.v[1][kz]) - oz,
             Cz = load(blk.v[2][kz]) - oz;
    const F4 ax = (load(blk.v[0][kx]) - ox) - sx * Az, ay = (load(blk.v[0][ky]) - oy) - sy * Az;
    const F4 bx = (load(blk.v[1][kx]) - ox) - sx * Bz, by = (load(blk.v[1][ky]) - oy) - sy * Bz;
    const F4 cx = (load(blk.v[2][kx]) - ox) - sx * Cz, cy = (load(blk.v[2][ky]) - oy) - sy * Cz;
    // Edge functions in float; lanes where one is zero take all three from double (as the
    // scalar test does: triangle.h).
    F4 U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    const I4 exact = (U == zero) | (V == zero) | (W == zero);
    if (mask_bits(exact)) [[unlikely]] {
      U = exact ? edge_exact(cx, by, cy, bx) : U;
      V = exact ? edge_exact(ax, cy, ay, cx) : V;
      W = exact ? edge_exact(bx, ay, by, ax) : W;
    }
    // Inside: edge functions of one sign. Most blocks are missed here.
    I4 ok = ~((vmin(U, vmin(V, W)) < zero) & (vmax(U, vmax(V, W)) > zero));
    if (!mask_bits(ok)) continue;
    const F4 det = (U + V) + W;
    const F4 adet = vabs(det);
    ok &= adet > zero;  // not degenerate (false for NaN)
    const F4 az = sz * Az, bz = sz * Bz, cz = sz * Cz;
    const F4 T = ((U * az) + (V * bz)) + (W * cz);
    const F4 sT = (F4)((I4)T ^ ((I4)det & I4{INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN}));
    const F4 tmax = splat(hit.t);
    ok &= ~(sT <= tmin * adet) & ~(sT >= tmax * adet);
    if (!mask_bits(ok)) continue;
    const F4 inv = 1.0f / det;
    const F4 t = T * inv;
    // The conservative bound on the error of t (pbrt-v3 section 3.9.6), as in triangle.h.
    const F4 max_zt = vfmax(vabs(az), vfmax(vabs(bz), vabs(cz)));
    const F4 max_xt = vfmax(vabs(ax), vfmax(vabs(bx), vabs(cx)));
    const F4 max_yt = vfmax(vabs(ay), vfmax(vabs(by), vabs(cy)));
    const F4 delta_z = splat(gamma(3)) * max_zt;
    const F4 delta_x = splat(gamma(5)) * (max_xt + max_zt);
    const F4 delta_y = splat(gamma(5)) * (max_yt + max_zt);
    const F4 delta_e =
        splat(2.0f) * (((splat(gamma(2)) * max_xt) * max_yt + delta_y * max_xt) + delta_x * max_yt);
    const F4 max_e = vfmax(vabs(U), vfmax(vabs(V), vabs(W)));
    const F4 delta_t = (splat(3.0f) * (((splat(gamma(3)) * max_e) * max_zt + delta_e * max_zt) +
                                       delta_z * max_e)) *
                       vabs(inv);
    ok &= (t > delta_t) & (t > tmin) & (t < tmax);
    unsigned lanes = mask_bits(ok);
    if (!lanes) continue;
    if constexpr (kAnyHit) return true;
    // Accept the candidates in lane order as the scalar loop would: each hit shrinks the
    // interval, and a later lane must pass the two tests that depend on it again (with their
    // own rounding, so that a t equal to the current one in all but the last bit is decided the
    // same way).
    for (; lanes; lanes &= lanes - 1) {
      const int i = std::countr_zero(lanes);
      if (found && (sT[i] >= hit.t * adet[i] || !(t[i] < hit.t))) continue;
      hit.t = t[i];
      hit.u = V[i] * inv[i];
      hit.v = W[i] * inv[i];
      hit.prim = blk.id[i];
      found = true;
    }
  }
  return found;
}

}  // namespace penumbra
