#pragma once
/// Wall-clock timing.
#include <chrono>

namespace penumbra {

/// Measures wall time since construction (or the last reset).
class Timer {
 public:
  Timer() : start_(std::chrono::steady_clock::now()) {}
  void reset() { start_ = std::chrono::steady_clock::now(); }
  /// Milliseconds elapsed.
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  /// Seconds elapsed.
  double elapsed_s() const { return elapsed_ms() * 1e-3; }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace penumbra
