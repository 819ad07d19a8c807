#pragma once
/// Random numbers: the PCG32 generator with independent streams, and hashing to derive seeds.
#include <cstdint>

namespace penumbra {

/// Mixes a 64-bit value (the SplitMix64 finaliser; Steele, Lea, Flood 2014, "Fast splittable
/// pseudorandom number generators").
constexpr uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  x ^= x >> 31;
  return x;
}

/// Mixes a 32-bit value (Wellons' "lowbias32" from his hash prospector, 2018: two products and
/// three xor-shifts, bias 0.17). Also lane-wise on GCC vectors of uint32_t, where AVX2 multiplies
/// 32-bit lanes natively (64-bit products it emulates with three 32-bit ones and shifts).
template <class U>
constexpr U mix32(U x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/// Hash of several integers, order-sensitive; used to derive seeds from (pixel, sample, seed).
constexpr uint64_t hash_combine(uint64_t a, uint64_t b) {
  return mix64(a ^ (mix64(b) + 0x9e3779b97f4a7c15ull));
}

/// PCG-XSH-RR 64/32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
/// Algorithms for Random Number Generation"). Each odd increment selects an independent stream.
class Pcg32 {
 public:
  /// Generator for a seed and a stream selector.
  constexpr explicit Pcg32(uint64_t seed = 0x853c49e6748fea9bull,
                           uint64_t stream = 0xda3e39cb94b95bdbull) {
    set(seed, stream);
  }
  /// Restarts the generator at (seed, stream).
  constexpr void set(uint64_t seed, uint64_t stream) {
    state_ = 0;
    inc_ = (stream << 1u) | 1u;
    next_u32();
    state_ += seed;
    next_u32();
  }
  /// Uniform 32-bit integer.
  constexpr uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }
  /// Uniform float in [0, 1): the top 24 bits, so 1 is never returned.
  constexpr float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }
  /// Uniform double in [0, 1).
  constexpr double next_double() {
    const uint64_t hi = next_u32(), lo = next_u32();
    return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1p-53;
  }
  /// Uniform integer in [0, bound) without modulo bias (Lemire 2019, "Fast Random Integer
  /// Generation in an Interval").
  constexpr uint32_t next_bounded(uint32_t bound) {
    uint64_t m = uint64_t(next_u32()) * bound;
    auto l = static_cast<uint32_t>(m);
    if (l < bound) {
      const uint32_t t = (~bound + 1u) % bound;
      while (l < t) {
        m = uint64_t(next_u32()) * bound;
        l = static_cast<uint32_t>(m);
      }
    }
    return static_cast<uint32_t>(m >> 32);
  }

 private:
  uint64_t state_ = 0;
  uint64_t inc_ = 1;
};

}  // namespace penumbra
