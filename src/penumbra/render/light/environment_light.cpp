#include "penumbra/render/light/environment_light.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <utility>

#include "penumbra/core/error.h"
#include "penumbra/image/image_io.h"
#include "penumbra/render/sampling.h"
#include "penumbra/render/sampling/equal_area.h"
#include "penumbra/scene/json_value.h"
#include "penumbra/scene/transform_parser.h"

namespace penumbra {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr double kPiD = std::numbers::pi;

// The map named by "map" (empty when absent), checked: an existing .exr or .pfm file with finite
// pixels.
RgbImage read_map(const SceneParams& params) {
  const bool present = params.has("map");
  const std::string path = params.get_string("map", "");
  if (!present) return {};
  if (path.empty()) params.fail("map", "must not be empty");
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".exr" && ext != ".pfm")
    params.fail("map", "an environment map must be an .exr or .pfm image, got \"" + path + "\"");
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) params.fail("map", "environment map not found: " + path);
  if (!std::filesystem::is_regular_file(path, ec))
    params.fail("map", "not a regular file: " + path);
  RgbImage map;
  try {
    map = read_image(path);
  } catch (const Error& e) {
    params.fail("map", std::string("cannot read the environment map: ") + e.what());
  }
  if (map.empty()) params.fail("map", "environment map has no pixels: " + path);
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) {
      const Rgb c = map.at(x, y);
      if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b))
        params.fail("map", path + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                               ") is not finite");
    }
  return map;
}

// The optional "transform", which must be a rotation (or a mirroring).
Transform read_rotation(const SceneParams& params) {
  const nlohmann::json* ops = params.get_json("transform");
  if (!ops) return {};
  const JsonPlace place = JsonPlace{params.file(), params.path()}.key("transform");
  const Transform t = parse_transform(*ops, place);
  const auto& m = t.matrix().m;
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0)
    place.fail(
        "an environment's transform must be a rotation; a translation has no meaning for "
        "light from infinitely far away");
  const double len = std::sqrt(m[0][0] * m[0][0] + m[1][0] * m[1][0] + m[2][0] * m[2][0]);
  if (!is_similarity(t) || std::fabs(len - 1.0) > 1e-5)
    place.fail("an environment's transform must be a rotation; it scales or shears");
  return t;
}

}  // namespace

EnvironmentLight::EnvironmentLight(RgbImage map, Rgb scale, const Transform& to_world,
                                   bool octahedral)
    : map_(std::move(map)),
      scale_(scale),
      to_world_(to_world),
      to_map_(to_world.inverted()),
      octahedral_(octahedral) {
  build();
}

EnvironmentLight::EnvironmentLight(const SceneParams& params) {
  scale_ = params.get_rgb("radiance", Rgb(1.0f));
  for (int c = 0; c < 3; ++c)
    if (!(scale_[c] >= 0.0f && std::isfinite(scale_[c])))
      params.fail("radiance", "must be finite and non-negative");
  map_ = read_map(params);
  const std::string mapping = params.get_string("mapping", "equirectangular");
  if (mapping == "octahedral")
    octahedral_ = true;
  else if (mapping != "equirectangular")
    params.fail("mapping",
                "unknown mapping \"" + mapping + "\" (valid: equirectangular, octahedral)");
  if (octahedral_ && !map_.empty() && map_.width() != map_.height())
    params.fail("map", "an octahedral map must be square, got " + std::to_string(map_.width()) +
                           " x " + std::to_string(map_.height()));
  to_world_ = read_rotation(params);
  to_map_ = to_world_.inverted();
  params.check_all_used();
  build();
}

