#include "penumbra/render/film.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/core/memory_limit.h"

namespace penumbra {

namespace {

// Checked before the member vector is sized: the film is the largest allocation a scene file
// or --resolution asks for directly (65536 x 65536 pixels would be 384 GiB of accumulators).
size_t checked_pixels(int width, int height) {
  check_memory(Film::memory_bytes(width, height),
               fmt::format("the film of {} x {} pixels", width, height), "lower the resolution");
  return size_t(width) * size_t(height);
}

}  // namespace

double Film::memory_bytes(int width, int height) {
  // The accumulators, then the resolved and variance images (3 floats each) and their encoded
  // bytes when written (at most as many again).
  return double(width) * double(height) * double(sizeof(Pixel) + 4 * 3 * sizeof(float));
}

Film::Film(int width, int height)
    : width_(width), height_(height), pixels_(checked_pixels(width, height)) {}

void Film::set_pixel(int x, int y, Rgb value, uint32_t samples) {
  Pixel& p = pixels_[size_t(y) * size_t(width_) + size_t(x)];
  p = Pixel{};
  for (int c = 0; c < 3; ++c) {
    p.sum[c] = value[c];
    p.sum_w2l[c] = value[c];
    p.sum_w2l2[c] = double(value[c]) * double(value[c]);
  }
  p.weight = 1.0;
  p.sum_w2 = 1.0;
  p.count = samples;
}

RgbImage Film::resolve() const {
  RgbImage image(width_, height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Pixel& p = pixel(x, y);
      if (p.weight > 0)
        image.at(x, y) = {float(p.sum[0] / p.weight), float(p.sum[1] / p.weight),
                          float(p.sum[2] / p.weight)};
    }
  return image;
}

double Film::channel_variance(const Pixel& p, int c) {
  if (!(p.weight > 0) || p.count < 2) return 0.0;
  const double m = p.sum[c] / p.weight;
  // sum w^2 (L - m)^2 expanded; the factor n / (n - 1) corrects the bias of using m.
  const double ss = p.sum_w2l2[c] - 2.0 * m * p.sum_w2l[c] + m * m * p.sum_w2;
  const double n = double(p.count);
  return std::max(0.0, ss) / (p.weight * p.weight) * (n / (n - 1.0));
}

RgbImage Film::variance() const {
  RgbImage image(width_, height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Pixel& p = pixel(x, y);
      image.at(x, y) = {float(channel_variance(p, 0)), float(channel_variance(p, 1)),
                        float(channel_variance(p, 2))};
    }
  return image;
}

double Film::mean_relative_error() const {
  if (pixels_.empty()) return 0.0;
  constexpr double kY[3] = {0.2126, 0.7152, 0.0722};
  double mean_y = 0.0;
  for (const Pixel& p : pixels_)
    if (p.weight > 0) mean_y += (kY[0] * p.sum[0] + kY[1] * p.sum[1] + kY[2] * p.sum[2]) / p.weight;
  mean_y /= double(pixels_.size());
  const double floor = std::max(1e-3 * mean_y, 1e-12);
  double sum = 0.0;
  for (const Pixel& p : pixels_) {
    if (!(p.weight > 0)) continue;
    const double y = (kY[0] * p.sum[0] + kY[1] * p.sum[1] + kY[2] * p.sum[2]) / p.weight;
    // The luminance's variance from the channels', taking them as perfectly correlated (an
    // upper bound; radiance channels of one path are strongly correlated).
    double sd = 0.0;
    for (int c = 0; c < 3; ++c) sd += kY[c] * std::sqrt(channel_variance(p, c));
    sum += sd / std::max(y, floor);
  }
  return sum / double(pixels_.size());
}

}  // namespace penumbra
