#pragma once
/// How to run a render, how it reports progress, and what it did.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

namespace penumbra {

class Film;

/// Where a render stands, reported while it runs.
struct RenderProgress {
  int spp_done = 0;      ///< samples per pixel finished in every pixel
  int spp_target = 0;    ///< samples per pixel asked for
  double fraction = 0;   ///< of the samples asked for, done (counting the current pass's tiles)
  double elapsed_s = 0;  ///< since the first pass started
  uint64_t rays = 0;     ///< rays traced in finished tiles
  double mean_rel_error = -1;  ///< the image's mean relative standard error, when measured
};

/// Why a render stopped.
enum class StopReason : uint8_t { kComplete, kTimeLimit, kTargetError, kCancelled };

/// How to run a render and how to report on it.
struct RenderOptions {
  int tile_size = 16;
  /// Stop before a pass that would end after this many seconds (0: no limit).
  double time_limit_s = 0;
  /// Stop once the image's mean relative standard error falls below this (0: never).
  double target_error = 0;
  /// Samples per pixel of every pass; 0 chooses them: 1, 2, 4, ... while a pass stays under
  /// about a second, so checkpoints, time limits and progress keep their pace.
  int pass_spp = 0;
  /// Call on_checkpoint with the film after the first pass that ends this many seconds after the
  /// previous checkpoint (0: never).
  double checkpoint_s = 0;
  std::function<void(const Film&, int spp_done)> on_checkpoint;
  /// Called after each finished tile, from worker threads (calls may overlap: the callee
  /// synchronises).
  std::function<void(const RenderProgress&)> on_progress;
  /// Called by an integrator's preprocessing step with what it does and how far it is (0..1).
  std::function<void(const char* what, double fraction)> on_preprocess;
  /// Called with a warning about the render (a material an integrator cannot represent, ...).
  std::function<void(const std::string& message)> on_warning;
  /// When set and true, no further tiles are started; finished tiles are kept.
  const std::atomic<bool>* cancel = nullptr;
};

/// What a render did.
struct RenderStats {
  uint64_t camera_rays = 0;
  uint64_t rays = 0;   ///< every ray traced: camera, secondary and shadow
  double seconds = 0;  ///< the passes
  double preprocess_seconds = 0;
  int spp_done = 0;  ///< samples per pixel that every pixel has
  int spp_target = 0;
  int passes = 0;
  size_t tiles_done = 0, tiles_total = 0;  ///< of the last pass (fewer when it was cancelled)
  StopReason stop = StopReason::kComplete;
  /// Of the worker threads' time in tiles, the share spent in ray traversal and intersection.
  double traversal_share = 0;
  double mean_rel_error = -1;  ///< measured when a target error was set
  /// A line the integrator adds to the render's summary (the cost view's colour scale), or empty.
  std::string note;
  /// True unless the render was cancelled (a time limit or an error target is a normal end).
  bool complete() const { return stop != StopReason::kCancelled; }
};

}  // namespace penumbra