void EnvironmentLight::build() {
  if (map_.empty()) map_ = RgbImage(1, 1, Rgb(1.0f));
  constant_ = map_.width() == 1 && map_.height() == 1;
  const int w = map_.width(), h = map_.height();
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (int k = 0; k < 3; ++k) map_.at(i, j)[k] = std::fmax(map_.at(i, j)[k], 0.0f);
  if (octahedral_) {
    std::vector<float> weights;
    build_octahedral(weights);
    distribution_ = Distribution2D(weights, w, h);
    return;
  }

  // Row boundaries in cos(theta), from the zenith (+1) down to the nadir (-1).
  row_z_.resize(h + 1);
  for (int j = 0; j <= h; ++j) row_z_[j] = std::cos(kPiD * j / h);
  row_z_[0] = 1.0, row_z_[h] = -1.0;

  // The exact integral of the bilinear Le over each pixel's patch of the sphere. Across columns
  // (uniform in phi) the footprint average of the interpolant weighs the neighbours 1/8, 3/4,
  // 1/8; across rows, the hat functions are integrated against dz = sin(theta) dtheta in closed
  // form: f(v0, v1, a) = integral over [v0, v1] (in pixel rows) of (v - a) dz, g = that of dz.
  const double c = kPiD / h;
  const auto p = [c](double v, double a) {
    return -(v - a) * std::cos(c * v) + std::sin(c * v) / c;
  };
  const auto f = [&p](double v0, double v1, double a) { return p(v1, a) - p(v0, a); };
  const auto g = [c](double v0, double v1) { return std::cos(c * v0) - std::cos(c * v1); };
  constexpr double kColumn[3] = {0.125, 0.75, 0.125};
  std::vector<float> weights(static_cast<size_t>(w) * h);
  row_factor_.resize(h);
  double sum[3] = {0, 0, 0};
  for (int j = 0; j < h; ++j) {
    row_factor_[j] = static_cast<float>(1.0 / (2.0 * kPiD * h * (row_z_[j] - row_z_[j + 1])));
    // Upper half [j, j + 1/2) blends rows j - 1 and j, the lower half rows j and j + 1.
    const double up_self = f(j, j + 0.5, j - 0.5), down_next = f(j + 0.5, j + 1.0, j + 0.5);
    const double row_weight[3] = {g(j, j + 0.5) - up_self,
                                  up_self + g(j + 0.5, j + 1.0) - down_next, down_next};
    const int rows[3] = {std::max(j - 1, 0), j, std::min(j + 1, h - 1)};  // clamped at the poles
    for (int i = 0; i < w; ++i) {
      const int cols[3] = {(i + w - 1) % w, i, (i + 1) % w};  // wrapping around in phi
      double e[3] = {0, 0, 0};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const Rgb px = map_.at(cols[b], rows[a]);
          const double weight = 2.0 * kPiD / w * row_weight[a] * kColumn[b];
          for (int k = 0; k < 3; ++k) e[k] += weight * scale_[k] * px[k];
        }
      weights[static_cast<size_t>(j) * w + i] =
          static_cast<float>(Rgb(float(e[0]), float(e[1]), float(e[2])).luminance());
      for (int k = 0; k < 3; ++k) sum[k] += e[k];
    }
  }
  integral_ = Rgb(float(sum[0]), float(sum[1]), float(sum[2]));
  distribution_ = Distribution2D(weights, w, h);
}

void EnvironmentLight::build_octahedral(std::vector<float>& weights) {
  // Every pixel covers the solid angle 4 pi / (W H); the integral of the bilinear interpolant
  // over a pixel weighs its neighbours (across the folded edges) 1/8, 3/4, 1/8 along each axis.
  const int w = map_.width(), h = map_.height();
  const double solid_angle = 4.0 * kPiD / (double(w) * h);
  constexpr double kTap[3] = {0.125, 0.75, 0.125};
  weights.assign(static_cast<size_t>(w) * h, 0.0f);
  double sum[3] = {0, 0, 0};
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      double e[3] = {0, 0, 0};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const Rgb px = texel(i + b - 1, j + a - 1);
          const double weight = solid_angle * kTap[a] * kTap[b];
          for (int k = 0; k < 3; ++k) e[k] += weight * scale_[k] * px[k];
        }
      weights[static_cast<size_t>(j) * w + i] =
          static_cast<float>(Rgb(float(e[0]), float(e[1]), float(e[2])).luminance());
      for (int k = 0; k < 3; ++k) sum[k] += e[k];
    }
  integral_ = Rgb(float(sum[0]), float(sum[1]), float(sum[2]));
}

Rgb EnvironmentLight::texel(int x, int y) const {
  equal_area_wrap(x, y, map_.width(), map_.height());
  return map_.at(x, y);
}

void EnvironmentLight::preprocess(const Bounds3& b) {
  bounding_sphere(b, center_, radius_);
  radius_ = std::fmax(radius_, 1e-3f);  // an empty scene still gets a finite disc
}

Vec2 EnvironmentLight::uv_of(Vec3 w) const {
  if (octahedral_) return equal_area_sphere_to_square(w);
  return {0.5f + std::atan2(w.x, -w.z) * (0.5f / kPi),
          std::acos(std::clamp(w.y, -1.0f, 1.0f)) / kPi};
}

EnvironmentLight::Pixel EnvironmentLight::pixel_of(Vec2 uv) const {
  const int w = map_.width(), h = map_.height();
  return {std::clamp(static_cast<int>(uv.x * w), 0, w - 1),
          std::clamp(static_cast<int>(uv.y * h), 0, h - 1)};
}

