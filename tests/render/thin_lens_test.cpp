#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "penumbra/core/error.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

/// Diameter in pixels of the blur disc, from the image's radial second moment: a uniform disc of
/// diameter D has E[r^2] = D^2 / 8; convolving with the sphere's own image (a disc of diameter d)
/// adds d^2 / 8 and the pixel box adds 1/6 (1/12 per axis). Averaging over all pixels makes this
/// far less noisy than locating the disc's edge.
double blur_diameter(const RgbImage& img, double d) {
  double sum = 0, sx = 0, sy = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const double v = img.at(x, y).g;
      sum += v, sx += v * (x + 0.5), sy += v * (y + 0.5);
    }
  const double cx = sx / sum, cy = sy / sum;
  double r2 = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
      r2 += img.at(x, y).g * (dx * dx + dy * dy);
    }
  return std::sqrt(std::max(0.0, 8.0 * (r2 / sum - 1.0 / 6.0) - d * d));
}

/// A tiny emissive sphere at depth z seen by a thin lens focused at 10 (128 x 128, vfov 20).
RgbImage render_point(float z, float aperture) {
  const std::string json = R"({
    "camera": {"type": "thin_lens", "position": [0, 0, 0], "look_at": [0, 0, 1], "vfov": 20,
               "aperture_radius": )" +
                           std::to_string(aperture) + R"(, "focus_distance": 10},
    "render": {"resolution": [128, 128], "spp": 256, "sampler": "sobol",
               "integrator": "raycast:mode=albedo"},
    "materials": {"m": {"type": "diffuse", "albedo": 0}},
    "shapes": [{"type": "sphere", "center": [0, 0, )" +
                           std::to_string(z) + R"(],
                "radius": 0.01, "material": "m", "emission": 1}]})";
  return test::render_desc(test::scene_from_text(json));
}

// A point off the focal plane images as a disc of the thin-lens circle of confusion:
// diameter = aperture |1/z - 1/focus| H / tan(vfov / 2).
TEST(ThinLensCamera, DefocusedPointImagesAsTheCircleOfConfusion) {
  const double tan_half = std::tan(10.0 * std::numbers::pi / 180.0);
  for (float z : {5.0f, 4.0f}) {
    const double expected = 0.2 * std::fabs(1.0 / z - 1.0 / 10.0) * 128 / tan_half;
    const double sphere = 2 * 0.01 / z * 64 / tan_half;  // the sphere's own image diameter
    EXPECT_NEAR(blur_diameter(render_point(z, 0.2f), sphere), expected, 1.0) << "z = " << z;
  }
}

// On the focal plane the lens changes nothing: the sphere is as sharp as through a pinhole.
TEST(ThinLensCamera, PointsOnTheFocalPlaneAreSharp) {
  // The sphere's image (0.73 px across) falls on the corner of four pixels at the image centre:
  // all its energy stays within those pixels, as with a pinhole.
  const RgbImage img = render_point(10.0f, 0.2f);
  double total = 0, centre = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      total += img.at(x, y).g;
      if (x >= 63 && x <= 64 && y >= 63 && y <= 64) centre += img.at(x, y).g;
    }
  EXPECT_GT(total, 0.0);
  EXPECT_GT(centre, 0.999 * total);
}

TEST(ThinLensCamera, FocusDistanceIsRequiredAndPositive) {
  const auto missing = test::scene_from_text(R"({
    "camera": {"type": "thin_lens", "position": [0, 0, 0], "look_at": [0, 0, 1],
               "aperture_radius": 0.1}, "shapes": []})");
  EXPECT_THROW(make_camera(missing.camera, 4, 4), InputError);
  const auto negative = test::scene_from_text(R"({
    "camera": {"type": "thin_lens", "position": [0, 0, 0], "look_at": [0, 0, 1],
               "focus_distance": -2}, "shapes": []})");
  EXPECT_THROW(make_camera(negative.camera, 4, 4), InputError);
  const auto typo = test::scene_from_text(R"({
    "camera": {"type": "thin_lens", "position": [0, 0, 0], "look_at": [0, 0, 1],
               "focus_distance": 2, "apperture_radius": 1}, "shapes": []})");
  EXPECT_THROW(make_camera(typo.camera, 4, 4), InputError);
}

}  // namespace
}  // namespace penumbra
