#include "penumbra/app/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

#include <fmt/format.h>

namespace penumbra::app {

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  if (s < 60) return fmt::format("{:.1f}s", s);
  const auto total = static_cast<long long>(s);
  if (total < 3600) return fmt::format("{}m {:02}s", total / 60, total % 60);
  return fmt::format("{}h {:02}m", total / 3600, (total % 3600) / 60);
}

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)), total_(total), tty_(isatty(STDERR_FILENO) != 0) {}

void Progress::update(size_t done) {
  std::lock_guard lock(mutex_);
  if (done < last_done_) return;  // a late report from another thread
  last_done_ = done;
  const double t = timer_.elapsed_s();
  // A terminal redraws at most 10 times a second; a log gets a line every 5 seconds.
  const double interval = tty_ ? 0.1 : 5.0;
  if (done != total_ && t - last_print_s_ < interval) return;
  last_print_s_ = t;
  const double frac = total_ ? double(done) / double(total_) : 1.0;
  const double eta = frac > 0 ? t * (1.0 - frac) / frac : NAN;
  if (tty_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    fmt::print(stderr, "\r{} [{}{}] {:5.1f}%  elapsed {}  ETA {}   ", label_,
               std::string(size_t(filled), '#'), std::string(size_t(kWidth - filled), '.'),
               frac * 100.0, format_duration(t), format_duration(eta));
  } else {
    fmt::print(stderr, "{}: {:5.1f}% ({}/{})  elapsed {}  ETA {}\n", label_, frac * 100.0, done,
               total_, format_duration(t), format_duration(eta));
  }
  std::fflush(stderr);
}

RenderProgressLine::RenderProgressLine() : tty_(isatty(STDERR_FILENO) != 0) {}

void RenderProgressLine::print(const std::string& text, bool force) {
  const double t = timer_.elapsed_s();
  // A terminal redraws at most 10 times a second; a log gets a line every 5 seconds.
  if (!force && t - last_print_s_ < (tty_ ? 0.1 : 5.0)) return;
  last_print_s_ = t;
  printed_ = true;
  if (tty_) fmt::print(stderr, "\r{}   ", text);
  else fmt::print(stderr, "{}\n", text);
  std::fflush(stderr);
}

void RenderProgressLine::update(const RenderProgress& p) {
  std::lock_guard lock(mutex_);
  if (p.fraction < last_fraction_) return;  // a late report from another thread
  last_fraction_ = p.fraction;
  const double eta = p.fraction > 0 ? p.elapsed_s * (1.0 - p.fraction) / p.fraction : NAN;
  const double mrays = p.elapsed_s > 0 ? double(p.rays) / p.elapsed_s * 1e-6 : 0.0;
  std::string text = fmt::format("render: {:5.1f}%  {}/{} spp  elapsed {}  ETA {}  {:.2f} Mrays/s",
                                 p.fraction * 100.0, p.spp_done, p.spp_target,
                                 format_duration(p.elapsed_s), format_duration(eta), mrays);
  if (p.mean_rel_error >= 0) text += fmt::format("  error {:.4f}", p.mean_rel_error);
  print(text, p.fraction >= 1.0);
}

void RenderProgressLine::preprocess(const char* what, double fraction) {
  std::lock_guard lock(mutex_);
  print(fmt::format("{}: {:5.1f}%", what, fraction * 100.0), fraction >= 1.0);
}

void RenderProgressLine::finish() {
  std::lock_guard lock(mutex_);
  if (tty_ && printed_) fmt::print(stderr, "\n");
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (tty_) fmt::print(stderr, "\n");
}

}  // namespace penumbra::app
