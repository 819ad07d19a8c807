#include "penumbra/accel/build/binned_sah.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "penumbra/accel/build/box_accumulator.h"
#include "penumbra/accel/build/bvh_split.h"
#include "penumbra/core/parallel.h"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace penumbra {

namespace {

/// References per parallel binning task: fixed, so the chunking never depends on the thread count.
constexpr size_t kBinChunk = 32768;
/// Nodes with at least this many references bin into two alternating bin sets.
constexpr size_t kSpareMin = 256;

/// Bin boxes and counts of the three axes. A box is stored as eight floats (lo.x, lo.y, lo.z, -,
/// -hi.x, -hi.y, -hi.z, -) with the upper corner negated, so that growing it by a reference is
/// one minimum over eight lanes: a reference costs a load, a minimum and a store per axis (AVX),
/// half the instructions of separate lower and upper corners. The 4th and 8th lanes carry the
/// reference's id and padding bits and are never read.
struct BinSet {
  int bins;
  alignas(32) float box[3][kMaxBins][8];
  uint32_t count[3][kMaxBins];

  /// Empty bins (only the `bins` in use are initialised).
  explicit BinSet(int bins_) : bins(bins_) {
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < bins; ++i) {
        for (int k = 0; k < 8; ++k) box[a][i][k] = kInfinity;
        count[a][i] = 0;
      }
  }

#if defined(__SSE2__)
  /// The bins of one reference on the three axes (SIMD: `org`, `scl` and `top` come from the
  /// mapping, see add()), as the low three lanes.
  static __m128i bins_of(const PrimRef& r, __m128 org, __m128 scl, __m128 top) {
    const __m128 l = _mm_load_ps(&r.lo.x), h = _mm_load_ps(&r.hi.x);
    __m128 f = _mm_mul_ps(_mm_sub_ps(_mm_add_ps(l, h), org), scl);
    f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), top);
    return _mm_cvttps_epi32(f);
  }
  /// Grows the bins `b` (one per axis) by reference `r`.
  void grow(const PrimRef& r, const int32_t* b) {
#if defined(__AVX__)
    const __m256 g = _mm256_xor_ps(_mm256_load_ps(&r.lo.x),
                                   _mm256_setr_ps(0, 0, 0, 0, -0.0f, -0.0f, -0.0f, -0.0f));
#else
    const __m128 l = _mm_load_ps(&r.lo.x);
    const __m128 nh = _mm_xor_ps(_mm_load_ps(&r.hi.x), _mm_set1_ps(-0.0f));
#endif
    for (int a = 0; a < 3; ++a) {
      float* x = box[a][b[a]];
#if defined(__AVX__)
      _mm256_store_ps(x, _mm256_min_ps(_mm256_load_ps(x), g));
#else
      _mm_store_ps(x, _mm_min_ps(_mm_load_ps(x), l));
      _mm_store_ps(x + 4, _mm_min_ps(_mm_load_ps(x + 4), nh));
#endif
      ++count[a][b[a]];
    }
  }
#endif

  /// Adds `refs` to the bins of `map`; `spare` (same bin count) takes every other reference.
  /// Neighbouring references mostly fall into the same bins, and alternating between two bin
  /// sets halves the chains of dependent read-modify-writes on one bin. The bins of a group of
  /// references are computed before any of them is added: interleaved, each bin update waited
  /// for the previous reference's whole chain (its bin address from its coordinates), since the
  /// processor cannot tell in advance that a bin load does not alias the store before it.
  void add(std::span<const PrimRef> refs, const BinMapping& map, BinSet* spare) {
#if defined(__SSE2__)
    // The clamp reproduces BinMapping::bin exactly (max_ps(NaN, 0) is 0), so partitioning
    // agrees with the bins.
    const __m128 org = _mm_setr_ps(map.origin.x, map.origin.y, map.origin.z, 0.0f);
    const __m128 scl = _mm_setr_ps(map.scale.x, map.scale.y, map.scale.z, 0.0f);
    const __m128 top = _mm_set1_ps(float(bins - 1));
    constexpr size_t kGroup = 32;
    alignas(16) int32_t b[kGroup][4];
    BinSet* other = spare ? spare : this;
    for (size_t i = 0; i < refs.size(); i += kGroup) {
      const size_t m = std::min(kGroup, refs.size() - i);
      for (size_t k = 0; k < m; ++k)
        _mm_store_si128(reinterpret_cast<__m128i*>(b[k]), bins_of(refs[i + k], org, scl, top));
      size_t k = 0;
      for (; k + 1 < m; k += 2) {
        grow(refs[i + k], b[k]);
        other->grow(refs[i + k + 1], b[k + 1]);
      }
      if (k < m) grow(refs[i + k], b[k]);
    }
#else
    (void)spare;
    for (const PrimRef& r : refs) {
      const Vec3 c = r.centroid2();
      for (int a = 0; a < 3; ++a) {
        const int i = map.bin(c[a], a);
        float* x = box[a][i];
        for (int k = 0; k < 3; ++k)
          x[k] = std::min(x[k], r.lo[k]), x[4 + k] = std::min(x[4 + k], -r.hi[k]);
        ++count[a][i];
      }
    }
#endif
  }
  /// Adds the bins of `o` (exact: minima and integer sums).
  void merge(const BinSet& o) {
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < bins; ++i) {
        for (int k = 0; k < 8; ++k) box[a][i][k] = std::min(box[a][i][k], o.box[a][i][k]);
        count[a][i] += o.count[a][i];
      }
  }
  /// Box of bin i on axis a.
  Bounds3 bounds(int a, int i) const {
    const float* x = box[a][i];
    Bounds3 b;
    b.lo = {x[0], x[1], x[2]};
    b.hi = {-x[4], -x[5], -x[6]};
    return b;
  }
};

