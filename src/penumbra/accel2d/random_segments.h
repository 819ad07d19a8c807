#pragma once
/// Generated inputs for the laboratory: random disjoint segments, and an adversarial input on which
/// taking the segments in the given order makes a BSP of quadratic size.
#include <cstddef>
#include <cstdint>

#include "penumbra/accel2d/scene2d.h"

namespace penumbra::lab2d {

/// n pairwise disjoint segments in the square [0, √n]², lengths uniform in [0.25, 1] and uniform
/// directions: candidates are drawn uniformly and rejected when they meet an accepted segment,
/// found through a bucket grid of unit cells (each candidate is tested against the few segments of
/// the buckets its box covers), so expected O(n) time. Same (n, seed), same segments.
Scene2D random_segments(size_t n, uint64_t seed);

/// n disjoint segments s1..sn on tangents of the parabola y = x²/n, s_k starting at its tangent
/// point p_k = n − k and running right to (p_1 + p_k)/2: the line through s_i cuts every s_j with
/// j > i, so the first-segment order yields about n²/2 fragments; a random order, O(n log n).
Scene2D comb_segments(size_t n);

}  // namespace penumbra::lab2d
