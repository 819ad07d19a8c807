#pragma once
/// Progress display on stderr: a redrawn bar with elapsed time and ETA on a terminal, plain
/// periodic lines otherwise (logs, CI).
#include <cstddef>
#include <mutex>
#include <string>

#include "penumbra/core/timer.h"
#include "penumbra/render/render_stats.h"

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

/// The progress line of a render: samples per pixel done, elapsed time, ETA and Mrays/s;
/// redrawn on a terminal, a line every 5 seconds otherwise.
class RenderProgressLine {
 public:
  RenderProgressLine();
  /// Reports render progress (calls from several threads may overlap).
  void update(const RenderProgress& p);
  /// Reports preprocessing progress.
  void preprocess(const char* what, double fraction);
  /// Ends the display (a final newline on a terminal).
  void finish();

 private:
  void print(const std::string& text, bool force);

  bool tty_;
  std::mutex mutex_;
  Timer timer_;
  double last_print_s_ = -1.0;
  double last_fraction_ = -1.0;
  bool printed_ = false;
};

/// "1m 23s"-style duration.
std::string format_duration(double seconds);

}  // namespace penumbra::app