/// A union of bin boxes (BinSet's layout) grown one bin at a time, with the area of
/// BoxAccumulator: the same floats, since negating the upper corner back is exact.
struct BinBoxAccumulator {
  BoxAccumulator acc;
  void add(const float* x) {
#if defined(__SSE2__)
    acc.lo = _mm_min_ps(acc.lo, _mm_load_ps(x));
    acc.hi = _mm_max_ps(acc.hi, _mm_xor_ps(_mm_load_ps(x + 4), _mm_set1_ps(-0.0f)));
#else
    const float l[3] = {x[0], x[1], x[2]}, h[3] = {-x[4], -x[5], -x[6]};
    acc.add(l, h);
#endif
  }
  float area() const {
    return acc.area();
  }
};

/// Bins `refs`, in parallel chunks for large sets.
void bin_refs(std::span<const PrimRef> refs, const BinMapping& map, bool parallel, BinSet& out) {
  const size_t chunks = (refs.size() + kBinChunk - 1) / kBinChunk;
  if (!parallel || chunks < 2) {
    if (refs.size() < kSpareMin) {
      out.add(refs, map, nullptr);
    } else {
      BinSet spare(map.bins);
      out.add(refs, map, &spare);
      out.merge(spare);
    }
    return;
  }
  std::vector<BinSet> partial(2 * chunks, BinSet(map.bins));
  parallel_for(chunks, [&](size_t c) {
    const size_t begin = c * kBinChunk;
    const auto part = refs.subspan(begin, std::min(kBinChunk, refs.size() - begin));
    partial[2 * c].add(part, map, &partial[2 * c + 1]);
  });
  for (const BinSet& p : partial) out.merge(p);  // in chunk order
}

}  // namespace

BinMapping::BinMapping(const Bounds3& centroid_bounds, int bins_) : bins(bins_) {
  origin = centroid_bounds.lo;
  const Vec3 extent = centroid_bounds.diagonal();
  for (int a = 0; a < 3; ++a) {
    // Slightly fewer than `bins` bins per extent keeps the largest centroid inside the last bin.
    const float s = float(bins) * (1.0f - 1e-6f) / extent[a];
    scale[a] = extent[a] > 0.0f && std::isfinite(s) ? s : 0.0f;
  }
}

