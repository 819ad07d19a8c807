#include "penumbra/accel/octree.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#if defined(__SSE4_1__)
#include <immintrin.h>
#endif

#include "penumbra/accel/build/prim_box_overlap.h"
#include "penumbra/accel/build/prim_ref.h"
#include "penumbra/accel/ray_mailbox.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/timer.h"

namespace penumbra {

namespace {

/// A node whose contents are known but not yet decided (leaf or split), one level at a time.
struct Pending {
  uint32_t node;  ///< its slot in the node array
  Vec3 lo;        ///< lower corner
  int depth;
  std::vector<uint32_t> prims;  ///< primitive ids overlapping it, ascending
};

/// Primitives distributed over a node's eight octants.
using Octants = std::array<std::vector<uint32_t>, 8>;

/// Lists in one parallel chunk of a large node (fixed, so the result is independent of threads).
constexpr size_t kSplitChunk = 8192;

/// Fraction of the spare room (side - extent) placed below the scene box on each axis: an
/// irrational fraction (sqrt(2) - 1) keeps the split planes off the round coordinates that CAD
/// models are centred on, where many primitives meet.
constexpr float kRootOffset = 0.41421356f;

#if defined(__SSE4_1__)
/// A node's lower corner as SSE lanes (x, y, z, 0): the mid-plane step below is a handful of
/// vector instructions, and the corner never goes through memory lane by lane (scalar stores
/// read back by a vector load would stall store forwarding).
using Corner = __m128;
inline Corner make_corner(Vec3 p) {
  return _mm_setr_ps(p.x, p.y, p.z, 0.0f);
}
/// Lower corner of octant `oct`: lo + h on the axes of its set bits (lo + 0 elsewhere, exact).
inline Corner child_corner(Corner lo, float h, unsigned oct) {
  const __m128i bits = _mm_and_si128(_mm_set1_epi32(int(oct)), _mm_setr_epi32(1, 2, 4, 8));
  const __m128 sel = _mm_castsi128_ps(_mm_cmpeq_epi32(bits, _mm_setr_epi32(1, 2, 4, 8)));
  return _mm_add_ps(lo, _mm_and_ps(_mm_set1_ps(h), sel));
}
#else
/// A node's lower corner (x, y, z).
struct Corner {
  float v[3];
};
inline Corner make_corner(Vec3 p) {
  return {{p.x, p.y, p.z}};
}
/// Lower corner of octant `oct`: lo + h on the axes of its set bits.
inline Corner child_corner(Corner lo, float h, unsigned oct) {
  for (int a = 0; a < 3; ++a)
    if (oct >> a & 1u) lo.v[a] += h;
  return lo;
}
#endif

/// A traversal stack entry: a node with its lower corner and ray interval. No default
/// initialisers: the stack array is not cleared for every ray.
struct Entry {
  Corner lo;
  uint32_t node;
  int depth;
  float t0, t1;
};

/// Per-ray values of the mid-plane step, as SSE lanes (x, y, z, -) where available.
struct OctreeRay {
#if defined(__SSE4_1__)
  __m128 org;  ///< origin, 0 in the last lane
  __m128 inv;  ///< 1 / direction, NaN in the last lane (that lane then never counts)
#else
  float org[3], inv[3];
#endif

  explicit OctreeRay(const PreparedRay& pr) {
#if defined(__SSE4_1__)
    org = _mm_setr_ps(pr.ray.o.x, pr.ray.o.y, pr.ray.o.z, 0.0f);
    inv = _mm_setr_ps(pr.inv_dir.x, pr.inv_dir.y, pr.inv_dir.z, std::nanf(""));
#else
    for (int a = 0; a < 3; ++a) org[a] = pr.ray.o[a], inv[a] = pr.inv_dir[a];
#endif
  }
};

/// One step of the parametric walk (Revelles et al. 2000) in a node with lower corner `lo` and
/// half edge `h`, entered at t0 and left at t1: returns the mirrored octant the ray is in at t0
/// (bit a set once past mid plane a, or on it) and sets `exit` to where it leaves that octant,
/// the nearest mid plane not yet crossed (or t1). The mid-plane parameters come from their
/// positions, so a zero direction component gives +-inf (NaN on the plane: counted as crossed)
/// instead of the +-inf averages of Revelles' formulation.
inline unsigned octant_step(const OctreeRay& r, Corner lo, float h, float t0, float t1,
                            float& exit) {
#if defined(__SSE4_1__)
  const __m128 tm = _mm_mul_ps(_mm_sub_ps(_mm_add_ps(lo, _mm_set1_ps(h)), r.org), r.inv);
  const __m128 ahead = _mm_cmpgt_ps(tm, _mm_set1_ps(t0));  // false for NaN
  __m128 e = _mm_blendv_ps(_mm_set1_ps(kInfinity), tm, ahead);
  e = _mm_min_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(2, 3, 0, 1)));
  e = _mm_min_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(1, 0, 3, 2)));
  exit = std::min(_mm_cvtss_f32(e), t1);
  return ~unsigned(_mm_movemask_ps(ahead)) & 7u;
