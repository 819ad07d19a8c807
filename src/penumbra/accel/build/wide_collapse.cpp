#include "penumbra/accel/build/wide_collapse.h"

#include <algorithm>
#include <limits>

#include <oneapi/tbb/parallel_invoke.h>

#include "penumbra/core/error.h"

namespace penumbra {

SahCollapse::SahCollapse(const BvhNodeArray& bin, int width, float node_cost, int block_shift,
                         uint32_t max_leaf)
    : bin_(bin),
      width_(width),
      block_shift_(block_shift),
      node_cost_(node_cost),
      max_leaf_(max_leaf) {
  if (width < 2 || width > kMaxWidth) throw Error("SahCollapse: width must be in 2..16");
  if (bin.empty() || bin[0].is_leaf()) return;
  dense_.resize(bin.size());
  // Number the reachable nodes (depth first), so the table holds only those.
  uint32_t rows = 0;
  std::vector<uint32_t> stack = {0};
  while (!stack.empty()) {
    const uint32_t b = stack.back();
    stack.pop_back();
    dense_[b] = rows++;
    if (!bin[b].is_leaf()) stack.push_back(bin[b].index), stack.push_back(bin[b].index + 1);
  }
  cost_.resize(size_t(rows) * width_);
  choice_.resize(size_t(rows) * width_);
  if (max_leaf_ > 0) refs_.resize(rows);
  plan(0, rows >= kParallelRows ? kParallelDepth : 0);
  root_cost_ = cost_[row(0)];
}

void SahCollapse::plan(uint32_t b, int parallel_depth) {
  const BvhNode& n = bin_[b];
  const size_t r = row(b);
  const float area = n.bounds().surface_area();
  const auto tests_of = [&](uint32_t count) { return float(((count - 1) >> block_shift_) + 1); };
  if (n.is_leaf()) {
    if (max_leaf_ > 0) refs_[dense_[b]] = n.count;
    const float tests = tests_of(n.count);
    for (int i = 0; i < width_; ++i) cost_[r + i] = area * tests, choice_[r + i] = 0;
    return;
  }
  // The two subtrees' rows are disjoint: near the root they fill in parallel (the table is the
  // same whatever the order).
  if (parallel_depth > 0) {
    tbb::parallel_invoke([&] { plan(n.index, parallel_depth - 1); },
                         [&] { plan(n.index + 1, parallel_depth - 1); });
  } else {
    plan(n.index, 0);
    plan(n.index + 1, 0);
  }
  // One slot: this node becomes a wide node of its own over `width` slots.
  int k = 1;
  cost_[r] = node_cost_ * area + distribute(b, width_, k);
  choice_[r] = 0;
  // Or one leaf of the subtree's references, where they are few enough and that is cheaper
  // (Ylitie et al. 2017 decide leaves in the same table).
  if (max_leaf_ > 0) {
    const uint32_t refs = refs_[dense_[n.index]] + refs_[dense_[n.index + 1]];
    refs_[dense_[b]] = refs;
    if (refs <= max_leaf_ && area * tests_of(refs) <= cost_[r])
      cost_[r] = area * tests_of(refs), choice_[r] = kMerge;
  }
  for (int i = 2; i <= width_; ++i) {
    const float c = distribute(b, i, k);
    if (c < cost_[r + i - 2]) {
      cost_[r + i - 1] = c, choice_[r + i - 1] = uint8_t(k | (i - 1) << 4);
    } else {  // fewer slots are as cheap
      cost_[r + i - 1] = cost_[r + i - 2], choice_[r + i - 1] = choice_[r + i - 2];
    }
  }
}

void SahCollapse::expand(uint32_t b, int i, uint32_t* kids, int& n) const {
  const uint8_t c = choice_[row(b) + i - 1];
  const int split = c & 15, used = (c >> 4) + 1;
  if (split == 0) {
    kids[n++] = b;
    return;
  }
  expand(bin_[b].index, split, kids, n);
  expand(bin_[b].index + 1, used - split, kids, n);
}

float SahCollapse::distribute(uint32_t b, int j, int& best_k) const {
  const size_t l = row(bin_[b].index), r = row(bin_[b].index + 1);
  float best = std::numeric_limits<float>::infinity();
  for (int k = 1; k < j; ++k) {
    const float c = cost_[l + k - 1] + cost_[r + (j - k) - 1];
    if (c < best) best = c, best_k = k;
  }
  return best;
}

int SahCollapse::children(uint32_t b, uint32_t* kids) const {
  // The wide node of b spreads its `width` slots over its two children as planned.
  int k = 1;
  distribute(b, width_, k);
  int n = 0;
  expand(bin_[b].index, k, kids, n);
  expand(bin_[b].index + 1, width_ - k, kids, n);
  return n;
}

double SahCollapse::cost() const {
  if (cost_.empty()) return 0.0;
  return double(root_cost_) / double(bin_[0].bounds().surface_area());
}

}  // namespace penumbra
