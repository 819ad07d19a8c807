#pragma once
/// A balanced kd-tree over points: the lecture's kd-tree in its point form, for photon maps and
/// other point queries (Bentley 1975, "Multidimensional binary search trees used for associative
/// searching"; the photon-map layout after Jensen 2001, "Realistic Image Synthesis Using Photon
/// Mapping", chapter 6). Separate from the ray accelerators: it answers "which points are near q",
/// not "what does this ray hit".
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/core/bounds.h"
#include "penumbra/core/error.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// One point found by a query: its index in PointKdTree::points() and its squared distance.
struct KdNeighbor {
  uint32_t index = 0;
  float dist2 = 0;
};

/// A kd-tree over records of type T, each with a public `Vec3 p` member (its position). The
/// records are stored once, reordered into tree order (a node is the median of its subrange:
/// no pointers, no child indices), with one byte per node for its split axis.
///
/// Layout: pointer-free like Jensen's balanced photon map (2001, chapter 6), but in in-order
/// form rather than his left-balanced heap order, so a subtree is a contiguous subrange. The
/// node of the subrange [lo, hi) is the record at mid = lo + (hi - lo) / 2; its left subtree is
/// [lo, mid) and its right subtree (mid, hi). The build puts there the median along the axis of
/// largest extent of the subrange's bounds (std::nth_element, so p[axis] <= median on the left
/// and >= on the right). Each level costs O(n) (bounds plus a linear-time selection), the depth is
/// floor(log2 N) + 1, so the build is O(N log N) and needs no memory beyond the axes. Queries walk
/// the same subranges iteratively with a fixed-size stack: near child first, far child only if
/// the split plane is within the search radius (Bentley 1975; Friedman, Bentley, Finkel 1977,
/// "An Algorithm for Finding Best Matches in Logarithmic Expected Time").
template <class T>
class PointKdTree {
 public:
  PointKdTree() = default;
  /// Builds the tree over `points` (taking them): O(N log N); throws Error above 2^32 - 1 points.
  explicit PointKdTree(std::vector<T> points);

  /// Number of points.
  size_t size() const { return points_.size(); }
  /// True when the tree holds no points.
  bool empty() const { return points_.empty(); }
  /// The points, in tree order (indices of KdNeighbor refer to this order).
  const std::vector<T>& points() const { return points_; }
  /// Bounds of the points (the empty box for an empty tree).
  const Bounds3& bounds() const { return bounds_; }
  /// Bytes held (records and split axes).
  size_t bytes() const { return points_.capacity() * sizeof(T) + axes_.capacity(); }

  /// Calls f(const T& point, float dist2) for every point with squared distance to q at most r2,
  /// in no particular order.
  template <class F>
  void for_each_in_radius(Vec3 q, float r2, F&& f) const;

  /// The (up to) k nearest points to q among those with squared distance at most max_r2 for
  /// which accept(const T&) is true, written to `out` sorted by increasing distance (ties in
  /// any order); returns how many. `out` is reused (cleared first) so queries allocate nothing
  /// once it has grown to k.
  template <class Accept>
  size_t nearest(Vec3 q, size_t k, float max_r2, std::vector<KdNeighbor>& out,
                 Accept&& accept) const;
  /// nearest() accepting every point.
  size_t nearest(Vec3 q, size_t k, float max_r2, std::vector<KdNeighbor>& out) const {
    return nearest(q, k, max_r2, out, [](const T&) { return true; });
  }

 private:
  static constexpr uint8_t kLeaf = 3;
  /// A balanced tree of < 2^32 points has depth <= 32; a traversal stack holds at most one
  /// pending far child per level, so 64 leaves a wide margin.
  static constexpr int kStackSize = 64;

  /// A subtree waiting on the traversal stack, with the squared distance from q to its split
  /// plane: kept so it can be dropped when popped if the k-nearest radius has shrunk since.
  struct Pending {
    uint32_t lo, hi;
    float plane_d2;
  };

  void build(size_t lo, size_t hi, const Bounds3& box);
  static Bounds3 bounds_of(const T* first, const T* last);
  static float distance2(Vec3 a, Vec3 b) {
    const Vec3 d = a - b;
    return d.x * d.x + d.y * d.y + d.z * d.z;
  }
  template <class Visit>
  void traverse(Vec3 q, const float& r2, Visit&& visit) const;

  std::vector<T> points_;
  std::vector<uint8_t> axes_;  ///< split axis of the node at each index (3: leaf)
  Bounds3 bounds_;
};

template <class T>
PointKdTree<T>::PointKdTree(std::vector<T> points) : points_(std::move(points)) {
  if (points_.size() > std::numeric_limits<uint32_t>::max())
    throw Error("PointKdTree: " + std::to_string(points_.size()) +
                " points, more than the 2^32 - 1 that 32-bit neighbour indices can address");
  // Drop the slack of a vector grown by push_back (up to 2x for photon maps): records are the
  // whole cost of the structure. A no-op when capacity == size.
  points_.shrink_to_fit();
  axes_.assign(points_.size(), kLeaf);
  if (points_.empty()) return;
  bounds_ = bounds_of(points_.data(), points_.data() + points_.size());
  build(0, points_.size(), bounds_);
}

template <class T>
Bounds3 PointKdTree<T>::bounds_of(const T* first, const T* last) {
  Bounds3 b;
  for (; first != last; ++first) b.extend(first->p);
  return b;
}