#else
  unsigned c = 0;
  exit = t1;
  for (int a = 0; a < 3; ++a) {
    const float t = (lo.v[a] + h - r.org[a]) * r.inv[a];
    if (t > t0)
      exit = std::min(exit, t);
    else
      c |= 1u << a;
  }
  return c;
#endif
}

/// Triangle vertices are copied into leaf order only up to this many references per primitive
/// (beyond, the copy would cost more memory than its locality is worth).
constexpr double kCopyLimitRefsPerPrim = 8.0;

/// Stack depth: at most one deferred entry per level.
constexpr int kStackSize = kMaxOctreeDepth + 2;

/// Lower corner of octant `c` (bit 0: upper x half, bit 1: y, bit 2: z) of a node with lower
/// corner `lo` and half edge `h`; the traversal forms the same sums.
Vec3 octant_lo(Vec3 lo, float h, unsigned c) {
  return {c & 1u ? lo.x + h : lo.x, c & 2u ? lo.y + h : lo.y, c & 4u ? lo.z + h : lo.z};
}

/// What the level-by-level build shares: the primitives, their boxes and the parameters.
struct OctreeBuilder {
  const PrimitiveSet& prims;
  const std::vector<Bounds3>& boxes;  ///< by primitive id
  const float* half;                  ///< half edge per depth
  Vec3 margin;                        ///< slack of the octant candidates, above the overlap pad
  size_t leaf_size;
  int max_depth;
  double trav_cost;

  /// Distributes ids[b, e) of a node (lower corner lo, depth) over its octants, keeping order.
  void distribute(const std::vector<uint32_t>& ids, size_t b, size_t e, Vec3 lo, int depth,
                  Octants& out) const {
    const float h = half[depth];
    Bounds3 child[8];
    for (unsigned c = 0; c < 8; ++c) {
      child[c].lo = octant_lo(lo, h, c);
      child[c].hi = child[c].lo + Vec3(h);
    }
    const Vec3 mid = child[7].lo;
    for (size_t i = b; i < e; ++i) {
      const uint32_t id = ids[i];
      const Bounds3& pb = boxes[id];
      unsigned lower = 0, upper = 0;  // per axis: may touch the lower / upper half
      for (int a = 0; a < 3; ++a) {
        lower |= unsigned(pb.lo[a] <= mid[a] + margin[a]) << a;
        upper |= unsigned(pb.hi[a] >= mid[a] - margin[a]) << a;
      }
      // Within one octant by its box (the common case deep down): the primitive overlaps the
      // node, so it overlaps that octant; no test.
      if ((lower ^ upper) == 7u) {
        out[upper].push_back(id);
        continue;
      }
      for (unsigned c = 0; c < 8; ++c)
        if ((c & upper) == c && (~c & 7u & lower) == (~c & 7u) &&
            prim_box_overlap(prims, id, pb, child[c]))
          out[c].push_back(id);
    }
  }

