#pragma once
/// Text forms of statistics for the CLI.
#include <string>

#include "penumbra/accel/accelerator.h"

namespace penumbra::app {

/// "nodes 123, leaves 62, depth 9, 3.1 prims/leaf, 192 refs, 4.0 KiB" plus extra figures.
std::string format_accel_stats(const AccelStats& s);

/// Bytes as "512 B", "4.0 KiB", "12.3 MiB".
std::string format_bytes(size_t bytes);

}  // namespace penumbra::app
