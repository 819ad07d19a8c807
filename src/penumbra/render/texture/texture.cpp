#include "penumbra/render/texture/texture.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "penumbra/render/surface_interaction.h"

namespace penumbra {

namespace {

/// Parity of the integer cell index floor(x) (0 even, 1 odd), exact for |x| < 2^31.
int cell_parity(float x) {
  return static_cast<int>(static_cast<int64_t>(std::floor(x)) & 1);
}

/// Pixel index i of an axis of n pixels under `wrap`, or -1 for black.
int wrap_index(int64_t i, int n, Texture::Wrap wrap) {
  switch (wrap) {
    case Texture::Wrap::kRepeat:
      return int((i % n + n) % n);
    case Texture::Wrap::kClamp:
      return int(std::clamp<int64_t>(i, 0, n - 1));
    case Texture::Wrap::kBlack:
      return i >= 0 && i < n ? int(i) : -1;
    case Texture::Wrap::kMirror: {
      // Copy k = floor(i / n) is mirrored when odd: reduce modulo 2n, then reflect the second half.
      const int64_t m = (i % (2 * int64_t{n}) + 2 * int64_t{n}) % (2 * int64_t{n});
      return int(m < n ? m : 2 * int64_t{n} - 1 - m);
    }
  }
  return -1;
}

}  // namespace

Texture Texture::constant(Rgb c) {
  Texture t;
  t.kind_ = Kind::kConstant;
  t.c0_ = c;
  return t;
}

Texture Texture::checkerboard(Vec2 scale, Rgb even, Rgb odd) {
  Texture t;
  t.kind_ = Kind::kCheckerboard;
  t.scale_ = {scale.x, scale.y, 0.0f};
  t.c0_ = even;
  t.c1_ = odd;
  return t;
}

Texture Texture::checkerboard_3d(float scale, Rgb even, Rgb odd) {
  Texture t;
  t.kind_ = Kind::kCheckerboard3d;
  t.scale_ = {scale, scale, scale};
  t.c0_ = even;
  t.c1_ = odd;
  return t;
}

Texture Texture::zone_plate(float k, Vec2 center, Rgb c0, Rgb c1) {
  Texture t;
  t.kind_ = Kind::kZonePlate;
  t.k_ = k;
  t.center_ = center;
  t.c0_ = c0;
  t.c1_ = c1;
  return t;
}

Texture Texture::image(std::shared_ptr<const RgbImage> image, Vec2 scale, Vec2 offset, Wrap wrap) {
  return Texture::image(std::move(image), scale, offset, wrap, wrap, Rgb(1.0f));
}

Texture Texture::image(std::shared_ptr<const RgbImage> image, Vec2 scale, Vec2 offset, Wrap wrap_s,
                       Wrap wrap_t, Rgb factor) {
  Texture t;
  t.kind_ = Kind::kImage;
  t.image_ = std::move(image);
  t.scale_ = {scale.x, scale.y, 0.0f};
  t.center_ = offset;
  t.wrap_s_ = wrap_s;
  t.wrap_t_ = wrap_t;
  t.c0_ = factor;
  return t;
}

Rgb Texture::texel(int64_t x, int64_t y) const {
  const int ix = wrap_index(x, image_->width(), wrap_s_);
  const int iy = wrap_index(y, image_->height(), wrap_t_);
  if (ix < 0 || iy < 0) return Rgb(0.0f);
  return image_->at(ix, iy);
}

double Texture::zone_plate_intensity(double k, double r2) {
  return 0.5 * (1.0 + std::cos(k * r2));
}

Rgb Texture::eval(const TextureQuery& q) const {
  switch (kind_) {
    case Kind::kConstant:
      return c0_;
    case Kind::kCheckerboard: {
      const int parity = cell_parity(q.uv.x * scale_.x) ^ cell_parity(q.uv.y * scale_.y);
      return parity ? c1_ : c0_;
    }
    case Kind::kCheckerboard3d: {
      const int parity = cell_parity(q.p.x * scale_.x) ^ cell_parity(q.p.y * scale_.y) ^
                         cell_parity(q.p.z * scale_.z);
      return parity ? c1_ : c0_;
    }
    case Kind::kZonePlate: {
      // The phase k r^2 reaches thousands of radians: computed in double so that it stays exact
      // to float rounding of uv.
      const double du = double(q.uv.x) - center_.x, dv = double(q.uv.y) - center_.y;
      const auto a = static_cast<float>(zone_plate_intensity(k_, du * du + dv * dv));
      return c0_ + (c1_ - c0_) * a;
    }
    case Kind::kImage: {
      // Pixel coordinates of (s, t), with t = 1 at the top row; bilinear between centres. The
      // floor is taken in double so that huge uv (a repeat far from the origin) stays exact.
      const double s = double(q.uv.x) * scale_.x + center_.x;
      const double t = double(q.uv.y) * scale_.y + center_.y;
      const double x = s * image_->width() - 0.5, y = (1.0 - t) * image_->height() - 0.5;
      if (!std::isfinite(x) || !std::isfinite(y) || std::fabs(x) > 1e9 || std::fabs(y) > 1e9)
        return Rgb(0.0f);
      // |x|, |y| <= 1e9: the int64 pixel indices and their wrapping cannot overflow.
      const double fx = std::floor(x), fy = std::floor(y);
      const auto x0 = static_cast<int64_t>(fx), y0 = static_cast<int64_t>(fy);
      const auto tx = float(x - fx), ty = float(y - fy);
      const Rgb top = texel(x0, y0) + (texel(x0 + 1, y0) - texel(x0, y0)) * tx;
      const Rgb bottom = texel(x0, y0 + 1) + (texel(x0 + 1, y0 + 1) - texel(x0, y0 + 1)) * tx;
      return (top + (bottom - top) * ty) * c0_;
    }
  }
  return c0_;
}

Rgb Texture::eval(const SurfaceInteraction& si) const {
  return eval(TextureQuery{si.p, si.uv});
}

}  // namespace penumbra