Rgb EnvironmentLight::lookup(Vec2 uv) const {
  // Bilinear between pixel centres, wrapping around in u and clamped at the poles; a + t (b - a)
  // keeps a constant map exactly constant.
  const int w = map_.width(), h = map_.height();
  const float x = uv.x * w - 0.5f, y = uv.y * h - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  if (octahedral_) {  // neighbours across the folded edges
    const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
    const Rgb p00 = texel(ix, iy), p10 = texel(ix + 1, iy);
    const Rgb p01 = texel(ix, iy + 1), p11 = texel(ix + 1, iy + 1);
    const Rgb top = p00 + (p10 - p00) * tx, bottom = p01 + (p11 - p01) * tx;
    return scale_ * (top + (bottom - top) * ty);
  }
  const int x0 = (static_cast<int>(fx) % w + w) % w, x1 = x0 + 1 == w ? 0 : x0 + 1;
  const int y0 = std::clamp(static_cast<int>(fy), 0, h - 1);
  const int y1 = std::clamp(static_cast<int>(fy) + 1, 0, h - 1);
  const Rgb top = map_.at(x0, y0) + (map_.at(x1, y0) - map_.at(x0, y0)) * tx;
  const Rgb bottom = map_.at(x0, y1) + (map_.at(x1, y1) - map_.at(x0, y1)) * tx;
  return scale_ * (top + (bottom - top) * ty);
}

Vec3 EnvironmentLight::direction_of(const Sample2D& s) const {
  // Equal area: uniform in the square within the pixel is uniform in solid angle.
  if (octahedral_) return normalize(to_world_.vector(equal_area_square_to_sphere(s.p)));
  // Uniform in cos(theta) within the row (so uniform in solid angle within the pixel).
  const float t = std::clamp(s.p.y * map_.height() - s.y, 0.0f, 1.0f);
  const double z = row_z_[s.y] + t * (row_z_[s.y + 1] - row_z_[s.y]);
  const double sin_theta = std::sqrt(std::fmax(0.0, (1.0 - z) * (1.0 + z)));
  const double phi = 2.0 * kPiD * (s.p.x - 0.5);
  const Vec3 local(float(sin_theta * std::sin(phi)), float(z), float(-sin_theta * std::cos(phi)));
  return normalize(to_world_.vector(local));
}

float EnvironmentLight::pdf_of(Pixel px) const {
  if (octahedral_) return distribution_.cell_pdf(px.x, px.y) * (0.25f / kPi);
  return distribution_.cell_pdf(px.x, px.y) * row_factor_[px.y];
}

Vec3 EnvironmentLight::to_map(Vec3 d) const {
  return normalize(to_map_.vector(d));
}

LightSample EnvironmentLight::sample_li(Vec3, Vec2 u) const {
  LightSample ls;
  ls.wi = direction_of(distribution_.sample(u));
  ls.distance = kInfinity;
  // A constant map: its one pixel's density and radiance, as pdf_li and le give them without
  // the direction's lookup (an atan2 and an acos: 2.5 % of a 1M-triangle scene's render under a
  // constant sky).
  if (constant_) {
    ls.pdf = pdf_of({0, 0});
    if (ls.pdf > 0.0f) ls.li = scale_ * map_.at(0, 0);
    return ls;
  }
  // Radiance and density from the direction itself, exactly as le and pdf_li compute them.
  const Vec2 uv = uv_of(to_map(ls.wi));
  ls.pdf = pdf_of(pixel_of(uv));
  if (ls.pdf > 0.0f) ls.li = lookup(uv);
  return ls;
}

float EnvironmentLight::pdf_li(Vec3, Vec3 wi, const LightPoint&) const {
  // A constant map: its one pixel, the whole sphere, without the direction's lookup.
  if (constant_) return pdf_of({0, 0});
  return pdf_of(pixel_of(uv_of(to_map(wi))));
}

Rgb EnvironmentLight::le(const Ray& ray) const {
  if (constant_) return scale_ * map_.at(0, 0);
  return lookup(uv_of(to_map(ray.d)));
}

LightLeSample EnvironmentLight::sample_le(Vec2 u_pos, Vec2 u_dir, float time) const {
  LightLeSample s;
  const Vec3 w = direction_of(distribution_.sample(u_dir));  // the direction light arrives from
  const Vec2 uv = uv_of(to_map(w));
  s.pdf_dir = pdf_of(pixel_of(uv));
  if (!(s.pdf_dir > 0.0f)) return s;
  s.ray.o = sample_disc_origin(center_, radius_, w, u_pos);
  s.ray.d = -w;
  s.ray.time = time;
  s.l = lookup(uv);
  s.pdf_pos = 1.0f / (kPi * radius_ * radius_);
  return s;
}

void EnvironmentLight::pdf_le(const Ray& ray, Vec3, float& pdf_pos, float& pdf_dir) const {
  pdf_pos = 1.0f / (kPi * radius_ * radius_);
  pdf_dir = pdf_li({}, -ray.d, {});
}

Rgb EnvironmentLight::power() const {
  // Radiance from every direction crossing the bounding sphere's disc: pi r^2 * integral of Le.
  return integral_ * (kPi * radius_ * radius_);
}

}  // namespace penumbra
