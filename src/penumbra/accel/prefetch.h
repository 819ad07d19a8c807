#pragma once
/// Software prefetches of whole nodes and leaves for the traversals.
///
/// On x86 each line's prefetch is an asm statement, which the compiler emits as written. GCC 12
/// (-O3 -march=native, Zen 4) dropped a loop of __builtin_prefetch calls over a leaf's lines
/// down to its first: wide_bvh.cpp's object code came out the same whether the loop was capped
/// at one line or at two to ten (docs/accel.md, "2026-12-06, nineteenth session").
#include <cstddef>
#include <cstdint>

namespace penumbra {

/// Bytes per cache line assumed by the prefetches.
inline constexpr size_t kCacheLine = 64;

/// Starts loading the cache line that holds `p` into every cache level.
[[gnu::always_inline]] inline void prefetch_line(const void* p) {
#if defined(__x86_64__) || defined(__i386__)
  asm volatile("prefetcht0 %0" ::"m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

/// Starts loading the lines that the `bytes` bytes from `p` on touch, at most kMaxLines of them
/// (the first ones).
template <int kMaxLines>
[[gnu::always_inline]] inline void prefetch_bytes(const void* p, size_t bytes) {
  const auto a = reinterpret_cast<uintptr_t>(p);
  const uintptr_t first = a & ~uintptr_t(kCacheLine - 1), end = a + bytes;
#pragma GCC unroll 16
  for (int l = 0; l < kMaxLines; ++l)
    if (first + l * kCacheLine < end)
      prefetch_line(reinterpret_cast<const void*>(first + l * kCacheLine));
}

}  // namespace penumbra
