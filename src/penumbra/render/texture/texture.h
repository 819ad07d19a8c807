#pragma once
/// Textures: colours that vary over a surface, evaluated at a surface interaction. A closed set of
/// kinds behind one `switch` (no virtual call per lookup), small enough to copy by value.
#include <cstdint>
#include <memory>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"
#include "penumbra/image/image.h"

namespace penumbra {

struct SurfaceInteraction;

/// Where a texture is looked up. Filtering (a footprint from ray differentials, mip-maps) would
/// add the uv derivatives here; today a lookup is a point sample.
struct TextureQuery {
  Vec3 p;   ///< world-space position
  Vec2 uv;  ///< surface parameters (quads: along the edges; spheres: spherical; meshes: uvs or
            ///< barycentric)
};

/// An RGB texture: constant, 2D checkerboard over uv, 3D (solid) checkerboard over world position,
/// a Fresnel zone plate over uv, or an image over uv (shared, not copied, between copies).
class Texture {
 public:
  /// The kinds of texture.
  enum class Kind : uint8_t { kConstant, kCheckerboard, kCheckerboard3d, kZonePlate, kImage };
  /// What an image texture shows outside [0, 1)^2, per axis: the image repeated, its edge pixels
  /// extended, black, or the image repeated with every other copy mirrored (glTF's
  /// MIRRORED_REPEAT: pixel x of copy k is pixel W - 1 - x when k is odd).
  enum class Wrap : uint8_t { kRepeat, kClamp, kBlack, kMirror };

  /// A constant colour.
  static Texture constant(Rgb c);
  /// Checks of size 1/scale.x by 1/scale.y in uv: cell (i, j) = (floor(u sx), floor(v sy)) is
  /// `even` when i + j is even, `odd` otherwise (cells are half-open: [i, i + 1)).
  static Texture checkerboard(Vec2 scale, Rgb even, Rgb odd);
  /// Cubes of side 1/scale in world space, coloured by the parity of floor(x s) + floor(y s) +
  /// floor(z s) (a solid texture: no uv needed).
  static Texture checkerboard_3d(float scale, Rgb even, Rgb odd);
  /// The Fresnel zone plate c0 + (c1 - c0) (1 + cos(k r^2)) / 2, r = |uv - center|: the local
  /// frequency k r / pi (cycles per unit of uv) rises linearly with r.
  static Texture zone_plate(float k, Vec2 center, Rgb c0, Rgb c1);

  /// The image over uv, as pbrt-v4's image textures: (s, t) = (u su + du, v sv + dv) and the
  /// image spans [0, 1]^2 with t = 0 at its bottom row and t = 1 at its top; pixel (x, y) is
  /// centred on s = (x + 0.5) / W, t = 1 - (y + 0.5) / H; lookups are bilinear between pixel
  /// centres, with `wrap` outside the image. `image` must not be empty.
  static Texture image(std::shared_ptr<const RgbImage> image, Vec2 scale, Vec2 offset, Wrap wrap);
  /// The image texture with a wrap mode per axis (`wrap_s` along s, `wrap_t` along t), every
  /// lookup multiplied by `factor` per channel (glTF's baseColorFactor).
  static Texture image(std::shared_ptr<const RgbImage> image, Vec2 scale, Vec2 offset, Wrap wrap_s,
                       Wrap wrap_t, Rgb factor);

  /// The kind.
  Kind kind() const { return kind_; }
  /// True for a constant texture (materials then keep the exact untextured path).
  bool is_constant() const { return kind_ == Kind::kConstant; }
  /// The colour at a lookup point.
  Rgb eval(const TextureQuery& q) const;
  /// The colour at a surface interaction.
  Rgb eval(const SurfaceInteraction& si) const;

  /// Zone plate intensity (1 + cos(k r2)) / 2 for r2 = r^2, in double for reference computations.
  static double zone_plate_intensity(double k, double r2);

 private:
  Kind kind_ = Kind::kConstant;
  Rgb c0_, c1_;  ///< constant colour / even / dark colour / image factor, and odd / bright colour
  Vec3 scale_;   ///< checkerboard frequencies per axis
  Vec2 center_;  ///< zone plate centre in uv; image texture offset (du, dv)
  float k_ = 0;  ///< zone plate chirp rate
  Wrap wrap_s_ = Wrap::kRepeat, wrap_t_ = Wrap::kRepeat;  ///< image texture wrap modes
  std::shared_ptr<const RgbImage> image_;                 ///< image texture pixels (linear RGB)

  /// Image texel (x, y) after each axis's wrap mode (black: zero outside the image).
  Rgb texel(int64_t x, int64_t y) const;
};

}  // namespace penumbra
