#pragma once
/// Sorting the few children a wide BVH node's box test keeps, by their entry distances, without
/// branches on the data where that pays: for incoherent rays which child is nearer is a coin
/// toss, so a compare-and-branch mispredicts about half the time.
#include <bit>
#include <cstdint>
#include <utility>

namespace penumbra {

/// A key ordering lane `lane` by `dist`: the float's bits mapped to an unsigned integer of the
/// same order (negative values reversed, -0 just below +0), then the lane (at most 255), so
/// equal distances keep lane order. No NaN reaches it (the box tests' running bounds never
/// become NaN).
inline uint64_t distance_key(float dist, int lane) {
  const uint32_t b = std::bit_cast<uint32_t>(dist);
  const uint32_t ordered = b ^ (uint32_t(int32_t(b) >> 31) | 0x80000000u);
  return uint64_t(ordered) << 32 | uint32_t(lane);
}

/// The lane of a distance_key.
inline int key_lane(uint64_t key) {
  return int(key & 0xffu);
}

/// Orders a and b ascending by selects.
inline void sort2(uint64_t& a, uint64_t& b) {
  const uint64_t lo = a < b ? a : b, hi = a < b ? b : a;
  a = lo, b = hi;
}

/// Sorts key[0, n) ascending: three and four keys by optimal sorting networks (Knuth, TAOCP
/// vol. 3, section 5.3.4) of selects, more by insertion (rare in a traversal).
[[gnu::always_inline]] inline void sort_small(uint64_t* key, int n) {
  if (n == 3) {
    sort2(key[0], key[1]), sort2(key[1], key[2]), sort2(key[0], key[1]);
  } else if (n == 4) {
    sort2(key[0], key[1]), sort2(key[2], key[3]), sort2(key[0], key[2]);
    sort2(key[1], key[3]), sort2(key[1], key[2]);
  } else {
    for (int i = 1; i < n; ++i)
      for (int j = i; j > 0 && key[j] < key[j - 1]; --j) std::swap(key[j], key[j - 1]);
  }
}

}  // namespace penumbra
