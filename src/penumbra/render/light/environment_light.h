#pragma once
/// An environment map: radiance from every direction, read from an equirectangular HDR image
/// and importance-sampled by luminance (pbrt-v4's ImageInfiniteLight, on a latitude-longitude map).
#include <vector>

#include "penumbra/core/transform.h"
#include "penumbra/image/image.h"
#include "penumbra/render/light/light.h"
#include "penumbra/render/sampling/distribution_2d.h"
#include "penumbra/scene/scene_params.h"

namespace penumbra {

/// Light of type "environment": Le(w) = radiance * map(w), arriving from every direction.
///
/// Parameters:
/// - radiance: RGB scale (a number s means (s, s, s)), default 1, finite and non-negative.
/// - map: optional path of an equirectangular .exr or .pfm image (relative paths are resolved
///   against the scene file's folder by the scene loader). Without it the map is constant 1 and
///   the light is a constant environment (the scene's background is one): le and pdf_li then
///   return the radiance and 1 / (4 pi) without a lookup. Negative pixel values are read as 0; NaN
///   or infinite pixels are an error.
/// - mapping: the layout of the map, "equirectangular" (default; below) or "octahedral": pbrt-v4's
///   equal-area octahedral square (render/sampling/equal_area.h; Clarberg 2008), whose centre
///   pixel looks along the map frame's +z and whose four corners along -z. An octahedral map
///   must be square.
/// - transform: optional map-to-world rotation, in the syntax of shapes' "transform" (for example
///   [{"rotate": {"axis": [0, 1, 0], "angle": 90}}]); only rotations (and mirrorings) are
///   accepted: no scale, shear or translation.
///
/// Map orientation, in the map's frame (the world frame when there is no transform): +y is up.
/// Row 0 (the image's top) is the zenith +y, the bottom row the nadir -y; the image's centre
/// column looks along -z, the column at u = 0.75 along +x and the left/right edges along +z, so
/// seen from inside the sphere the image is not mirrored. For a unit direction w = (x, y, z):
///   u = 0.5 + atan2(x, -z) / (2 pi),   v = acos(y) / pi,   in pixel (floor(u W), floor(v H)),
///   w(u, v) = (sin(theta) sin(phi), cos(theta), -sin(theta) cos(phi)), theta = pi v,
///   phi = 2 pi (u - 0.5);
/// pixel (x, y) is centred on u = (x + 0.5) / W, v = (y + 0.5) / H, where Le is its value. A map
/// point (u, v) shows the world direction transform(w(u, v)).
///
/// Lookup is bilinear between pixel centres (wrapping around in u, clamped at the poles), and
/// sampling is piecewise constant (as in pbrt-v4): a pixel is chosen with probability
/// proportional to the luminance of the exact integral of Le over the pixel's patch of the sphere
/// (its solid angle (2 pi / W) (cos theta_j - cos theta_j+1) times the mean of the interpolated
/// Le there), by a Distribution2D (marginal over rows, conditional per row); the direction is
/// then uniform in solid angle within the pixel (uniform in phi and in cos theta). The density is
/// pdf = P(pixel) / solid_angle(pixel): nothing diverges at the poles, a constant map gives
/// 1 / (4 pi) everywhere, and it is positive wherever Le > 0 (every pixel whose interpolation
/// reaches a non-black pixel gets a positive weight; luminance is positive for every non-black
/// non-negative colour).
///
/// An octahedral map is looked up bilinearly with its edges folded as the mapping folds them
/// (pbrt-v4's octahedral wrap) and sampled the same way over its pixels, each of solid angle
/// 4 pi / (W H): pdf = P(pixel) W H / (4 pi), and the direction is uniform within the pixel.
///
/// Emitted rays (sample_le) take a direction from the map and an origin on the disc of the
/// scene's bounding-sphere radius r facing it, pdf_pos = 1 / (pi r^2); power() = pi r^2 times
/// the integral of Le over the sphere.
class EnvironmentLight final : public Light {
 public:
  /// A light of radiance `scale` * `map` (an empty map is constant 1) with the map-to-world
  /// rotation `to_world` (must be orthogonal; not checked here).
  EnvironmentLight(RgbImage map, Rgb scale, const Transform& to_world = {},
                   bool octahedral = false);
  /// From scene parameters; throws InputError naming the file, JSON path and problem.
  explicit EnvironmentLight(const SceneParams& params);

  LightKind kind() const override { return LightKind::kInfinite; }
  void preprocess(const Bounds3& scene_bounds) override;
  LightSample sample_li(Vec3 p, Vec2 u) const override;
  float pdf_li(Vec3 p, Vec3 wi, const LightPoint& hit) const override;
  Rgb le(const Ray& ray) const override;
  LightLeSample sample_le(Vec2 u_pos, Vec2 u_dir, float time) const override;
  void pdf_le(const Ray& ray, Vec3 n, float& pdf_pos, float& pdf_dir) const override;
  Rgb power() const override;

  /// The map (1 x 1 of value 1 for a constant environment), without the radiance scale.
  const RgbImage& map() const { return map_; }
  /// True for a map in the equal-area octahedral layout.
  bool octahedral() const { return octahedral_; }
  /// Integral of Le over the sphere of directions (W sr^-1 m^-2 integrated over solid angle).
  Rgb integral() const { return integral_; }

 private:
  /// A pixel of the map.
  struct Pixel {
    int x = 0, y = 0;
  };
  void build();
  /// The per-pixel sampling weights and integral of an octahedral map.
  void build_octahedral(std::vector<float>& weights);
  /// The pixel (x, y) of the map, where x and y may lie one pixel outside it.
  Rgb texel(int x, int y) const;
  /// Map coordinates (u, v) in [0, 1]^2 of the unit map-frame direction w.
  Vec2 uv_of(Vec3 w) const;
  /// The pixel that contains map point uv.
  Pixel pixel_of(Vec2 uv) const;
  /// Le at map point uv: the map interpolated bilinearly, times the radiance scale.
  Rgb lookup(Vec2 uv) const;
  /// A direction in the world frame (unit) and map frame from a map sample.
  Vec3 direction_of(const Sample2D& s) const;
  /// Solid-angle density of sampling the map-frame direction's pixel.
  float pdf_of(Pixel px) const;
  /// The unit map-frame direction of the world direction d.
  Vec3 to_map(Vec3 d) const;

  RgbImage map_;
  Rgb scale_;
  Transform to_world_, to_map_;
  Distribution2D distribution_;
  std::vector<double> row_z_;      ///< cos(theta) at the H + 1 row boundaries, from +1 to -1
  std::vector<float> row_factor_;  ///< per row: 1 / (2 pi H (z_j - z_j+1)), to turn a density on
                                   ///< [0, 1)^2 into one per solid angle
  Rgb integral_;
  bool octahedral_ = false;  ///< the map's layout: equal-area octahedral, else equirectangular
  bool constant_ = false;    ///< a 1 x 1 map: the same radiance from every direction
  Vec3 center_;
  float radius_ = 1;
};

}  // namespace penumbra
