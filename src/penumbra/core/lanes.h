#pragma once
/// Eight floats at once, for code that shades many paths together (path's lanes): GCC's vector
/// types, which compile to one AVX instruction per operation where the machine has AVX and to
/// SSE pairs or scalar code elsewhere. Every operation rounds as its scalar counterpart does (the
/// build turns floating-point contraction off), so a lane computes the same floats as the scalar
/// code it mirrors.
#include <cstdint>
#include <cstring>
#include <limits>

#include "penumbra/core/vec.h"

#if defined(__AVX__)
#include <immintrin.h>
#endif

// Without AVX, GCC notes that 32-byte vector arguments pass differently than with it; these
// functions are inline and never cross a library boundary, so the note does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace penumbra::lanes {

/// Lanes per vector.
inline constexpr int kWidth = 8;

using F8 = float __attribute__((vector_size(32)));
/// Comparison results: -1 (all bits set) where true, 0 where false.
using I8 = int32_t __attribute__((vector_size(32)));
using U8 = uint32_t __attribute__((vector_size(32)));

/// v in every lane.
inline F8 splat(float v) {
  return F8{} + v;
}
/// Square root per lane, correctly rounded like std::sqrt.
inline F8 sqrt(F8 v) {
#if defined(__AVX__)
  return (F8)_mm256_sqrt_ps((__m256)v);
#else
  F8 r;
  for (int i = 0; i < kWidth; ++i) r[i] = std::sqrt(v[i]);
  return r;
#endif
}
/// |v| per lane (the sign bit cleared, as std::fabs).
inline F8 abs(F8 v) {
  return (F8)((U8)v & 0x7fffffffu);
}
/// a where m, else b.
inline F8 select(I8 m, F8 a, F8 b) {
  return m ? a : b;
}
/// std::max(a, b) per lane: (a < b) ? b : a, NaNs included.
inline F8 max(F8 a, F8 b) {
  return a < b ? b : a;
}
/// True where v is finite (not infinite, not NaN).
inline I8 is_finite(F8 v) {
  return abs(v) < std::numeric_limits<float>::infinity();
}
/// One bit per lane: bit i set where m is true in lane i.
inline unsigned bits(I8 m) {
#if defined(__AVX__)
  return unsigned(_mm256_movemask_ps((__m256)m));
#else
  unsigned b = 0;
  for (int i = 0; i < kWidth; ++i) b |= unsigned(m[i] != 0) << i;
  return b;
#endif
}

/// The floats base[idx[i]] (AVX2's gather where the machine has it).
inline F8 gather(const float* base, I8 idx) {
#if defined(__AVX2__)
  return (F8)_mm256_i32gather_ps(base, (__m256i)idx, 4);
#else
  F8 r;
  for (int i = 0; i < kWidth; ++i) r[i] = base[idx[i]];
  return r;
#endif
}

/// Eight lane values written one at a time, then read as one vector. A vector variable written
/// lane by lane is stored and reloaded whole around every write when the compiler keeps it in a
/// register, and each reload waits for a narrower store it cannot be forwarded from (perf put
/// several percent of path's lanes on such reloads); the buffer takes the writes in memory and
/// is loaded once.
template <class V, class T>
struct LaneBuf {
  alignas(32) T v[kWidth] = {};
  V load() const {
    V r;
    std::memcpy(&r, v, sizeof r);
    return r;
  }
};
using F8Buf = LaneBuf<F8, float>;
/// The same for masks and integers.
using I8Buf = LaneBuf<I8, int32_t>;

