#include "penumbra/accel/build/bsp_builder.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"

namespace penumbra {

BspBuildParams read_bsp_build_params(const ParamList& params) {
  BspBuildParams p;
  const std::string order = params.get_string("order", "random");
  if (order == "random") {
    p.order = BspOrder::kRandom;
  } else if (order == "first") {
    p.order = BspOrder::kFirst;
  } else if (order == "fewest-cuts") {
    p.order = BspOrder::kFewestCuts;
  } else {
    throw Error(fmt::format("{}: parameter 'order' must be random, first or fewest-cuts, got '{}'",
                            params.name(), order));
  }
  // Parameters that the chosen order would ignore are mistakes: reject them.
  if (params.has("seed") && p.order == BspOrder::kFirst)
    throw Error(fmt::format("{}: parameter 'seed' has no effect with order=first", params.name()));
  if (params.has("candidates") && p.order != BspOrder::kFewestCuts)
    throw Error(
        fmt::format("{}: parameter 'candidates' applies to order=fewest-cuts only", params.name()));
  p.seed = uint64_t(params.get_int("seed", 1, 0, (1ll << 62)));
  p.candidates = int(params.get_int("candidates", p.candidates, 1, 1024));
  p.max_depth = int(params.get_int("depth", p.max_depth, 1, kBspMaxDepth));
  p.max_fragments =
      size_t(params.get_int("max_fragments", (long long)p.max_fragments, 1, 1ll << 28));
  return p;
}

namespace {

/// A fragment during the build: its primitive and its polygon in the list's vertex array.
struct Frag {
  uint32_t prim, first, count;
};

/// The fragments and objects of one node, fragments in the order of the build.
struct FragList {
  std::vector<Frag> frags;
  std::vector<Vec3d> verts;
  std::vector<uint32_t> objects;  ///< spheres and polygons without a plane

  bool empty() const { return frags.empty() && objects.empty(); }
  std::span<const Vec3d> polygon(const Frag& f) const { return {verts.data() + f.first, f.count}; }
  void add(uint32_t prim, std::span<const Vec3d> poly) {
    frags.push_back({prim, uint32_t(verts.size()), uint32_t(poly.size())});
    verts.insert(verts.end(), poly.begin(), poly.end());
  }
};

/// A node still to build: its list, where to link it, and its depth.
struct Job {
  FragList list;
  uint32_t parent;  ///< kBspEmpty for the root
  int side;         ///< child slot in the parent
  int depth;
};

/// Polygon of primitive `id` (3 or 4 vertices) at time 0, or at time 1 when `end`; 0 for a
/// sphere.
int end_polygon(const PrimitiveSet& prims, uint32_t id, bool end, Vec3d out[4]) {
  switch (prims.kind(id)) {
    case PrimKind::kTriangle: {
      const Vec3* p = end ? prims.triangle_end(id) : prims.triangle(id);
      for (int k = 0; k < 3; ++k) out[k] = Vec3d(p[k]);
      return 3;
    }
    case PrimKind::kQuad: {  // corners in order around the parallelogram, summed in double
      const QuadData& q = end ? prims.quad_end(id) : prims.quad(id);
      const Vec3d p(q.p), e1(q.e1), e2(q.e2);
      out[0] = p, out[1] = p + e1, out[2] = p + e1 + e2, out[3] = p + e2;
      return 4;
    }
    default:
      return 0;
  }
}

/// Polygon of a static primitive `id` (3 or 4 vertices); 0 for a sphere or a moving primitive,
/// which has no fixed plane: it never splits and is an object, like a sphere.
int prim_polygon(const PrimitiveSet& prims, uint32_t id, Vec3d out[4]) {
  return prims.moving(id) ? 0 : end_polygon(prims, id, false, out);
}

/// Nodes with fewer objects (and no fragments) are leaves.
constexpr size_t kMinObjectsToSplit = 8;

/// Top-down, depth-first auto-partition with an explicit stack of jobs.
class Builder {
 public:
  Builder(const PrimitiveSet& prims, const BspBuildParams& params, const BspFragmentSink* sink)
      : prims_(prims), params_(params), sink_(sink) {}

