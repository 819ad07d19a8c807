#include "penumbra/accel/uniform_grid.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/accel/build/prim_box_overlap.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/ray_mailbox.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"

namespace penumbra {

namespace {

/// Parses "N" or "AxBxC" into three axis resolutions in [1, kMaxAxisCells].
std::array<int, 3> parse_res(const std::string& text) {
  std::vector<int> parts;
  size_t begin = 0;
  bool ok = true;
  while (ok) {
    const size_t end = std::min(text.find('x', begin), text.size());
    const std::string part = text.substr(begin, end - begin);
    ok = !part.empty() && part.size() <= 5 &&
         std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (ok) parts.push_back(std::stoi(part));
    ok = ok && parts.back() >= 1 && parts.back() <= kMaxAxisCells;
    if (end == text.size()) break;
    begin = end + 1;
  }
  if (!ok || (parts.size() != 1 && parts.size() != 3))
    throw Error(
        fmt::format("grid: res={} is not N or AxBxC with each in [1, {}]", text, kMaxAxisCells));
  if (parts.size() == 1) return {parts[0], parts[0], parts[0]};
  return {parts[0], parts[1], parts[2]};
}

size_t cell_count(const std::array<int, 3>& r) {
  return size_t(r[0]) * size_t(r[1]) * size_t(r[2]);
}

}  // namespace

std::array<int, 3> grid_resolution(Vec3 d, size_t n, double lambda) {
  const double cells = std::max(1.0, lambda * double(n));
  std::array<int, 3> res{1, 1, 1};
  bool thin[3] = {false, false, false};
  // Near-cubic cells: n_i = d_i * s with s^k * prod(d_i) = cells over the k axes not yet found
  // too thin for one cell; those get one cell and the others share the budget.
  for (int round = 0; round < 3; ++round) {
    double prod = 1.0;
    int k = 0;
    for (int a = 0; a < 3; ++a)
      if (!thin[a]) prod *= double(d[a]), ++k;
    if (k == 0) break;
    const double s = std::pow(cells / prod, 1.0 / k);
    bool changed = false;
    for (int a = 0; a < 3; ++a)
      if (!thin[a] && !(double(d[a]) * s >= 1.0)) thin[a] = changed = true;
    if (changed) continue;
    for (int a = 0; a < 3; ++a)
      if (!thin[a])
        res[a] = int(std::clamp(std::round(double(d[a]) * s), 1.0, double(kMaxAxisCells)));
    break;
  }
  return cap_resolution(res, n);
}

std::array<int, 3> cap_resolution(std::array<int, 3> res, size_t n) {
  const double cap =
      double(std::min(kMaxCells, std::max(kMinCellCap, size_t(kMaxCellsPerPrim * double(n)))));
  for (int& r : res) r = std::clamp(r, 1, kMaxAxisCells);
  while (double(cell_count(res)) > cap) {
    const double f = std::min(0.99, std::cbrt(cap / double(cell_count(res))));
    for (int& r : res) r = std::max(1, int(std::floor(r * f)));
  }
  return res;
}

UniformGrid::UniformGrid(const ParamList& params) {
  lambda_ = params.get_real("lambda", lambda_, 0.01, kMaxCellsPerPrim);
  if (params.has("res")) fixed_res_ = parse_res(params.get_string("res", ""));
  mailbox_ = read_mailbox_size(params, mailbox_, "grid");
  copy_ = params.get_int("copy", 1, 0, 1);
  if (params.has("res") && params.has("lambda"))
    throw Error("grid: give either lambda or res, not both");
  params.check_all_used();
  name_ = params.to_string();
}

Bounds3 UniformGrid::cell_bounds(int x, int y, int z) const {
  const int c[3] = {x, y, z};
  Bounds3 b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = box_.lo[a] + float(c[a]) * cell_size_[a];
    b.hi[a] = c[a] + 1 == res_[a] ? box_.hi[a] : box_.lo[a] + float(c[a] + 1) * cell_size_[a];
  }
  return b;
}

std::span<const uint32_t> UniformGrid::cell(int x, int y, int z) const {
  const size_t c = size_t(x) + size_t(res_[0]) * (size_t(y) + size_t(res_[1]) * size_t(z));
  return {ids_.data() + offsets_[c], ids_.data() + offsets_[c + 1]};
}