SahSplit find_binned_split(std::span<const PrimRef> refs, const BinMapping& map, bool parallel,
                           int block_shift) {
  BinSet set(map.bins);
  bin_refs(refs, map, parallel, set);
  const int nb = map.bins;
  SahSplit best;
  // The three axes' sweeps side by side (independent chains of box growth, which the processor
  // overlaps); the choice below scans the costs in the order of one axis after another, so the
  // split is the one a sweep per axis finds. From the right: area and count of bins [i, nb).
  float right_area[3][kMaxBins];
  uint32_t right_count[3][kMaxBins];
  {
    BinBoxAccumulator acc[3];
    uint32_t n[3] = {0, 0, 0};
    for (int i = nb - 1; i > 0; --i)
      for (int a = 0; a < 3; ++a) {
        acc[a].add(set.box[a][i]);
        n[a] += set.count[a][i];
        right_area[a][i] = acc[a].area(), right_count[a][i] = n[a];
      }
  }
  // From the left, the cost at each boundary where both sides hold references.
  float cost[3][kMaxBins];
  bool valid[3][kMaxBins];
  {
    BinBoxAccumulator acc[3];
    uint32_t n[3] = {0, 0, 0};
    for (int i = 1; i < nb; ++i)
      for (int a = 0; a < 3; ++a) {
        acc[a].add(set.box[a][i - 1]);
        n[a] += set.count[a][i - 1];
        valid[a][i] = n[a] != 0 && right_count[a][i] != 0;
        cost[a][i] = acc[a].area() * sah_tests(n[a], block_shift) +
                     right_area[a][i] * sah_tests(right_count[a][i], block_shift);
      }
  }
  // Ties keep the first split (axis by axis, left to right).
  for (int a = 0; a < 3; ++a) {
    if (map.scale[a] == 0.0f) continue;
    for (int i = 1; i < nb; ++i)
      if (valid[a][i] && (best.axis < 0 || cost[a][i] < best.cost))
        best.axis = a, best.pos = i, best.cost = cost[a][i];
  }
  if (best.axis < 0) return best;
  for (int i = 0; i < nb; ++i) {
    const int a = best.axis;
    if (i < best.pos)
      best.left.extend(set.bounds(a, i)), best.left_count += set.count[a][i];
    else
      best.right.extend(set.bounds(a, i)), best.right_count += set.count[a][i];
  }
  return best;
}

namespace {

/// Centroid bounds (of lo + hi) grown one reference at a time; SIMD where available.
struct CentroidBounds {
  BoxAccumulator box;
#if defined(__SSE2__)
  void add(__m128 lo, __m128 hi) {
    const __m128 c = _mm_add_ps(lo, hi);
    box.lo = _mm_min_ps(box.lo, c);
    box.hi = _mm_max_ps(box.hi, c);
  }
  void add(const PrimRef& r) {
    add(_mm_load_ps(&r.lo.x), _mm_load_ps(&r.hi.x));
  }
#else
  void add(const PrimRef& r) {
    const Vec3 c = r.centroid2();
    box.add(&c.x, &c.x);
  }
#endif
#if defined(__AVX__)
  /// add() of a reference held in a register (lo in the low half, hi in the high half).
  void add(__m256 r) {
    add(_mm256_castps256_ps128(r), _mm256_extractf128_ps(r, 1));
  }
#endif
  Bounds3 get() const {
    return box.bounds();
  }
};

/// Partition along a fixed axis A (the axis is a template parameter, so the centroid coordinate
/// is a plain member read in the loop).
template <int A>
size_t partition_axis(std::span<PrimRef> refs, const BinMapping& map, int pos, Bounds3& left,
                      Bounds3& right) {
  const auto coord = [](Vec3 v) { return A == 0 ? v.x : (A == 1 ? v.y : v.z); };
  const auto goes_left = [&](const PrimRef& r) {
    return map.bin(coord(r.lo) + coord(r.hi), A) < pos;  // lo + hi as in centroid2()
  };
  size_t i = 0, j = refs.size();
  CentroidBounds lc, rc;
  // Hoare-style: grow the left part from the front and the right part from the back.
  while (true) {
    while (i < j && goes_left(refs[i])) lc.add(refs[i++]);
    while (i < j && !goes_left(refs[j - 1])) rc.add(refs[--j]);
    if (i >= j) break;
#if defined(__AVX__)
    // refs[i] belongs right and refs[j - 1] left: swap, then both are placed; as two 32-byte
    // registers, whose centroids are then taken from the registers: std::swap stored the fields
    // one by one, and reading a reference back from those narrower stores stalled every swap (a
    // store-forwarding failure).
    float* a = &refs[i].lo.x;
    float* b = &refs[j - 1].lo.x;
    const __m256 x = _mm256_load_ps(a), y = _mm256_load_ps(b);
    _mm256_store_ps(a, y);
    _mm256_store_ps(b, x);
    lc.add(y), rc.add(x);
    ++i, --j;
#else
    std::swap(refs[i], refs[j - 1]);
    lc.add(refs[i++]);
    rc.add(refs[--j]);
#endif
  }
  left = lc.get(), right = rc.get();
  return i;
}

}  // namespace

size_t partition_refs(std::span<PrimRef> refs, const BinMapping& map, const SahSplit& split,
                      Bounds3& left_centroids, Bounds3& right_centroids) {
  switch (split.axis) {
    case 0:
      return partition_axis<0>(refs, map, split.pos, left_centroids, right_centroids);
    case 1:
      return partition_axis<1>(refs, map, split.pos, left_centroids, right_centroids);
    default:
      return partition_axis<2>(refs, map, split.pos, left_centroids, right_centroids);
  }
}

}  // namespace penumbra