  BspBuildResult run() {
    FragList root = root_list();
    if (root.empty()) return std::move(out_);
    std::vector<Job> jobs;
    jobs.push_back({std::move(root), kBspEmpty, 0, 0});
    while (!jobs.empty()) {
      Job job = std::move(jobs.back());
      jobs.pop_back();
      const auto index = uint32_t(out_.nodes.size());
      out_.nodes.emplace_back();
      if (job.parent != kBspEmpty) out_.nodes[job.parent].child[job.side] = index;
      if (job.depth >= params_.max_depth) {
        make_leaf(job, index);
      } else if (!job.list.frags.empty()) {
        const size_t splitter = choose(job.list);
        split(job, index, planes_[job.list.frags[splitter].prim], splitter, jobs);
      } else if (const auto plane = object_splitter(job.list)) {
        split(job, index, *plane, SIZE_MAX, jobs);
      } else {
        make_leaf(job, index);
      }
    }
    out_.nodes.shrink_to_fit();
    out_.refs.shrink_to_fit();
    return std::move(out_);
  }

 private:
  /// Every valid primitive: planar ones as fragments in the build order, the rest as objects.
  FragList root_list() {
    std::vector<uint32_t> order;
    for (uint32_t i = 0; i < prims_.size(); ++i)
      if (!prims_.prim_bounds(i).empty()) order.push_back(i);
    if (params_.order != BspOrder::kFirst) {  // Fisher-Yates with the seeded generator
      Pcg32 rng(params_.seed, 0x6273702d6f726465ull);
      for (size_t i = order.size(); i > 1; --i)
        std::swap(order[i - 1], order[rng.next_bounded(uint32_t(i))]);
    }
    const Bounds3& b = prims_.bounds();
    if (!b.empty()) out_.scale = std::max(max_component(abs(b.lo)), max_component(abs(b.hi)));
    eps_ = kBspBuildEps * out_.scale;
    planes_.assign(prims_.size(), BspPlane{});
    object_plane_.assign(prims_.size(), 0);
    FragList list;
    Vec3d poly[4];
    for (uint32_t id : order) {
      const int n = prim_polygon(prims_, id, poly);
      // Half the build tolerance: the plane rounded to float stays well inside it.
      const auto plane = polygon_plane({poly, size_t(n)}, 0.5 * eps_);
      if (plane) {
        planes_[id] = *plane;
        list.add(id, {poly, size_t(n)});
      } else {
        list.objects.push_back(id);
        if (prims_.moving(id)) moving_plane(id);
      }
    }
    out_.planar = list.frags.size();
    spend(list.frags.size() + list.objects.size());
    return list;
  }

  /// A moving polygon's plane half-way through its motion (a splitting candidate for nodes left
  /// with objects only), when it has one.
  void moving_plane(uint32_t id) {
    Vec3d a[4], b[4];
    const int n = end_polygon(prims_, id, false, a);
    end_polygon(prims_, id, true, b);
    for (int k = 0; k < n; ++k) a[k] = (a[k] + b[k]) * 0.5;
    if (const auto plane = polygon_plane({a, size_t(n)}, 0.5 * eps_)) {
      planes_[id] = *plane;
      object_plane_[id] = 1;
    }
  }

  /// For a node without fragments: the plane of one of its moving polygons (at mid-motion) that
  /// best splits its objects, or none (a leaf). Moving primitives never lie in a plane, so the
  /// plane only separates; without it a mesh that moves as a whole would be one leaf (brute
  /// force). Among up to 8 candidates spread over the node's (random) order, the one leaving the
  /// fewest objects on its fuller side, which must hold fewer than the node (progress).
  std::optional<BspPlane> object_splitter(const FragList& list) {
    const std::vector<uint32_t>& objs = list.objects;
    if (objs.size() < kMinObjectsToSplit) return std::nullopt;
    std::vector<uint32_t> candidates;
    for (uint32_t id : objs)
      if (object_plane_[id]) candidates.push_back(id);
    const size_t c = std::min<size_t>(candidates.size(), 8);
    std::optional<BspPlane> best;
    size_t best_side = objs.size();
    for (size_t ci = 0; ci < c; ++ci) {
      const BspPlane& plane = planes_[candidates[(2 * ci + 1) * candidates.size() / (2 * c)]];
      size_t below = 0, above = 0;
      for (uint32_t id : objs) {
        bool lower, upper;
        object_sides(id, plane, lower, upper);
        below += lower, above += upper;
      }
      if (std::max(below, above) < best_side) best = plane, best_side = std::max(below, above);
    }
    return best;
  }

