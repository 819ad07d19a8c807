#include "penumbra/accel2d/segment_bsp.h"

#include <numeric>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/timer.h"

namespace penumbra::lab2d {

namespace {

/// fewest-cuts scores every fragment of a cell against every other when the cell holds at most
/// this many (O(m²)); larger cells score kCandidates fragments spread evenly over the cell's list
/// against all of its fragments (O(kCandidates · m)), so the build stays near O(n log² n) · 32.
constexpr size_t kExhaustive = 256;
constexpr size_t kCandidates = 32;

/// Side of fragment f of segment s relative to line (kBoth: cut strictly inside).
Side classify(const Segment2& s, const Fragment& f, const Line2& line, double eps) {
  return side_of_piece(line.eval(s.at(f.t0)), line.eval(s.at(f.t1)), eps);
}

}  // namespace

BspOrder parse_bsp_order(const std::string& text) {
  if (text == "random") return BspOrder::kRandom;
  if (text == "first") return BspOrder::kFirst;
  if (text == "fewest-cuts") return BspOrder::kFewestCuts;
  throw Error(fmt::format("unknown BSP order '{}' (valid: random, first, fewest-cuts)", text));
}

const char* to_string(BspOrder order) {
  switch (order) {
    case BspOrder::kRandom:
      return "random";
    case BspOrder::kFirst:
      return "first";
    case BspOrder::kFewestCuts:
      return "fewest-cuts";
  }
  return "?";
}

SegmentBsp::SegmentBsp(const ParamList& p)
    : order_(parse_bsp_order(p.get_string("order", "random"))),
      seed_(uint64_t(p.get_int("seed", 1, 0, (1ll << 53)))) {
  p.check_all_used();
}

std::string SegmentBsp::name() const {
  return fmt::format("bsp:order={},seed={}", to_string(order_), seed_);
}

size_t SegmentBsp::cuts_of(const std::vector<Fragment>& work, size_t begin, size_t end,
                           size_t k) const {
  const Segment2& s = segs_[work[k].seg];
  const Line2 line = Line2::through(s.a, s.b);
  size_t cuts = 0;
  for (size_t i = begin; i < end; ++i)
    cuts += i != k && classify(segs_[work[i].seg], work[i], line, eps_) == Side::kBoth;
  return cuts;
}

size_t SegmentBsp::pick_splitter(const std::vector<Fragment>& work, size_t begin,
                                 size_t end) const {
  if (order_ != BspOrder::kFewestCuts) return begin;  // the permutation decides
  const size_t m = end - begin;
  const size_t candidates = m <= kExhaustive ? m : kCandidates;
  size_t best = begin, best_cuts = SIZE_MAX;
  for (size_t c = 0; c < candidates; ++c) {
    const size_t k = begin + c * m / candidates;
    const size_t cuts = cuts_of(work, begin, end, k);
    if (cuts < best_cuts) best = k, best_cuts = cuts;  // ties: the earlier one
    if (cuts == 0) break;
  }
  return best;
}

void SegmentBsp::build(const Scene2D& scene) {
  const Timer timer;
  if (!scene.all_segments())
    throw Error(scene.source + ": the segment BSP takes segments only (use --structure objects)");
  segs_.clear();
  for (const Shape2& s : scene.shapes) segs_.push_back(s.segment());
  eps_ = scene.eps();
  tree_ = LineTree{};
  frags_.clear();

  // The order: a seeded Fisher–Yates permutation (2DRANDOMBSP), or the input order.
  std::vector<uint32_t> perm(segs_.size());
  std::iota(perm.begin(), perm.end(), 0u);
  if (order_ == BspOrder::kRandom) {
    Pcg32 rng(seed_, 0x2d);
    for (size_t i = perm.size(); i > 1; --i)
      std::swap(perm[i - 1], perm[rng.next_bounded(uint32_t(i))]);
  }
  // Work list: the fragments of the cells still to split, the cell on top of the job stack last.
  std::vector<Fragment> work;
  work.reserve(2 * segs_.size());
  for (uint32_t s : perm) work.push_back({s, 0.0, 1.0});
  struct Job {
    size_t begin, end;
    uint32_t parent;
    int side;
    uint32_t depth;
  };
  std::vector<Job> jobs{{0, work.size(), LineNode::kNone, 0, 0}};
  std::vector<Fragment> pos, neg;
  while (!jobs.empty()) {
    const Job job = jobs.back();
    jobs.pop_back();
    const size_t m = job.end - job.begin;
    tree_.depth = std::max<size_t>(tree_.depth, job.depth);
    LineNode node;
    node.first = uint32_t(frags_.size());
    uint32_t index;
    if (m <= 1) {
      // A leaf: at most one fragment.
      if (m == 1) frags_.push_back(work[job.begin]);
      node.count = uint32_t(m);
      index = tree_.add(node, false);
    } else {
      // Split by ℓ(s) of the chosen fragment; it and the fragments in ℓ(s) stay at the node.
      const size_t k = pick_splitter(work, job.begin, job.end);
      const Segment2& split = segs_[work[k].seg];
      node.line = Line2::through(split.a, split.b);
      pos.clear();
      neg.clear();
      frags_.push_back(work[k]);
      node.touch = 0;
      // Records that `side` (0: ℓ⁺, 1: ℓ⁻) holds a fragment within 4 eps of the line.
      auto note = [&](int side, const Segment2& s, const Fragment& f) {
        if (std::min(std::abs(node.line.eval(s.at(f.t0))), std::abs(node.line.eval(s.at(f.t1)))) <=
            4 * eps_)
          node.touch |= uint8_t(1 << side);
      };
      for (size_t i = job.begin; i < job.end; ++i) {
        if (i == k) continue;
        const Fragment f = work[i];
        const Segment2& s = segs_[f.seg];
        switch (classify(s, f, node.line, eps_)) {
          case Side::kOn:
            frags_.push_back(f);
            break;
          case Side::kPositive:
            pos.push_back(f);
            note(0, s, f);
            break;
          case Side::kNegative:
            neg.push_back(f);
            note(1, s, f);
            break;
          case Side::kBoth: {
            // Cut at the crossing, computed on the whole segment: the two pieces share tc.
            const double da = node.line.eval(s.a), db = node.line.eval(s.b);
            const double tc = da / (da - db);
            const bool first_positive = node.line.eval(s.at(f.t0)) > 0;
            if (!(tc > f.t0 && tc < f.t1)) {  // rounding put tc outside: keep the larger part
              const double d0 = std::abs(node.line.eval(s.at(f.t0)));
              const double d1 = std::abs(node.line.eval(s.at(f.t1)));
              const bool positive = d0 >= d1 ? first_positive : !first_positive;
              (positive ? pos : neg).push_back(f);
              node.touch = 3;
              break;
            }
            (first_positive ? pos : neg).push_back({f.seg, f.t0, tc});
            (first_positive ? neg : pos).push_back({f.seg, tc, f.t1});
            node.touch = 3;  // both pieces end in the line
            break;
          }
        }
      }
      node.count = uint32_t(frags_.size() - node.first);
      index = tree_.add(node, true);
      // Children: ℓ⁻ below ℓ⁺ in the work list and on the job stack, so ℓ⁺ is built first
      // (preorder, ℓ⁺ first) and each cell's fragments are the top of the work list.
      work.resize(job.begin);
      work.insert(work.end(), neg.begin(), neg.end());
      work.insert(work.end(), pos.begin(), pos.end());
      const size_t mid = job.begin + neg.size();
      jobs.push_back({job.begin, mid, index, 1, job.depth + 1});
      jobs.push_back({mid, work.size(), index, 0, job.depth + 1});
    }
    if (m <= 1) work.resize(job.begin);
    if (job.parent != LineNode::kNone) tree_.nodes[job.parent].child[job.side] = index;
  }
  tree_.refs.resize(frags_.size());
  for (size_t i = 0; i < frags_.size(); ++i) tree_.refs[i] = frags_[i].seg;
  build_ms_ = timer.elapsed_ms();
}

Hit2 SegmentBsp::shoot(const Ray2& ray, TraceLog* trace) const {
  return shoot_line_tree(
      tree_, ray, eps_, [&](uint32_t id) { return intersect(ray, segs_[id]); }, trace);
}

Stats2D SegmentBsp::stats() const {
  Stats2D s = line_tree_stats(tree_, build_ms_);  // refs hold one id per fragment
  size_t empty = 0;
  for (const LineNode& n : tree_.nodes) empty += n.leaf() && n.count == 0;
  s.extra = {{"segments", double(segs_.size())},
             {"cuts", double(frags_.size()) - double(segs_.size())},
             {"empty_leaves", double(empty)}};
  return s;
}

Drawing2D SegmentBsp::draw(const Box2d& frame) const {
  return draw_line_tree(tree_, frame);
}

}  // namespace penumbra::lab2d
