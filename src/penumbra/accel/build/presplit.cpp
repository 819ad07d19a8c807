#include "penumbra/accel/build/presplit.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "penumbra/accel/build/kd_clip.h"
#include "penumbra/core/dvec3.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"

namespace penumbra {

namespace {

/// Levels of the split grid: planes at multiples of the scene's extent / 2^level.
constexpr int kGridLevels = 24;
/// Pieces one triangle may become (its references), and the depth of its split recursion.
constexpr uint32_t kMaxPieces = 64;
constexpr int kMaxDepth = 24;
/// Triangles per parallel chunk.
constexpr size_t kChunk = 4096;

/// The coarsest plane of the scene grid strictly inside box `b` on `axis`: its level (1 is the
/// scene's midplane), or kGridLevels + 1 when there is none; its position in `pos`.
int grid_plane(const Bounds3& scene, const Bounds3& b, int axis, float& pos) {
  const double lo = scene.lo[axis], extent = double(scene.hi[axis]) - lo;
  if (!(extent > 0)) return kGridLevels + 1;
  for (int level = 1; level <= kGridLevels; ++level) {
    const double cell = extent / double(uint64_t{1} << level);
    const double m = std::ceil((double(b.lo[axis]) - lo) / cell);
    const auto p = static_cast<float>(lo + m * cell);
    if (p > b.lo[axis] && p < b.hi[axis]) {
      pos = p;
      return level;
    }
    // The next multiple may be the one inside (ceil landed on b.lo itself).
    const auto q = static_cast<float>(lo + (m + 1) * cell);
    if (q > b.lo[axis] && q < b.hi[axis]) {
      pos = q;
      return level;
    }
  }
  return kGridLevels + 1;
}

/// Writes at most `pieces` references of triangle `id`, whose part inside `box` is bounded by
/// `box`, to `out`; returns how many it wrote.
uint32_t split(const PrimitiveSet& prims, const Bounds3& scene, uint32_t id, const Bounds3& box,
               uint32_t pieces, int depth, PrimRef* out) {
  const auto emit = [&] {
    *out = make_prim_ref(box, id);
    return 1u;
  };
  if (pieces <= 1 || depth >= kMaxDepth) return emit();
  int axis = -1, best = kGridLevels + 1;
  float pos = 0;
  const Vec3 d = box.diagonal();
  for (int a = 0; a < 3; ++a) {
    float p;
    const int level = grid_plane(scene, box, a, p);
    if (level < best || (level == best && axis >= 0 && level <= kGridLevels && d[a] > d[axis]))
      best = level, axis = a, pos = p;
  }
  if (axis < 0) return emit();  // too thin for any plane of the grid
  Bounds3 below, above;
  split_prim_bounds(prims, id, box, axis, pos, true, below, above);
  if (below.empty() && above.empty()) return emit();  // rounding: keep the box as it was
  if (below.empty()) return split(prims, scene, id, above, pieces, depth + 1, out);
  if (above.empty()) return split(prims, scene, id, below, pieces, depth + 1, out);
  const double sb = below.surface_area(), sa = above.surface_area();
  const double share = sb + sa > 0 ? sb / (sb + sa) : 0.5;
  const auto nb =
      static_cast<uint32_t>(std::clamp(std::lround(double(pieces) * share), 1l, long(pieces) - 1));
  const uint32_t k = split(prims, scene, id, below, nb, depth + 1, out);
  return k + split(prims, scene, id, above, pieces - nb, depth + 1, out + k);
}

/// Twice the area of triangle `id`, in double.
double twice_area(const PrimitiveSet& prims, uint32_t id) {
  const Vec3* v = prims.triangle(id);
  return length(cross(DVec3(v[1]) - DVec3(v[0]), DVec3(v[2]) - DVec3(v[0])));
}

}  // namespace

void presplit_refs(const PrimitiveSet& prims, PrimRefs& in, double budget) {
  if (!(budget >= 0 && budget <= 4)) throw Error("presplit: the budget must lie in [0, 4]");
  if (!prims.all_triangles()) throw Error("presplit: only sets of static triangles are split");
  const size_t n = in.refs.size();
  const auto extra = static_cast<double>(std::floor(budget * double(n)));
  if (n == 0 || extra < 1) return;

  // Priorities, then each triangle's share of the budget (in id order: deterministic).
  std::vector<double> priority(n);
  parallel_for_range(
      n,
      [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
          const PrimRef& r = in.refs[i];
          const double waste = double(r.bounds().surface_area()) - twice_area(prims, r.id);
          int level = kGridLevels + 1;
          for (int a = 0; a < 3; ++a) {
            float pos;
            level = std::min(level, grid_plane(in.bounds, r.bounds(), a, pos));
          }
          priority[i] = waste > 0 && std::isfinite(waste) && level <= kGridLevels
                            ? std::cbrt(std::ldexp(waste, -level))
                            : 0.0;
        }
      },
      kChunk);
  double total = 0;
  for (double p : priority) total += p;
  if (!(total > 0) || !std::isfinite(total)) return;
  std::vector<size_t> first(n + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    const double k = std::floor(extra * priority[i] / total);
    first[i + 1] = first[i] + 1 + size_t(std::min(k, double(kMaxPieces - 1)));
  }
  if (first[n] == n) return;

  // Each triangle's pieces at its slots; slots it does not fill are marked and dropped.
  decltype(in.refs) out(first[n]);
  const Bounds3 scene = in.bounds;
  parallel_for_range(
      n,
      [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
          const auto pieces = static_cast<uint32_t>(first[i + 1] - first[i]);
          const PrimRef& r = in.refs[i];
          const uint32_t k = pieces == 1
                                 ? (out[first[i]] = r, 1u)
                                 : split(prims, scene, r.id, r.bounds(), pieces, 0, &out[first[i]]);
          for (uint32_t j = k; j < pieces; ++j) out[first[i] + j].id = kNoPrim;
        }
      },
      kChunk);
  out.erase(
      std::remove_if(out.begin(), out.end(), [](const PrimRef& r) { return r.id == kNoPrim; }),
      out.end());
  in.refs = std::move(out);
  Bounds3 centroids;
  for (const PrimRef& r : in.refs) centroids.extend(r.centroid2());
  in.centroid_bounds = centroids;
}

}  // namespace penumbra