double UniformGrid::choose_resolution(std::span<const PrimRef> refs, const Bounds3& bounds) {
  // The grid box: the scene box enlarged a little, every axis of positive extent.
  box_ = bounds;
  const float max_extent = max_component(box_.diagonal());
  for (int a = 0; a < 3; ++a) {
    const float pad =
        float(kOverlapPad) * (std::fabs(box_.lo[a]) + std::fabs(box_.hi[a]) + max_extent);
    box_.lo[a] -= pad, box_.hi[a] += pad;
    if (!(box_.hi[a] > box_.lo[a])) box_.lo[a] -= 1.0f, box_.hi[a] += 1.0f;
  }
  for (int a = 0; a < 3; ++a)
    cand_pad_[a] = 2.0f * float(kOverlapPad) * (std::fabs(box_.lo[a]) + std::fabs(box_.hi[a]));
  // The resolution, then the reference budget: while the primitives' boxes cover more than
  // kMaxCandidatesPerPrim cells each on average (large primitives crossing much of the scene,
  // where references would grow as N * cells), the resolution is lowered, so that build time
  // and memory stay linear in N.
  const Vec3 extent = box_.diagonal();
  const size_t n = refs.size();
  res_ = fixed_res_[0] ? cap_resolution(fixed_res_, n) : grid_resolution(extent, n, lambda_);
  while (true) {
    for (int a = 0; a < 3; ++a) {
      cell_size_[a] = extent[a] / float(res_[a]);
      inv_cell_size_[a] = float(res_[a]) / extent[a];
    }
    constexpr size_t kChunk = 16384;  // fixed: the sum does not depend on the thread count
    std::vector<double> part((n + kChunk - 1) / kChunk, 0.0);
    parallel_for(part.size(), [&](size_t c) {
      int c0[3], c1[3];
      for (size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
        candidates(refs[i], c0, c1);
        part[c] += double(c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1);
      }
    });
    double total = 0;
    for (double v : part) total += v;
    const double budget = kMaxCandidatesPerPrim * double(n);
    if (total <= budget || cell_count(res_) == 1) return total;
    const double f = std::clamp(std::cbrt(budget / total), 0.5, 0.9);
    for (int& r : res_) r = std::max(1, int(double(r) * f));
  }
}

void UniformGrid::candidates(const PrimRef& r, int c0[3], int c1[3]) const {
  for (int a = 0; a < 3; ++a) {
    const float l = (r.lo[a] - cand_pad_[a] - box_.lo[a]) * inv_cell_size_[a];
    const float h = (r.hi[a] + cand_pad_[a] - box_.lo[a]) * inv_cell_size_[a];
    c0[a] = int(std::clamp(l, 0.0f, float(res_[a] - 1)));
    c1[a] = int(std::clamp(h, 0.0f, float(res_[a] - 1)));
  }
}

template <class F>
void UniformGrid::for_each_cell(const PrimitiveSet& prims, const PrimRef& r, F&& f) const {
  int c0[3], c1[3];
  candidates(r, c0, c1);
  // A box spanning cells along one axis only: the primitive crosses all of them (see
  // prim_box_overlap); otherwise the exact test decides for each candidate.
  const bool line = (c0[0] == c1[0]) + (c0[1] == c1[1]) + (c0[2] == c1[2]) >= 2;
  for (int z = c0[2]; z <= c1[2]; ++z)
    for (int y = c0[1]; y <= c1[1]; ++y)
      for (int x = c0[0]; x <= c1[0]; ++x)
        if (line || prim_box_overlap(prims, r.id, r.bounds(), cell_bounds(x, y, z)))
          f(size_t(x) + size_t(res_[0]) * (size_t(y) + size_t(res_[1]) * size_t(z)));
}

