#pragma once
/// Building blocks of stratified and low-discrepancy samplers: bit reversal, the (0,2)-sequence,
/// hash-based Owen scrambling and random permutations without tables.
#include <cstdint>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace penumbra {

/// Reverses the 32 bits of x.
constexpr uint32_t reverse_bits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
  return x;
}

#if defined(__AVX2__)
/// 8 lanes of 32 bits, in GCC's vector extension (its shifts, products and XORs are lane-wise).
using U32x8 = uint32_t __attribute__((vector_size(32)));

/// reverse_bits of each of 8 lanes on AVX2: the bits of every byte reversed by two table lookups
/// of its nibbles (pshufb), then the bytes of every lane by a byte shuffle. Seven instructions
/// instead of the 23 shifts, masks and ORs that the portable version vectorises to (the Sobol'
/// sampler reverses three values per dimension).
inline U32x8 reverse_bits(U32x8 x) {
  // rev4[i] is i's 4 bits reversed; the low nibble's goes to the top of the byte and vice versa.
  const __m256i rev_hi = _mm256_setr_epi8(0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15, 0,
                                          8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15);
  const __m256i rev_lo = _mm256_slli_epi16(rev_hi, 4);  // no carry across bytes: values < 16
  const __m256i nibble = _mm256_set1_epi8(0x0f);
  const __m256i v = __m256i(x);
  const __m256i lo = _mm256_and_si256(v, nibble);
  const __m256i hi = _mm256_and_si256(_mm256_srli_epi16(v, 4), nibble);
  const __m256i bytes =
      _mm256_or_si256(_mm256_shuffle_epi8(rev_lo, lo), _mm256_shuffle_epi8(rev_hi, hi));
  // Per 128-bit half, bytes 3 2 1 0, 7 6 5 4, ...: every 32-bit lane byte-swapped.
  const __m256i bswap = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2,
                                         1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
  return U32x8(_mm256_shuffle_epi8(bytes, bswap));
}
#endif

/// First dimension of the Sobol' sequence (the base-2 van der Corput sequence) as 32-bit fraction.
constexpr uint32_t sobol_dim0(uint32_t i) {
  return reverse_bits(i);
}

/// Second dimension of the Sobol' sequence as a 32-bit fraction; with `sobol_dim0` it forms the
/// (0,2)-sequence in base 2 (Kollig, Keller 2002, "Efficient Multidimensional Sampling"): every
/// aligned block of 2^k points is stratified in every elementary interval of area 2^-k.
constexpr uint32_t sobol_dim1(uint32_t i) {
  uint32_t r = 0;
  // Branch-free: the bits of i are as unpredictable as the sample indices.
  for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1) r ^= v & (0u - (i & 1u));
  return r;
}

/// reverse_bits(sobol_dim1(i)) in a few operations and without a loop. The second dimension's
/// generator matrix is Pascal's triangle mod 2: bit k of i contributes to fraction digit p (bit
/// 31 - p) when C(k, p) is odd, which by Lucas' theorem is when p's bits are a subset of k's. So
/// digit p is the XOR of the bits k of i over the supersets k of p: the superset-XOR (binary
/// Moebius) transform of i over the five bits of a position, one masked shift per bit.
/// Also lane-wise on GCC vectors of uint32_t (the Sobol' sampler's batch).
template <class U>
constexpr U sobol_dim1_reversed(U i) {
  i ^= (i >> 1) & 0x55555555u;
  i ^= (i >> 2) & 0x33333333u;
  i ^= (i >> 4) & 0x0f0f0f0fu;
  i ^= (i >> 8) & 0x00ff00ffu;
  i ^= (i >> 16) & 0x0000ffffu;
  return i;
}

/// The hash-based nested uniform (Owen) scramble of a 32-bit fraction (Burley 2020, "Practical
/// Hash-based Owen Scrambling", JCGT 9(4)): the Laine-Karras permutation applied to the
/// bit-reversed value, so each bit is flipped depending only on the bits above it. The
/// permutation is also lane-wise on GCC vectors of uint32_t.
template <class U>
constexpr U laine_karras_permutation(U x, U seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}
constexpr uint32_t owen_scramble(uint32_t v, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(v), seed));
}

/// owen_scramble(sobol_dim0(i), seed) without its two cancelling bit reversals.
constexpr uint32_t owen_scrambled_dim0(uint32_t i, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(i, seed));
}

/// owen_scramble(sobol_dim1(i), seed) without its two cancelling bit reversals.
constexpr uint32_t owen_scrambled_dim1(uint32_t i, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(sobol_dim1_reversed(i), seed));
}

/// Element i of a pseudo-random permutation of [0, n) chosen by `seed`, without tables
/// (Kensler 2013, "Correlated Multi-Jittered Sampling", Pixar technical memo 13-01).
constexpr uint32_t permutation_element(uint32_t i, uint32_t n, uint32_t seed) {
  uint32_t w = n - 1;
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= seed;
    i *= 0xe170893du;
    i ^= seed >> 16;
    i ^= (i & w) >> 4;
    i ^= seed >> 8;
    i *= 0x0929eb3fu;
    i ^= seed >> 23;
    i ^= (i & w) >> 1;
    i *= 1u | seed >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);  // cycle-walking: at most a few rounds since w < 2n
  return (i + seed) % n;
}

/// A 32-bit fraction as a float in [0, 1) (rounded down so that 1 is never returned).
constexpr float fraction_to_float(uint32_t v) {
  return float(v >> 8) * 0x1p-24f;
}

}  // namespace penumbra
