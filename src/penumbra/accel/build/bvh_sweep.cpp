#include "penumbra/accel/build/bvh_sweep.h"

#include <algorithm>

#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/parallel_sort.h>

#include "penumbra/accel/build/box_accumulator.h"

namespace penumbra {

namespace {

/// The strict total order of the sweep along `axis`: centroid, then id.
inline bool before(const PrimRef& x, const PrimRef& y, int axis) {
  const float cx = x.lo[axis] + x.hi[axis], cy = y.lo[axis] + y.hi[axis];  // as centroid2()
  return cx < cy || (cx == cy && x.id < y.id);
}

/// Calls f(0), f(1), ... f(k - 1) for k of 2 or 3, as parallel tasks when `parallel` is set.
template <class F>
void for_axes(int k, bool parallel, const F& f) {
  if (!parallel) {
    for (int i = 0; i < k; ++i) f(i);
  } else if (k == 2) {
    tbb::parallel_invoke([&] { f(0); }, [&] { f(1); });
  } else {
    tbb::parallel_invoke([&] { f(0); }, [&] { f(1); }, [&] { f(2); });
  }
}

}  // namespace

SahSplit find_exact_split(std::span<PrimRef> refs, int block_shift) {
  const auto n = uint32_t(refs.size());
  SahSplit best;
  if (n < 2 || n > kMaxExactSplit) return best;
  const auto sort_along = [&](int axis) {
    std::sort(refs.begin(), refs.end(),
              [axis](const PrimRef& x, const PrimRef& y) { return before(x, y, axis); });
  };
  float right[kMaxExactSplit];
  for (int axis = 0; axis < 3; ++axis) {
    sort_along(axis);  // in place: the last axis' order stays if it is the best
    // From the right: right[i] = area of the box of [i, n).
    BoxAccumulator acc;
    for (uint32_t i = n - 1; i > 0; --i) {
      acc.add(&refs[i].lo.x, &refs[i].hi.x);
      right[i] = acc.area();
    }
    // From the left: the cost of [0, i) | [i, n).
    acc = BoxAccumulator();
    for (uint32_t i = 1; i < n; ++i) {
      acc.add(&refs[i - 1].lo.x, &refs[i - 1].hi.x);
      const float cost =
          acc.area() * sah_tests(i, block_shift) + right[i] * sah_tests(n - i, block_shift);
      if (best.axis < 0 || cost < best.cost) best.axis = axis, best.cost = cost, best.pos = int(i);
    }
  }
  if (best.axis != 2) sort_along(best.axis);
  best.left_count = uint32_t(best.pos), best.right_count = n - best.left_count;
  BoxAccumulator left, right_box;
  for (uint32_t i = 0; i < n; ++i)
    (i < best.left_count ? left : right_box).add(&refs[i].lo.x, &refs[i].hi.x);
  best.left = left.bounds(), best.right = right_box.bounds();
  return best;
}

SweepSahSplitter::SweepSahSplitter(std::span<PrimRef> refs, const BvhBuildParams& params)
    : params_(params), n_(refs.size()) {
  sorted_[0] = refs.data();
  for (int k = 0; k < 2; ++k) {
    copies_[k].assign(refs.begin(), refs.end());
    sorted_[k + 1] = copies_[k].data();
    temp_[k].resize(n_);
  }
  right_area_.resize(3 * n_);
  // One sort per axis: the only O(N log N) step.
  for_axes(3, n_ >= params_.parallel_min, [&](int a) {
    tbb::parallel_sort(sorted_[a], sorted_[a] + n_,
                       [a](const PrimRef& x, const PrimRef& y) { return before(x, y, a); });
  });
}

SweepSahSplitter::AxisBest SweepSahSplitter::sweep(int axis, uint32_t b, uint32_t e) {
  const PrimRef* r = sorted_[axis];
  float* right = right_area_.data() + size_t(axis) * n_;
  // From the right: right[i] = area of the box of [i, e).
  BoxAccumulator acc;
  for (uint32_t i = e - 1; i > b; --i) {
    acc.add(&r[i].lo.x, &r[i].hi.x);
    right[i] = acc.area();
  }
  // From the left: the cost of [b, i) | [i, e); ties keep the first (fewest on the left).
  acc = BoxAccumulator();
  AxisBest best;
  for (uint32_t i = b + 1; i < e; ++i) {
    acc.add(&r[i - 1].lo.x, &r[i - 1].hi.x);
    const float cost = acc.area() * sah_tests(i - b, params_.block_shift) +
                       right[i] * sah_tests(e - i, params_.block_shift);
    if (best.count == 0 || cost < best.cost) best.cost = cost, best.count = i - b;
  }
  return best;
}

NodeSplit SweepSahSplitter::operator()(uint32_t b, uint32_t e, uint32_t /*cap*/, const Bounds3& box,
                                       const Bounds3& centroids, int depth) {
  const uint32_t n = e - b;
  const bool parallel = n >= params_.parallel_min;
  const bool small = n <= uint32_t(params_.max_leaf);
  int axis = 0;
  uint32_t count = n / 2;
  if (depth < kMaxSahDepth) {
    // The cheapest partition over the three axes; ties keep the lower axis.
    AxisBest best[3];
    for_axes(3, parallel, [&](int a) { best[a] = sweep(a, b, e); });
    for (int a = 1; a < 3; ++a)
      if (best[a].cost < best[axis].cost) axis = a;
    if (small &&
        sah_prefers_leaf(n, box, best[axis].cost, params_.traversal_cost, params_.block_shift))
      return NodeSplit::make_leaf();
    count = best[axis].count;
  } else {
    // Too deep for more SAH splits: the object median bounds the depth.
    if (small) return NodeSplit::make_leaf();
    axis = centroids.max_extent_axis();
  }
  return divide(axis, b, e, b + count, parallel);
}

NodeSplit SweepSahSplitter::divide(int axis, uint32_t b, uint32_t e, uint32_t mid, bool parallel) {
  NodeSplit s;
  s.mid = mid;
  // Children's boxes and centroid bounds from the prefix and suffix of the split axis.
  const PrimRef* r = sorted_[axis];
  BoxAccumulator left, right;
  for (uint32_t i = b; i < mid; ++i) {
    left.add(&r[i].lo.x, &r[i].hi.x);
    s.left_centroids.extend(r[i].centroid2());
  }
  for (uint32_t i = mid; i < e; ++i) {
    right.add(&r[i].lo.x, &r[i].hi.x);
    s.right_centroids.extend(r[i].centroid2());
  }
  s.left = left.bounds(), s.right = right.bounds();
  // The other two arrays: a stable partition by the split axis' order keeps each sorted.
  const PrimRef pivot = r[mid];  // the first reference on the right
  for_axes(2, parallel, [&](int k) {
    const int other = (axis + 1 + k) % 3;
    PrimRef* src = sorted_[other];
    PrimRef* tmp = temp_[k].data();
    uint32_t l = b, h = mid;
    for (uint32_t i = b; i < e; ++i) {
      if (before(src[i], pivot, axis))
        tmp[l++] = src[i];
      else
        tmp[h++] = src[i];
    }
    std::copy(tmp + b, tmp + e, src + b);
  });
  return s;
}

}  // namespace penumbra