  /// Fills the octants of `p` and returns true, or returns false when `p` stays a leaf.
  bool split(const Pending& p, Octants& o) const {
    const size_t n = p.prims.size();
    if (n <= leaf_size || p.depth >= max_depth) return false;
    if (n <= kSplitChunk) {
      distribute(p.prims, 0, n, p.lo, p.depth, o);
    } else {  // a large node: chunks in parallel, joined in chunk order
      const size_t chunks = (n + kSplitChunk - 1) / kSplitChunk;
      std::vector<Octants> part(chunks);
      parallel_for(chunks, [&](size_t c) {
        distribute(p.prims, c * kSplitChunk, std::min(n, (c + 1) * kSplitChunk), p.lo, p.depth,
                   part[c]);
      });
      for (const Octants& q : part)
        for (int c = 0; c < 8; ++c) o[c].insert(o[c].end(), q[c].begin(), q[c].end());
    }
    // The stop rules. No separation: two or more octants receive every primitive (primitives
    // through one point, along one line, or overlapping in one plane), or one octant receives
    // them all while at least half of them also reach its siblings (the fan of triangles
    // around a vertex of high valence: splitting again would zoom in on the vertex level after
    // level, copying the fan each time). No expected gain: an octant is crossed by a quarter of
    // the rays that cross the node (surface area ratio), so the split pays only when
    // trav + sum(n_c) / 4 < n (MacDonald & Booth 1990, "Heuristics for ray tracing using space
    // subdivision").
    int full = 0;
    size_t sum = 0;
    for (const auto& c : o) full += c.size() == n, sum += c.size();
    const bool fan = full == 1 && 2 * (sum - n) >= n;
    if (full >= 2 || fan || trav_cost + 0.25 * double(sum) >= double(n)) {
      o = {};
      return false;
    }
    return true;
  }
};

}  // namespace

Octree::Octree(const ParamList& params) {
  leaf_size_ = int(params.get_int("leaf", leaf_size_, 1, 1024));
  max_depth_ = int(params.get_int("depth", max_depth_, 1, kMaxOctreeDepth));
  trav_cost_ = params.get_real("trav", trav_cost_, 0.0, 1000.0);
  copy_ = params.get_int("copy", 1, 0, 1);
  mailbox_ = read_mailbox_size(params, mailbox_, "octree");
  params.check_all_used();
  name_ = params.to_string();
}

Vec3 Octree::child_lo(Vec3 lo, int depth, unsigned c) const {
  return octant_lo(lo, half_[depth], c);
}

