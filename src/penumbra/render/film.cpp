#include "penumbra/render/film.h"

namespace penumbra {

Film::Film(int width, int height)
    : width_(width), height_(height), pixels_(size_t(width) * size_t(height)) {}

void Film::add_sample(int x, int y, Rgb l, float weight) {
  Pixel& p = pixels_[size_t(y) * size_t(width_) + size_t(x)];
  p.r += double(l.r) * weight;
  p.g += double(l.g) * weight;
  p.b += double(l.b) * weight;
  p.weight += weight;
}

RgbImage Film::resolve() const {
  RgbImage image(width_, height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const Pixel& p = pixels_[size_t(y) * size_t(width_) + size_t(x)];
      if (p.weight > 0)
        image.at(x, y) = {float(p.r / p.weight), float(p.g / p.weight), float(p.b / p.weight)};
    }
  return image;
}

}  // namespace penumbra
