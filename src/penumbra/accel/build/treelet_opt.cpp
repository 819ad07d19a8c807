#include "penumbra/accel/build/treelet_opt.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <tuple>
#include <utility>
#include <vector>

#include "penumbra/core/parallel.h"

namespace penumbra {
namespace {

/// Subtrees per treelet, the paper's choice: the subsets, and so the time, double with each
/// one more.
constexpr int kTreeletLeaves = 7;
constexpr int kSubsets = 1 << kTreeletLeaves;

/// Surface area in double: sums over many nodes stay exact enough and cannot overflow.
double area(const Bounds3& b) {
  const double dx = double(b.hi.x) - b.lo.x, dy = double(b.hi.y) - b.lo.y,
               dz = double(b.hi.z) - b.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

class TreeletOptimizer {
 public:
  explicit TreeletOptimizer(BvhNodeArray& nodes) : nodes_(nodes) {}

  /// Post-order over the subtree of `x` (children, whose slots do not change when their own
  /// treelets are rewritten, before their parents), rewriting each inner node's treelet;
  /// returns the treelets rewritten.
  size_t subtree(uint32_t x) {
    size_t rewritten = 0;
    std::vector<std::pair<uint32_t, bool>> stack{{x, false}};
    while (!stack.empty()) {
      const auto [y, children_done] = stack.back();
      stack.pop_back();
      const BvhNode& n = nodes_[y];
      if (n.is_leaf()) continue;
      if (children_done) {
        rewritten += restructure(y);
        continue;
      }
      stack.push_back({y, true});
      stack.push_back({n.index + 1, false});
      stack.push_back({n.index, false});
    }
    return rewritten;
  }

  /// Rewrites the treelet rooted at inner node `r` when a cheaper topology exists; returns
  /// whether it did. It reads and writes only nodes of r's subtree, and r keeps its slot.
  bool restructure(uint32_t r) {
    // The treelet: start from r's children and open the subtree of largest area until there are
    // kTreeletLeaves of them (or only leaves are left). inner[] lists the opened nodes, r first,
    // parents before children.
    uint32_t leaf[kTreeletLeaves], inner[kTreeletLeaves - 1];
    int n = 0, m = 0;
    inner[m++] = r;
    leaf[n++] = nodes_[r].index;
    leaf[n++] = nodes_[r].index + 1;
    while (n < kTreeletLeaves) {
      int best = -1;
      double best_area = -1.0;
      for (int i = 0; i < n; ++i) {
        const BvhNode& c = nodes_[leaf[i]];
        if (c.is_leaf()) continue;
        const double a = area(c.bounds());
        if (a > best_area) best_area = a, best = i;
      }
      if (best < 0) break;
      const uint32_t c = leaf[best];
      inner[m++] = c;
      leaf[best] = nodes_[c].index;
      leaf[n++] = nodes_[c].index + 1;
    }
    if (n < 3) return false;  // two subtrees have one topology

    // The boxes and areas of every subset of the subtrees, then the least cost (the sum of the
    // inner nodes' areas) of a binary tree over each subset and its best split.
    const uint32_t full = (1u << n) - 1;
    for (int i = 0; i < n; ++i) box_[1u << i] = nodes_[leaf[i]].bounds();
    for (uint32_t s = 1; s <= full; ++s) {
      const uint32_t low = s & (0u - s);
      if (s != low) {
        box_[s] = box_[s ^ low];
        box_[s].extend(box_[low]);
      }
      area_[s] = area(box_[s]);
    }
    for (uint32_t s = 1; s <= full; ++s) {
      const uint32_t low = s & (0u - s);
      if (s == low) {
        cost_[s] = 0.0;
        continue;
      }
      // Each partition once: the lowest subtree on the left with any proper subset of the
      // others, largest first.
      double best = std::numeric_limits<double>::infinity();
      uint32_t best_part = 0;
      const uint32_t rest = s ^ low;
      for (uint32_t q = (rest - 1) & rest;; q = (q - 1) & rest) {
        const uint32_t p = low | q;
        const double c = cost_[p] + cost_[s ^ p];
        if (c < best) best = c, best_part = p;
        if (q == 0) break;
      }
      cost_[s] = area_[s] + best;
      split_[s] = best_part;
    }

    // The present topology's cost with the same boxes: each opened node's set of subtrees,
    // children after parents in inner[], so in reverse order.
    uint32_t mask[kTreeletLeaves - 1];
    const auto set_of = [&](uint32_t x, int after) {
      for (int i = 0; i < n; ++i)
        if (leaf[i] == x) return 1u << i;
      for (int j = after; j < m; ++j)
        if (inner[j] == x) return mask[j];
      return 0u;  // unreachable: every child is a subtree or an opened node
    };
    double old_cost = 0.0;
    for (int j = m - 1; j >= 0; --j) {
      const uint32_t c = nodes_[inner[j]].index;
      mask[j] = set_of(c, j + 1) | set_of(c + 1, j + 1);
      old_cost += area_[mask[j]];
    }
    // Rounding alone must not swap equal topologies back and forth.
    if (!(cost_[full] < old_cost * (1.0 - 1e-12))) return false;

    // Rewrite: the subtrees' nodes are kept aside, then the new inner nodes are written top
    // down, each taking the next of the opened nodes' child pairs (their slots, so each pair
    // stays where it was).
    BvhNode saved[kTreeletLeaves];
    uint32_t pairs[kTreeletLeaves - 1];
    for (int i = 0; i < n; ++i) saved[i] = nodes_[leaf[i]];
    for (int j = 0; j < m; ++j) pairs[j] = nodes_[inner[j]].index;
    int next_pair = 0;
    struct Pending {
      uint32_t slot, set;
    };
    Pending todo[kTreeletLeaves];
    int top = 0;
    todo[top++] = {r, full};
    while (top > 0) {
      const Pending p = todo[--top];
      BvhNode& node = nodes_[p.slot];
      if ((p.set & (p.set - 1)) == 0) {
        node = saved[__builtin_ctz(p.set)];
        continue;
      }
      node.set_bounds(box_[p.set]);
      node.count = 0;
      node.index = pairs[next_pair++];
      const uint32_t left = split_[p.set];
      todo[top++] = {node.index + 1, p.set ^ left};
      todo[top++] = {node.index, left};
    }
    return true;
  }

 private:
  BvhNodeArray& nodes_;
  Bounds3 box_[kSubsets];
  double area_[kSubsets];
  double cost_[kSubsets];
  uint32_t split_[kSubsets];
};

/// Sum of the inner nodes' areas over the root's, and the deepest leaf.
std::pair<double, size_t> inner_area_and_depth(const BvhNodeArray& nodes) {
  double sum = 0.0;
  size_t depth = 0;
  std::vector<std::pair<uint32_t, size_t>> stack{{0u, 0}};
  while (!stack.empty()) {
    const auto [x, d] = stack.back();
    stack.pop_back();
    const BvhNode& n = nodes[x];
    if (n.is_leaf()) {
      depth = std::max(depth, d);
      continue;
    }
    sum += area(n.bounds());
    stack.push_back({n.index, d + 1});
    stack.push_back({n.index + 1, d + 1});
  }
  const double root = area(nodes[0].bounds());
  return {root > 0 ? sum / root : 0.0, depth};
}

/// One bottom-up pass: the subtrees below depth kTaskDepth as parallel tasks, then the nodes
/// above them, children before parents. A treelet touches only its root's subtree, so the
/// order among disjoint subtrees does not matter: the result is the serial pass's, at any
/// thread count.
size_t optimize_pass(BvhNodeArray& nodes) {
  constexpr size_t kTaskDepth = 8;
  std::vector<uint32_t> tasks, top;  // inner nodes at kTaskDepth; those above, in post-order
  std::vector<std::tuple<uint32_t, size_t, bool>> stack{{0u, 0, false}};
  while (!stack.empty()) {
    const auto [x, depth, children_done] = stack.back();
    stack.pop_back();
    const BvhNode& n = nodes[x];
    if (n.is_leaf()) continue;
    if (depth == kTaskDepth) {
      tasks.push_back(x);
    } else if (children_done) {
      top.push_back(x);
    } else {
      stack.emplace_back(x, depth, true);
      stack.emplace_back(n.index + 1, depth + 1, false);
      stack.emplace_back(n.index, depth + 1, false);
    }
  }
  std::vector<size_t> rewritten(tasks.size() + 1, 0);
  parallel_for(tasks.size(), [&](size_t i) {
    TreeletOptimizer opt(nodes);
    rewritten[i] = opt.subtree(tasks[i]);
  });
  TreeletOptimizer opt(nodes);
  for (const uint32_t x : top) rewritten.back() += opt.restructure(x);
  size_t total = 0;
  for (const size_t r : rewritten) total += r;
  return total;
}

}  // namespace

TreeletStats optimize_treelets(BvhNodeArray& nodes, int passes) {
  TreeletStats stats;
  if (nodes.empty()) return stats;
  std::tie(stats.area_before, stats.max_depth) = inner_area_and_depth(nodes);
  if (!nodes[0].is_leaf()) {
    for (int p = 0; p < passes; ++p) {
      const size_t rewritten = optimize_pass(nodes);
      stats.treelets += rewritten;
      if (rewritten == 0) break;
    }
  }
  std::tie(stats.area_after, stats.max_depth) = inner_area_and_depth(nodes);
  return stats;
}

}  // namespace penumbra