void Octree::build(const PrimitiveSet& prims) {
  const Timer timer;
  prims_ = &prims;
  nodes_.clear(), ids_.clear(), tris_.clear();
  stats_ = {};
  PrimRefs refs = make_prim_refs(prims);
  max_extent_ = max_prim_extent(refs);
  if (refs.refs.empty()) {
    stats_.build_ms = timer.elapsed_ms();
    return;
  }
  // 1. The root cube: the scene box made cubic, 1% larger, offset irregularly (kRootOffset).
  const Vec3 d = refs.bounds.diagonal();
  float side = max_component(d) * 1.01f;
  if (!(side > 0.0f)) side = 1.0f;
  for (int a = 0; a < 3; ++a) root_lo_[a] = refs.bounds.lo[a] - (side - d[a]) * kRootOffset;
  half_[0] = side * 0.5f;
  for (int k = 1; k <= kMaxOctreeDepth; ++k) half_[k] = half_[k - 1] * 0.5f;
  std::vector<Bounds3> boxes(prims.size());
  Pending root{0, root_lo_, 0, {}};
  root.prims.reserve(refs.refs.size());
  for (const PrimRef& r : refs.refs) boxes[r.id] = r.bounds(), root.prims.push_back(r.id);
  const size_t root_count = root.prims.size();
  refs = {};
  // Octant candidates come from the boxes against the mid planes, with more margin than the
  // overlap pad; the exact test then decides.
  Vec3 margin;
  for (int a = 0; a < 3; ++a)
    margin[a] =
        4.0f * float(kOverlapPad) * (std::fabs(root_lo_[a]) + std::fabs(root_lo_[a] + side));
  const OctreeBuilder builder{prims,      boxes,     half_, margin, size_t(leaf_size_),
                              max_depth_, trav_cost_};

  // 2. Breadth first, one level at a time: decide every node of the level in parallel, then
  // lay out their children as eight consecutive nodes of the next level (deterministic order).
  // A reference budget, checked per level, keeps memory linear whatever the geometry.
  const double budget = kOctreeMaxRefsPerPrim * double(root_count);
  nodes_.push_back({});
  std::vector<Pending> level;
  level.push_back(std::move(root));
  size_t max_depth = 0, leaves = 0, empty_leaves = 0, largest_leaf = 0;
  while (!level.empty()) {
    std::vector<Octants> kids(level.size());
    std::vector<char> split(level.size(), 0);
    parallel_for(level.size(), [&](size_t i) { split[i] = builder.split(level[i], kids[i]); });
    double refs_next = double(ids_.size());  // references once this level is laid out
    for (size_t i = 0; i < level.size(); ++i) {
      if (!split[i]) refs_next += double(level[i].prims.size());
      for (const auto& c : kids[i]) refs_next += double(c.size());
    }
    const bool over_budget = refs_next > budget;
    std::vector<Pending> next;
    for (size_t i = 0; i < level.size(); ++i) {
      Pending& p = level[i];
      if (!split[i] || over_budget) {  // a leaf
        if (p.prims.size() >= size_t(OctreeNode::kInner))
          throw Error("octree: a leaf with more than 2^31 primitives");
        nodes_[p.node] = {uint32_t(ids_.size()), uint32_t(p.prims.size())};
        ids_.insert(ids_.end(), p.prims.begin(), p.prims.end());
        max_depth = std::max(max_depth, size_t(p.depth));
        ++leaves;
        empty_leaves += p.prims.empty();
        largest_leaf = std::max(largest_leaf, p.prims.size());
        continue;
      }
      if (nodes_.size() + 8 >= size_t(kNoPrim)) throw Error("octree: more than 2^32 nodes");
      const auto base = uint32_t(nodes_.size());
      nodes_.resize(nodes_.size() + 8);
      unsigned mask = 0;
      for (unsigned c = 0; c < 8; ++c) {
        mask |= unsigned(!kids[i][c].empty()) << c;
        next.push_back({base + c, child_lo(p.lo, p.depth, c), p.depth + 1, std::move(kids[i][c])});
      }
      nodes_[p.node] = {base, OctreeNode::kInner | mask};
    }
    level = std::move(next);
  }
  nodes_.shrink_to_fit();
  ids_.shrink_to_fit();
  tris_.clear();
  if (prims.all_triangles() && copy_ &&
      double(ids_.size()) <= kCopyLimitRefsPerPrim * double(root_count)) {
    tris_.resize(3 * ids_.size());
    parallel_for_range(
        ids_.size(),
        [&](size_t b, size_t e) {
          for (size_t i = b; i < e; ++i) {
            const Vec3* v = prims.triangle(ids_[i]);
            tris_[3 * i] = v[0], tris_[3 * i + 1] = v[1], tris_[3 * i + 2] = v[2];
          }
        },
        4096);
  }

  stats_.nodes = nodes_.size();
  stats_.leaves = leaves - empty_leaves;
  stats_.max_depth = max_depth;
  stats_.prim_refs = ids_.size();
  stats_.bytes = nodes_.capacity() * sizeof(OctreeNode) + ids_.capacity() * sizeof(uint32_t) +
                 tris_.capacity() * sizeof(Vec3);
  stats_.extra = {{"refs/prim", double(ids_.size()) / double(root_count)},
                  {"empty leaves", double(empty_leaves)},
                  {"largest leaf", double(largest_leaf)}};
  stats_.build_ms = timer.elapsed_ms();
}