/// Eight 3-vectors, one per lane.
struct V3 {
  F8 x, y, z;
  /// Lane i as a Vec3.
  Vec3 lane(int i) const { return {x[i], y[i], z[i]}; }
  /// Sets lane i.
  void set(int i, Vec3 v) { x[i] = v.x, y[i] = v.y, z[i] = v.z; }
};
/// Eight 3-vectors written lane by lane, then read as one V3 (see F8Buf).
struct V3Buf {
  F8Buf x, y, z;
  void set(int i, Vec3 a) { x.v[i] = a.x, y.v[i] = a.y, z.v[i] = a.z; }
  Vec3 lane(int i) const { return {x.v[i], y.v[i], z.v[i]}; }
  V3 load() const { return {x.load(), y.load(), z.load()}; }
};
inline V3 operator+(V3 a, V3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline V3 operator-(V3 a, V3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline V3 operator-(V3 a) {
  return {-a.x, -a.y, -a.z};
}
inline V3 operator*(V3 a, F8 s) {
  return {a.x * s, a.y * s, a.z * s};
}
inline V3 operator/(V3 a, F8 s) {
  return {a.x / s, a.y / s, a.z / s};
}
/// Componentwise product (Vec3 * Vec3, Rgb * Rgb).
inline V3 operator*(V3 a, V3 b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
/// The same operation order as penumbra::dot.
inline F8 dot(V3 a, V3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
/// The same operation order as penumbra::cross.
inline V3 cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline V3 abs(V3 v) {
  return {abs(v.x), abs(v.y), abs(v.z)};
}
inline V3 select(I8 m, V3 a, V3 b) {
  return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z};
}
/// std::max(r, std::max(g, b)) per lane (Rgb::max_channel).
inline F8 max_component(V3 v) {
  return max(v.x, max(v.y, v.z));
}

/// penumbra::normalize per lane. Lanes whose squared length leaves (kSafeLengthSqLo,
/// kSafeLengthSqHi) take the scalar function's rescaled path, one lane at a time.
inline V3 normalize(V3 v) {
  const F8 l2 = dot(v, v);
  V3 r = v / sqrt(l2);
  if (unsigned odd = bits(~((l2 > kSafeLengthSqLo) & (l2 < kSafeLengthSqHi)))) [[unlikely]]
    for (; odd; odd &= odd - 1) {
      const int i = __builtin_ctz(odd);
      r.set(i, penumbra::normalize(v.lane(i)));
    }
  return r;
}

/// penumbra::orthonormal_basis per lane (Duff et al. 2017): t and b complete n to a frame.
inline void orthonormal_basis(V3 n, V3& t, V3& b) {
  const F8 sign = (F8)(((U8)n.z & 0x80000000u) | (U8)splat(1.0f));  // copysign(1, n.z)
  const F8 a = splat(-1.0f) / (sign + n.z);
  const F8 c = n.x * n.y * a;
  t = {splat(1.0f) + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

/// penumbra::offset_ray_origin per lane: p moved off its surface along n by the error bound, to
/// the side of w, then to the next float away from p on each axis (the same floats).
inline V3 offset_ray_origin(V3 p, V3 p_error, V3 n, V3 w) {
  const F8 d = dot(abs(n), p_error);
  const F8 s = (F8)((U8)d ^ ((U8)(dot(w, n) < 0.0f) & 0x80000000u));
  const auto axis = [&](F8 pc, F8 nc) {
    F8 offset = nc * s;
#if defined(__AVX__)
    asm("" : "+x"(offset));  // two roundings, as the scalar form (no FMA)
#endif
    const F8 po = pc + offset;
    const U8 b = (U8)po;
    const U8 toward_up = (U8) ~(po > 0.0f) | 1u;  // +1 where positive, else -1 (all bits)
    const I8 is_zero = po == 0.0f;
    const U8 up = is_zero ? U8{} + 1u : b + toward_up;
    const U8 down = is_zero ? U8{} + 0x80000001u : b - toward_up;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const I8 move_up = (offset > 0.0f) & (po < kInf);
    const I8 move_down = (offset < 0.0f) & (po > -kInf);
    return (F8)(move_up ? up : (move_down ? down : b));
  };
  return {axis(p.x, n.x), axis(p.y, n.y), axis(p.z, n.z)};
}

}  // namespace penumbra::lanes
