#include "penumbra/accel/build/binned_sah.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "penumbra/core/parallel.h"

namespace penumbra {

namespace {

/// References per parallel binning task: fixed, so the chunking never depends on the thread count.
constexpr size_t kBinChunk = 32768;

/// Bin boxes and counts of the three axes.
struct BinSet {
  Bounds3 box[3][kMaxBins];
  uint32_t count[3][kMaxBins] = {};

  /// Adds `refs` to the bins of `map`.
  void add(std::span<const PrimRef> refs, const BinMapping& map) {
    for (const PrimRef& r : refs) {
      const Vec3 c = r.centroid2();
      const Bounds3 b = r.bounds();
      for (int a = 0; a < 3; ++a) {
        const int i = map.bin(c[a], a);
        box[a][i].extend(b);
        ++count[a][i];
      }
    }
  }
  /// Adds the bins of `o` (exact: min, max and integer sums).
  void merge(const BinSet& o, int bins) {
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < bins; ++i) box[a][i].extend(o.box[a][i]), count[a][i] += o.count[a][i];
  }
};

/// Bins `refs`, in parallel chunks for large sets.
void bin_refs(std::span<const PrimRef> refs, const BinMapping& map, bool parallel, BinSet& out) {
  const size_t chunks = (refs.size() + kBinChunk - 1) / kBinChunk;
  if (!parallel || chunks < 2) {
    out.add(refs, map);
    return;
  }
  std::vector<BinSet> partial(chunks);
  parallel_for(chunks, [&](size_t c) {
    const size_t begin = c * kBinChunk;
    partial[c].add(refs.subspan(begin, std::min(kBinChunk, refs.size() - begin)), map);
  });
  for (const BinSet& p : partial) out.merge(p, map.bins);  // in chunk order
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

SahSplit find_binned_split(std::span<const PrimRef> refs, const BinMapping& map, bool parallel) {
  BinSet set;
  bin_refs(refs, map, parallel, set);
  const int nb = map.bins;
  SahSplit best;
  for (int a = 0; a < 3; ++a) {
    if (map.scale[a] == 0.0f) continue;
    // Sweep from the right: area and count of bins [i, nb).
    float right_area[kMaxBins];
    uint32_t right_count[kMaxBins];
    Bounds3 acc;
    uint32_t n = 0;
    for (int i = nb - 1; i > 0; --i) {
      acc.extend(set.box[a][i]);
      n += set.count[a][i];
      right_area[i] = acc.surface_area(), right_count[i] = n;
    }
    // Sweep from the left, evaluating the cost at each boundary; ties keep the first split.
    acc = Bounds3{};
    n = 0;
    for (int i = 1; i < nb; ++i) {
      acc.extend(set.box[a][i - 1]);
      n += set.count[a][i - 1];
      if (n == 0 || right_count[i] == 0) continue;
      const float cost = acc.surface_area() * float(n) + right_area[i] * float(right_count[i]);
      if (best.axis < 0 || cost < best.cost) best.axis = a, best.pos = i, best.cost = cost;
    }
  }
  if (best.axis < 0) return best;
  for (int i = 0; i < nb; ++i) {
    const int a = best.axis;
    if (i < best.pos) best.left.extend(set.box[a][i]), best.left_count += set.count[a][i];
    else best.right.extend(set.box[a][i]), best.right_count += set.count[a][i];
  }
  return best;
}

size_t partition_refs(std::span<PrimRef> refs, const BinMapping& map, const SahSplit& split,
                      Bounds3& left_centroids, Bounds3& right_centroids) {
  const int a = split.axis;
  size_t i = 0, j = refs.size();
  Bounds3 lc, rc;
  // Hoare-style: grow the left part from the front and the right part from the back.
  while (true) {
    while (i < j) {
      const Vec3 c = refs[i].centroid2();
      if (map.bin(c[a], a) >= split.pos) break;
      lc.extend(c);
      ++i;
    }
    while (i < j) {
      const Vec3 c = refs[j - 1].centroid2();
      if (map.bin(c[a], a) < split.pos) break;
      rc.extend(c);
      --j;
    }
    if (i >= j) break;
    // refs[i] belongs right and refs[j - 1] left: swap, then both are placed.
    std::swap(refs[i], refs[j - 1]);
    lc.extend(refs[i].centroid2());
    rc.extend(refs[j - 1].centroid2());
    ++i, --j;
  }
  left_centroids = lc, right_centroids = rc;
  return i;
}

}  // namespace penumbra
