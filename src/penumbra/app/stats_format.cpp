#include "penumbra/app/stats_format.h"

#include <fmt/format.h>

namespace penumbra::app {

std::string format_bytes(size_t bytes) {
  if (bytes < 1024) return fmt::format("{} B", bytes);
  if (bytes < 1024 * 1024) return fmt::format("{:.1f} KiB", double(bytes) / 1024.0);
  return fmt::format("{:.1f} MiB", double(bytes) / (1024.0 * 1024.0));
}

std::string format_accel_stats(const AccelStats& s) {
  std::string text = fmt::format("nodes {}, leaves {}, depth {}, {:.2f} prims/leaf, {} refs, {}",
                                 s.nodes, s.leaves, s.max_depth, s.mean_prims_per_leaf(),
                                 s.prim_refs, format_bytes(s.bytes));
  for (const auto& [key, value] : s.extra) text += fmt::format(", {} {:g}", key, value);
  return text;
}

}  // namespace penumbra::app
