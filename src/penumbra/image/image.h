#pragma once
/// A 2D array of pixels: width x height values stored row by row, row 0 at the top of the picture.
#include <cassert>
#include <cstddef>
#include <string>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/core/error.h"

namespace penumbra {

/// Largest pixel count an image file may declare (2^28); readers reject larger headers before
/// allocating anything.
inline constexpr std::size_t kMaxImagePixels = std::size_t{1} << 28;

/// A width x height grid of T in flat row-major storage; row 0 is the top row, x grows to the
/// right.
template <class T>
class Image {
 public:
  /// An empty 0 x 0 image.
  Image() = default;
  /// A width x height image with every pixel set to value.
  Image(int width, int height, const T& value = T{}) { resize(width, height, value); }

  /// Number of columns.
  int width() const { return width_; }
  /// Number of rows.
  int height() const { return height_; }
  /// Number of pixels, width * height.
  std::size_t size() const { return pixels_.size(); }
  /// True when the image has no pixels.
  bool empty() const { return pixels_.empty(); }

  /// The pixel in column x of row y (row 0 is the top); unchecked in release builds.
  T& at(int x, int y) {
    assert(x >= 0 && x < width_ && y >= 0 && y < height_);
    return pixels_[static_cast<std::size_t>(y) * width_ + x];
  }
  /// The pixel in column x of row y (row 0 is the top); unchecked in release builds.
  const T& at(int x, int y) const {
    assert(x >= 0 && x < width_ && y >= 0 && y < height_);
    return pixels_[static_cast<std::size_t>(y) * width_ + x];
  }

  /// First pixel of row y; the row's width() pixels follow contiguously.
  T* row(int y) { return pixels_.data() + static_cast<std::size_t>(y) * width_; }
  /// First pixel of row y; the row's width() pixels follow contiguously.
  const T* row(int y) const { return pixels_.data() + static_cast<std::size_t>(y) * width_; }

  /// All pixels, row 0 first.
  T* data() { return pixels_.data(); }
  /// All pixels, row 0 first.
  const T* data() const { return pixels_.data(); }

  /// Changes the size to width x height and sets every pixel to value (old contents are lost).
  void resize(int width, int height, const T& value = T{}) {
    if (width < 0 || height < 0) {
      throw Error("image size " + std::to_string(width) + " x " + std::to_string(height) +
                  " is negative");
    }
    width_ = width;
    height_ = height;
    pixels_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), value);
  }

  /// Sets every pixel to value.
  void fill(const T& value) { pixels_.assign(pixels_.size(), value); }

  /// True when both images have the same size and the same pixels.
  bool operator==(const Image&) const = default;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> pixels_;
};

/// A linear-RGB image, the renderer's output.
using RgbImage = Image<Rgb>;

}  // namespace penumbra
