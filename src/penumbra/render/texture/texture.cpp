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
  Texture t;
  t.kind_ = Kind::kImage;
  t.image_ = std::move(image);
  t.scale_ = {scale.x, scale.y, 0.0f};
  t.center_ = offset;
  t.wrap_ = wrap;
  return t;
}

Rgb Texture::texel(int x, int y) const {
  const int w = image_->width(), h = image_->height();
  if (x < 0 || x >= w || y < 0 || y >= h) {
    switch (wrap_) {
      case Wrap::kRepeat:
        x = (x % w + w) % w, y = (y % h + h) % h;
        break;
      case Wrap::kClamp:
        x = std::clamp(x, 0, w - 1), y = std::clamp(y, 0, h - 1);
        break;
      case Wrap::kBlack:
        return Rgb(0.0f);
    }
  }
  return image_->at(x, y);
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
      const double fx = std::floor(x), fy = std::floor(y);
      const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
      const int w = image_->width(), h = image_->height();
      // Reduce repeat coordinates first so that the int arithmetic of texel() cannot overflow.
      const int x0 =
          wrap_ == Wrap::kRepeat ? int((ix % w + w) % w) : int(std::clamp<int64_t>(ix, -2, w + 1));
      const int y0 =
          wrap_ == Wrap::kRepeat ? int((iy % h + h) % h) : int(std::clamp<int64_t>(iy, -2, h + 1));
      const auto tx = float(x - fx), ty = float(y - fy);
      const Rgb top = texel(x0, y0) + (texel(x0 + 1, y0) - texel(x0, y0)) * tx;
      const Rgb bottom = texel(x0, y0 + 1) + (texel(x0 + 1, y0 + 1) - texel(x0, y0 + 1)) * tx;
      return top + (bottom - top) * ty;
    }
  }
  return c0_;
}

Rgb Texture::eval(const SurfaceInteraction& si) const {
  return eval(TextureQuery{si.p, si.uv});
}

}  // namespace penumbra
