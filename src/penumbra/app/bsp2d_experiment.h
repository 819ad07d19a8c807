#pragma once
/// The fragment experiment of the 2D laboratory: 2DRANDOMBSP on n = 100 … 100,000 random disjoint
/// segments (several seeds each), against the lecture's bounds: expected O(n log n) fragments and
/// O(n log² n) expected build time; and the first-segment order on the adversarial comb, where it
/// makes Θ(n²) fragments.
#include <cstddef>
#include <string>

namespace penumbra::app {

/// Runs the experiment up to max_n with `seeds` seeds per n, prints the table, and writes the
/// plot to svg_path when it is not empty.
void run_fragment_experiment(size_t max_n, size_t seeds, const std::string& svg_path);

}  // namespace penumbra::app