template <class T>
void PointKdTree<T>::build(size_t lo, size_t hi, const Bounds3& box) {
  // Recursion depth is the tree depth, floor(log2 N) + 1 <= 32: no risk for the call stack.
  // Subranges of size 1 are leaves (axes_ was filled with kLeaf); size 0 has no node.
  if (hi - lo < 2) return;
  // Split on the axis of largest extent of the subrange's own (tight) bounds, so clustered or
  // flat point sets still get cut where they spread; an all-equal subrange picks any axis.
  const int axis = box.max_extent_axis();
  const size_t mid = lo + (hi - lo) / 2;
  T* base = points_.data();
  // One comparator per axis, chosen once per node, so the selection's inner loop compares one
  // float member without branching on the axis.
  switch (axis) {
    case 0:
      std::nth_element(base + lo, base + mid, base + hi,
                       [](const T& a, const T& b) { return a.p.x < b.p.x; });
      break;
    case 1:
      std::nth_element(base + lo, base + mid, base + hi,
                       [](const T& a, const T& b) { return a.p.y < b.p.y; });
      break;
    default:
      std::nth_element(base + lo, base + mid, base + hi,
                       [](const T& a, const T& b) { return a.p.z < b.p.z; });
      break;
  }
  axes_[mid] = uint8_t(axis);
  if (mid - lo >= 2) build(lo, mid, bounds_of(base + lo, base + mid));
  if (hi - (mid + 1) >= 2) build(mid + 1, hi, bounds_of(base + mid + 1, base + hi));
}

template <class T>
template <class Visit>
void PointKdTree<T>::traverse(Vec3 q, const float& r2, Visit&& visit) const {
  // r2 is read by reference: the k-nearest visitor shrinks it as it finds closer points, and
  // every pruning test below sees the current value.
  if (points_.empty()) return;
  Pending stack[kStackSize];
  int top = 0;
  stack[top++] = {0, uint32_t(points_.size()), 0.0f};
  const T* pts = points_.data();
  const uint8_t* axes = axes_.data();
  while (top > 0) {
    Pending e = stack[--top];
    // Re-test on pop: the radius may have shrunk since this far child was pushed.
    if (e.plane_d2 > r2) continue;
    uint32_t lo = e.lo, hi = e.hi;
    // Descend to a leaf, always into the near child, leaving the far child on the stack.
    while (lo < hi) {
      const uint32_t mid = lo + (hi - lo) / 2;
      const T& node = pts[mid];
      visit(mid, node, distance2(q, node.p));
      const int axis = axes[mid];
      if (axis == kLeaf) break;
      const float diff = q[axis] - node.p[axis];
      const float plane_d2 = diff * diff;
      // Left holds p[axis] <= split, right p[axis] >= split: the far side is at least |diff|
      // away along the axis. The rounded diff^2 never exceeds the rounded distance of a point
      // behind the plane, so `plane_d2 > r2` prunes only points that fail `dist2 <= r2`.
      uint32_t far_lo, far_hi;
      if (diff < 0.0f) {
        far_lo = mid + 1, far_hi = hi, hi = mid;
      } else {
        far_lo = lo, far_hi = mid, lo = mid + 1;
      }
      if (far_lo < far_hi && plane_d2 <= r2) stack[top++] = {far_lo, far_hi, plane_d2};
    }
  }
}

template <class T>
template <class F>
void PointKdTree<T>::for_each_in_radius(Vec3 q, float r2, F&& f) const {
  traverse(q, r2, [&](uint32_t, const T& point, float d2) {
    if (d2 <= r2) f(point, d2);
  });
}

template <class T>
template <class Accept>
size_t PointKdTree<T>::nearest(Vec3 q, size_t k, float max_r2, std::vector<KdNeighbor>& out,
                               Accept&& accept) const {
  out.clear();
  if (k == 0 || points_.empty()) return 0;
  // out is a max-heap on dist2 (std heap order) while searching, sorted at the end.
  const auto closer = [](const KdNeighbor& a, const KdNeighbor& b) { return a.dist2 < b.dist2; };
  // Inclusive search bound: a point counts if dist2 <= r2. Once k points are held, only a
  // strictly closer one can improve the set (ties may be returned in any order), so r2 becomes
  // the float just below the k-th distance. The strict bound matters for duplicates: with many
  // copies of one point, an inclusive bound would visit every copy after the first k.
  float r2 = max_r2;
  const auto shrink = [&] {
    r2 = std::nextafter(out.front().dist2, -std::numeric_limits<float>::infinity());
  };
  traverse(q, r2, [&](uint32_t index, const T& point, float d2) {
    // Distance first: it is cheap and in cache, the predicate may not be.
    if (!(d2 <= r2) || !accept(point)) return;
    if (out.size() < k) {
      out.push_back({index, d2});
      std::push_heap(out.begin(), out.end(), closer);
      if (out.size() == k) shrink();
      return;
    }
    // Replace the farthest: one sift-down from the root instead of pop_heap + push_heap.
    const size_t n = out.size();
    size_t i = 0;
    for (;;) {
      size_t c = 2 * i + 1;
      if (c >= n) break;
      if (c + 1 < n && out[c + 1].dist2 > out[c].dist2) ++c;
      if (out[c].dist2 <= d2) break;
      out[i] = out[c];
      i = c;
    }
    out[i] = {index, d2};
    shrink();
  });
  std::sort_heap(out.begin(), out.end(), closer);
  return out.size();
}

}  // namespace penumbra