void UniformGrid::fill_cells(const PrimitiveSet& prims, std::span<const PrimRef> refs) {
  const size_t cells = cell_count(res_), n = refs.size();
  constexpr size_t kGrain = 512;
  // Count pass: references per cell (atomic increments commute: the counts are deterministic).
  std::vector<uint32_t> count(cells, 0);
  parallel_for_range(
      n,
      [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
          for_each_cell(prims, refs[i], [&](size_t c) {
            std::atomic_ref<uint32_t>(count[c]).fetch_add(1, std::memory_order_relaxed);
          });
      },
      kGrain);
  // Exclusive prefix sum into the CSR offsets.
  offsets_.resize(cells + 1);
  size_t total = 0;
  for (size_t c = 0; c < cells; ++c) {
    offsets_[c] = uint32_t(total);
    total += count[c];
    if (total >= size_t(kNoPrim)) throw Error("grid: more than 2^32 - 1 primitive references");
  }
  offsets_[cells] = uint32_t(total);
  // Fill pass: the same cells again, each reference at its cell's cursor.
  ids_.resize(total);
  std::copy(offsets_.begin(), offsets_.end() - 1, count.begin());
  parallel_for_range(
      n,
      [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
          for_each_cell(prims, refs[i], [&](size_t c) {
            ids_[std::atomic_ref<uint32_t>(count[c]).fetch_add(1, std::memory_order_relaxed)] =
                refs[i].id;
          });
      },
      kGrain);
  // Ascending ids in every cell: the result does not depend on the thread schedule.
  parallel_for_range(
      cells,
      [&](size_t b, size_t e) {
        for (size_t c = b; c < e; ++c)
          std::sort(ids_.begin() + offsets_[c], ids_.begin() + offsets_[c + 1]);
      },
      4096);
  // Occupancy bits, and the triangles in cell order (one stream per cell instead of a gather
  // through the primitive set), unless that would multiply the memory too much.
  occupied_.assign((cells + 63) / 64, 0);
  for (size_t c = 0; c < cells; ++c)
    occupied_[c >> 6] |= uint64_t(offsets_[c] != offsets_[c + 1]) << (c & 63);
  if (prims.all_triangles() && copy_ && double(total) <= kMaxCopiedRefsPerPrim * double(n)) {
    tris_.resize(3 * total);
    parallel_for_range(
        total,
        [&](size_t b, size_t e) {
          for (size_t i = b; i < e; ++i) {
            const Vec3* v = prims.triangle(ids_[i]);
            tris_[3 * i] = v[0], tris_[3 * i + 1] = v[1], tris_[3 * i + 2] = v[2];
          }
        },
        4096);
  }
}

void UniformGrid::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  offsets_.clear(), ids_.clear(), occupied_.clear(), tris_.clear();
  res_ = {0, 0, 0};
  stats_ = {};
  const PrimRefs refs = make_prim_refs(prims);
  max_extent_ = max_prim_extent(refs);
  if (refs.refs.empty()) {
    stats_.build_ms = timer.elapsed_ms();
    return;
  }
  const double candidates = choose_resolution(refs.refs, refs.bounds);
  fill_cells(prims, refs.refs);
  const size_t cells = cell_count(res_), n = refs.refs.size();
  size_t empty = 0;
  for (size_t c = 0; c < cells; ++c) empty += offsets_[c] == offsets_[c + 1];
  stats_.nodes = cells;
  stats_.leaves = cells - empty;
  stats_.max_depth = 0;
  stats_.prim_refs = ids_.size();
  stats_.bytes = offsets_.capacity() * sizeof(uint32_t) + ids_.capacity() * sizeof(uint32_t) +
                 occupied_.capacity() * sizeof(uint64_t) + tris_.capacity() * sizeof(Vec3);
  stats_.extra = {{"nx", res_[0]},
                  {"ny", res_[1]},
                  {"nz", res_[2]},
                  {"refs/prim", double(ids_.size()) / double(n)},
                  {"candidates/prim", candidates / double(n)},
                  {"empty cells", double(empty) / double(cells)}};
  stats_.build_ms = timer.elapsed_ms();
}