template <bool kAnyHit, bool kTriangles, int kMailbox, class Cost>
bool Octree::traverse(const PreparedRay& pr, Hit& hit, Cost cost) const {
  const Ray& ray = pr.ray;
  // 1. Clip the ray to the root cube (slab test; a NaN term, from a zero direction component
  // with the origin on a face plane, is ignored: the ray lies in the closed slab).
  float t0 = ray.tmin, t1 = hit.t;
  const float side = half_[0] * 2.0f;
  for (int a = 0; a < 3; ++a) {
    const float l = (root_lo_[a] - ray.o[a]) * pr.inv_dir[a];
    const float h = (root_lo_[a] + side - ray.o[a]) * pr.inv_dir[a];
    const float tn = pr.neg[a] ? h : l, tf = pr.neg[a] ? l : h;
    t0 = tn > t0 ? tn : t0;
    t1 = tf < t1 ? tf : t1;
  }
  if (!(t0 <= t1)) return false;
  // Octants are visited in the ray's direction: mirrored index bit a = 1 for the half the ray
  // reaches second on axis a; the real octant is the mirrored one XOR the direction signs.
  const unsigned neg = unsigned(pr.neg[0]) | unsigned(pr.neg[1]) << 1 | unsigned(pr.neg[2]) << 2;
  Entry stack[kStackSize];
  int sp = 0;
  const OctreeRay r(pr);
  // Nodes are passed over beyond cull_bound(hit.t, size_slack), not hit.t (hit.h): a
  // triangle's t may lie below the entry of a node that holds it by a share of its size.
  const float inv[3] = {pr.inv_dir.x, pr.inv_dir.y, pr.inv_dir.z};
  const float size_slack = cull_slack(max_extent_, inv);
  float cull = query_cull<kAnyHit>(hit.t, size_slack);  // renewed at each hit
  Entry cur{make_corner(root_lo_), 0, 0, t0, t1};
  RayMailbox<kMailbox> mailbox;
  bool found = false;
  while (true) {
    const OctreeNode node = nodes_[cur.node];
    cost.node();
    if (node.inner()) {
      // 2. Inner node: the octant the ray is in at t0 and where it leaves it.
      const float h = half_[cur.depth];
      float exit;
      const unsigned oct = octant_step(r, cur.lo, h, cur.t0, cur.t1, exit) ^ neg;
      // The rest of this node is deferred as the node itself from `exit` on: popped, it yields
      // its next octant. One entry per level instead of up to three siblings, and none of the
      // siblings' work for rays that stop in the first octant.
      if (node.child_mask() >> oct & 1u) {
        if (exit < cur.t1) stack[sp++] = {cur.lo, cur.node, cur.depth, exit, cur.t1};
        cur = {child_corner(cur.lo, h, oct), node.index + oct, cur.depth + 1, cur.t0, exit};
        continue;
      }
      // An empty octant: on to the next one.
      if (exit < cur.t1 && exit <= cull) {
        cur.t0 = exit;
        continue;
      }
    } else {
      // 3. Leaf: test its primitives. A hit before the leaf's exit, by its cull bound, is the
      // closest (all later nodes start beyond it; one near the exit may tie with a lower id
      // there, or round lower: hit.h); a hit beyond is kept (hit.t shrinks) and the walk goes on.
      if (test_mailboxed<kAnyHit, kTriangles>(*prims_, ids_.data(), tris_.data(), node.index,
                                              node.index + node.count(), pr, hit, mailbox,
                                              cost)) {
        if constexpr (kAnyHit) return true;
        found = true;
        cull = cull_bound(hit.t, size_slack);
      }
      if (cull < cur.t1) return found;
    }
    // 4. The next node front to back; none left, or it starts beyond the closest hit: done.
    if (sp == 0 || stack[sp - 1].t0 > cull) return found;
    cur = stack[--sp];
  }
}

template <bool kAnyHit, class Cost>
bool Octree::dispatch(const PreparedRay& pr, Hit& hit, Cost cost) const {
  return dispatch_mailbox(mailbox_, !tris_.empty(), [&](auto triangles, auto size) {
    return traverse<kAnyHit, decltype(triangles)::value, decltype(size)::value>(pr, hit, cost);
  });
}

bool Octree::intersect(const Ray& ray, Hit& hit) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  return dispatch<false>(PreparedRay(ray), hit);
}

bool Octree::intersect_cost(const Ray& ray, Hit& hit, TraversalCost& cost) const {
  hit = Hit{};
  hit.t = ray.tmax;
  if (!traceable(ray) || nodes_.empty()) return false;
  return dispatch<false>(PreparedRay(ray), hit, CostCounter{&cost});
}

bool Octree::occluded_cost(const Ray& ray, TraversalCost& cost) const {
  if (!traceable(ray) || nodes_.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  return dispatch<true>(PreparedRay(ray), hit, CostCounter{&cost});
}

bool Octree::occluded(const Ray& ray) const {
  if (!traceable(ray)) return false;
  if (nodes_.empty()) return false;
  Hit hit;
  hit.t = ray.tmax;
  return dispatch<true>(PreparedRay(ray), hit);
}

}  // namespace penumbra
