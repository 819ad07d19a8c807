#pragma once
/// Progress display on stderr: a redrawn bar with elapsed time and ETA on a terminal, plain
/// periodic lines otherwise (logs, CI).
#include <cstddef>
#include <mutex>
#include <string>

#include "penumbra/core/timer.h"

namespace penumbra::app {

/// Thread-safe progress reporter for a known amount of work.
class Progress {
 public:
  /// `label` prefixes every line; `total` units of work.
  Progress(std::string label, size_t total);
  /// Reports that `done` units are finished (calls from several threads may overlap).
  void update(size_t done);
  /// Ends the display (a final newline on a terminal).
  void finish();

 private:
  std::string label_;
  size_t total_;
  bool tty_;
  Timer timer_;
  std::mutex mutex_;
  double last_print_s_ = -1.0;
  size_t last_done_ = 0;
};

/// "1m 23s"-style duration.
std::string format_duration(double seconds);

}  // namespace penumbra::app