  /// Index in `list` of the fragment whose plane splits the node.
  size_t choose(const FragList& list) {
    const size_t n = list.frags.size();
    if (params_.order != BspOrder::kFewestCuts || n <= 2) return 0;
    // Fewest cuts among `candidates` fragments spread evenly over the (random) order, each scored
    // on at most kBspCutSample fragments spread the same way: O(candidates) per fragment of the
    // node, never O(n^2). Ties go to the better balance, then to the earlier candidate.
    const size_t c = std::min(n, size_t(params_.candidates));
    const size_t m = std::min(n, size_t(kBspCutSample));
    size_t best = 0, best_cuts = SIZE_MAX, best_balance = SIZE_MAX;
    for (size_t ci = 0; ci < c; ++ci) {
      const size_t k = (2 * ci + 1) * n / (2 * c);
      const BspPlane& plane = planes_[list.frags[k].prim];
      size_t cuts = 0, below = 0, above = 0;
      for (size_t si = 0; si < m; ++si) {
        const size_t j = (2 * si + 1) * n / (2 * m);
        if (j == k) continue;
        const BspSide side = classify_polygon(list.polygon(list.frags[j]), plane, eps_, dist_);
        cuts += side == BspSide::kStraddling;
        below += side == BspSide::kNegative || side == BspSide::kStraddling;
        above += side == BspSide::kPositive || side == BspSide::kStraddling;
      }
      const size_t balance = below > above ? below - above : above - below;
      if (cuts < best_cuts || (cuts == best_cuts && balance < best_balance))
        best = k, best_cuts = cuts, best_balance = balance;
    }
    return best;
  }

  /// Splits the node by `plane`, that of fragment `splitter` (or of a moving object when
  /// `splitter` is SIZE_MAX): fragments in the plane stay at the node, the others go below or
  /// above it, cut in two when they straddle it; objects go to every side they reach.
  void split(Job& job, uint32_t index, const BspPlane plane, size_t splitter,
             std::vector<Job>& jobs) {
    const FragList& list = job.list;
    FragList below, above;
    std::vector<uint32_t> coplanar;
    for (size_t i = 0; i < list.frags.size(); ++i) {
      const Frag& f = list.frags[i];
      const auto poly = list.polygon(f);
      const BspSide side =
          i == splitter ? BspSide::kCoplanar : classify_polygon(poly, plane, eps_, dist_);
      switch (side) {
        case BspSide::kCoplanar:
          coplanar.push_back(f.prim);
          emit(f.prim, index, poly);
          break;
        case BspSide::kNegative:
          below.add(f.prim, poly);
          break;
        case BspSide::kPositive:
          above.add(f.prim, poly);
          break;
        case BspSide::kStraddling:
          split_polygon(poly, dist_, eps_, above_poly_, below_poly_);
          below.add(f.prim, below_poly_);
          above.add(f.prim, above_poly_);
          spend(1);
          break;
      }
    }
    for (uint32_t id : list.objects) {
      bool lower, upper;
      object_sides(id, plane, lower, upper);
      if (lower) below.objects.push_back(id);
      if (upper) above.objects.push_back(id);
      if (lower && upper) spend(1);
    }
    BspNode& node = out_.nodes[index];
    node.n = plane.n;
    node.d = plane.d;
    store_refs(node, coplanar);
    job.list = {};  // release the parent's polygons before the children are built
    FragList* sides[2] = {&below, &above};
    for (int s = 1; s >= 0; --s) {  // below is built first (pushed last)
      if (sides[s]->empty()) {
        ++out_.empty_cells, ++out_.leaves;
        out_.max_depth = std::max(out_.max_depth, size_t(job.depth) + 1);
      } else {
        jobs.push_back({std::move(*sides[s]), index, s, job.depth + 1});
      }
    }
  }

