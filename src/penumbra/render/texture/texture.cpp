#include "penumbra/render/texture/texture.h"

#include <cmath>

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
  }
  return c0_;
}

Rgb Texture::eval(const SurfaceInteraction& si) const {
  return eval(TextureQuery{si.p, si.uv});
}

}  // namespace penumbra