template <bool kAnyHit, bool kTriangles, int kMailbox, class Cost>
bool UniformGrid::traverse(const PreparedRay& pr, Hit& hit, Cost cost) const {
  const Ray& ray = pr.ray;
  // 1. Clip the ray to the grid box (slab test). With a zero direction component and the origin
  // on a face plane, (plane - o) * inv is NaN; comparisons with NaN are false, so that term is
  // ignored: the ray lies in the closed slab.
  float t0 = ray.tmin, t1 = hit.t;
  for (int a = 0; a < 3; ++a) {
    const float l = (box_.lo[a] - ray.o[a]) * pr.inv_dir[a];
    const float h = (box_.hi[a] - ray.o[a]) * pr.inv_dir[a];
    const float tn = pr.neg[a] ? h : l, tf = pr.neg[a] ? l : h;
    t0 = tn > t0 ? tn : t0;
    t1 = tf < t1 ? tf : t1;
  }
  if (!(t0 <= t1)) return false;
  // 2. The entry cell and, per axis, the parameter of the next cell boundary. Boundary k lies at
  // t = base + k * delta, recomputed from k at every step rather than accumulated (Amanatides &
  // Woo add tDelta, whose rounding drifts by one ulp per step over thousands of cells).
  int cell[3], step[3], last[3], off[3];
  float next[3], base[3], delta[3];
  const int stride[3] = {1, res_[0], res_[0] * res_[1]};
  int idx = 0;
  for (int a = 0; a < 3; ++a) {
    const float p = ray.o[a] + ray.d[a] * t0;
    const float c = std::clamp((p - box_.lo[a]) * inv_cell_size_[a], 0.0f, float(res_[a] - 1));
    cell[a] = int(c);
    idx += cell[a] * stride[a];
    base[a] = (box_.lo[a] - ray.o[a]) * pr.inv_dir[a];
    delta[a] = cell_size_[a] * pr.inv_dir[a];
    if (ray.d[a] > 0.0f) {
      step[a] = 1, last[a] = res_[a], off[a] = 1;
    } else if (ray.d[a] < 0.0f) {
      step[a] = -1, last[a] = -1, off[a] = 0;
    } else {  // parallel to this axis: never leaves the slab of cells
      step[a] = 0, last[a] = -2, off[a] = 0;
      next[a] = kInfinity;
      continue;
    }
    next[a] = base[a] + float(cell[a] + off[a]) * delta[a];
  }
  // 3. Walk the cells in order. A hit found in a cell may lie beyond it (the primitive reaches
  // into later cells): it is kept as the closest so far (hit.t shrinks) and the walk goes on
  // until the hit lies within the current cell, cull_bound(t) < the cell's exit (hit.h: near the
  // exit, the next cell may hold a primitive at the same t with a lower id, tie_bound, or one
  // whose t rounds lower). Keeping it, rather than rejecting it and meeting the primitive again
  // later, is what makes the mailbox safe.
  const float inv[3] = {pr.inv_dir.x, pr.inv_dir.y, pr.inv_dir.z};
  const float size_slack = cull_slack(max_extent_, inv);
  float cull = query_cull<kAnyHit>(hit.t, size_slack);  // renewed at each hit
  RayMailbox<kMailbox> mailbox;
  bool found = false;
  while (true) {
    cost.node();
    // The occupancy bits (one cache line per 512 cells) spare empty cells the offsets' miss.
    if ((occupied_[idx >> 6] >> (idx & 63) & 1u) &&
        test_mailboxed<kAnyHit, kTriangles>(*prims_, ids_.data(), tris_.data(), offsets_[idx],
                                            offsets_[idx + 1], pr, hit, mailbox, cost)) {
      if constexpr (kAnyHit) return true;
      found = true;
      cull = cull_bound(hit.t, size_slack);
    }
    const int a = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    const float t_exit = next[a];
    // The closest hit lies in this cell, or the segment ends (or leaves the grid) in it.
    if (cull < t_exit || t1 <= t_exit) return found;
    cell[a] += step[a];
    if (cell[a] == last[a]) return found;
    idx += step[a] * stride[a];
    next[a] = base[a] + float(cell[a] + off[a]) * delta[a];
  }
}

template <bool kAnyHit, class Cost>
bool UniformGrid::dispatch(const PreparedRay& pr, Hit& hit, Cost cost) const {
  return dispatch_mailbox(mailbox_, !tris_.empty(), [&](auto triangles, auto size) {
    return traverse<kAnyHit, decltype(triangles)::value, decltype(size)::value>(pr, hit, cost);
  });
}

bool UniformGrid::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  if (ids_.empty()) return false;
  return dispatch<false>(PreparedRay(ray), hit);
}

bool UniformGrid::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || ids_.empty()) return false;
  return dispatch<false>(PreparedRay(ray), hit, CostCounter{&cost});
}

bool UniformGrid::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray) || ids_.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  return dispatch<true>(PreparedRay(ray), hit, CostCounter{&cost});
}

bool UniformGrid::occluded(const Ray& ray) const {
  if (!traceable(ray)) return false;
  if (ids_.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  return dispatch<true>(PreparedRay(ray), hit);
}

}  // namespace penumbra