  /// A leaf: the node's objects, and its fragments when the depth cap stopped the recursion.
  void make_leaf(const Job& job, uint32_t index) {
    std::vector<uint32_t> ids = job.list.objects;
    out_.object_refs += ids.size();
    for (const Frag& f : job.list.frags) {
      ids.push_back(f.prim);
      emit(f.prim, index, job.list.polygon(f));
    }
    out_.capped_leaves += !job.list.frags.empty();
    BspNode& node = out_.nodes[index];
    node.child[0] = node.child[1] = kBspLeaf;
    store_refs(node, ids);
    ++out_.leaves;
    out_.max_depth = std::max(out_.max_depth, size_t(job.depth));
  }

  /// Appends the node's references, each primitive once.
  void store_refs(BspNode& node, std::vector<uint32_t>& ids) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    node.first = uint32_t(out_.refs.size());
    node.count = uint32_t(ids.size());
    out_.refs.insert(out_.refs.end(), ids.begin(), ids.end());
  }

  /// Which sides of `plane` object `id` reaches beyond the tolerance; an object within the
  /// tolerance of the plane on both sides goes above only (the regions overlap there).
  void object_sides(uint32_t id, const BspPlane& plane, bool& lower, bool& upper) const {
    // The signed distance of every point is linear in the vertices (centre and radius), and
    // these are linear in time for a moving object: its extremes are at the ends' vertices.
    double lo = INFINITY, hi = -INFINITY;
    for (const bool end : {false, true}) {
      if (end && !prims_.moving(id)) break;
      if (prims_.kind(id) == PrimKind::kSphere) {
        const SphereData& s = end ? prims_.sphere_end(id) : prims_.sphere(id);
        const double c = plane.distance(Vec3d(s.center));
        lo = std::min(lo, c - double(s.radius)), hi = std::max(hi, c + double(s.radius));
      } else {
        Vec3d poly[4];
        const int n = end_polygon(prims_, id, end, poly);
        for (int k = 0; k < n; ++k) {
          const double s = plane.distance(poly[k]);
          lo = std::min(lo, s), hi = std::max(hi, s);
        }
      }
    }
    lower = lo < -eps_;
    upper = hi > eps_ || !lower;
  }

  /// A final fragment: counted, and shown to the sink.
  void emit(uint32_t prim, uint32_t node, std::span<const Vec3d> poly) {
    ++out_.fragments;
    if (sink_) (*sink_)(prim, node, poly);
  }

  /// Counts `n` new fragments or object references against the budget.
  void spend(size_t n) {
    made_ += n;
    if (made_ > params_.max_fragments)
      throw Error(fmt::format(
          "bsp: the build needs more than max_fragments={} fragments and object references for {} "
          "primitives ({} planar); raise max_fragments, lower depth or try order=fewest-cuts",
          params_.max_fragments, prims_.size(), out_.planar));
  }

  const PrimitiveSet& prims_;
  const BspBuildParams params_;
  const BspFragmentSink* sink_;
  double eps_ = 0;                  ///< build tolerance (absolute)
  std::vector<BspPlane> planes_;    ///< plane of each planar primitive
  std::vector<char> object_plane_;  ///< 1 for a moving polygon with a mid-motion plane in planes_
  size_t made_ = 0;                 ///< fragments and object references made so far
  std::vector<double> dist_;        ///< scratch: vertex distances
  std::vector<Vec3d> below_poly_, above_poly_;  ///< scratch: split parts
  BspBuildResult out_;
};

}  // namespace

BspBuildResult build_bsp(const PrimitiveSet& prims, const BspBuildParams& params,
                         const BspFragmentSink* sink) {
  return Builder(prims, params, sink).run();
}

}  // namespace penumbra
