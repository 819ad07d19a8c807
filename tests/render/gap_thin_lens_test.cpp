// The thin-lens camera's ray geometry off the optical axis, checked ray by ray against the
// thin-lens model written out here: every ray of a film point meets the plane of focus where the
// pinhole ray does, starts on the lens disc, and a point off that plane spreads over the circle of
// confusion aperture |1/z - 1/focus| H / tan(vfov / 2) (diameter, pixels).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "penumbra/core/dvec3.h"
#include "penumbra/core/rng.h"
#include "render_helpers.h"

namespace penumbra {
namespace {

// Double-precision vectors for the reference (core/dvec3.h).
using D3 = DVec3;

// An oblique camera on a wide film, so that no axis or aspect mistake cancels out.
constexpr int kW = 160, kH = 90;
constexpr double kVfov = 35, kAperture = 0.25, kFocus = 7;
const D3 kEye{1, 2, -3}, kTarget{2, 1.5, 4}, kUp{0.2, 1, 0.1};

std::string camera_json(const std::string& type, const std::string& lens) {
  return R"({"camera": {"type": ")" + type +
         R"(", "position": [1, 2, -3], "look_at": [2, 1.5, 4], "up": [0.2, 1, 0.1], "vfov": 35)" +
         lens + R"(}, "shapes": []})";
}

std::unique_ptr<Camera> thin_lens(double aperture) {
  const auto desc = test::scene_from_text(
      camera_json("thin_lens", ", \"aperture_radius\": " + std::to_string(aperture) +
                                   ", \"focus_distance\": " + std::to_string(kFocus)));
  return make_camera(desc.camera, kW, kH);
}

std::unique_ptr<Camera> pinhole() {
  return make_camera(test::scene_from_text(camera_json("pinhole", "")).camera, kW, kH);
}

/// The camera frame of the documented look-at convention: forward towards the target, image
/// right = forward x up, image up completing the frame.
struct Frame {
  D3 forward = normalize(kTarget - kEye);
  D3 right = normalize(cross(forward, kUp));
  D3 up = cross(right, forward);
};

/// Where `r` meets the plane at camera depth z (distance z from the eye along forward).
D3 at_depth(const Ray& r, double z) {
  const Frame fr;
  const D3 o(r.o), d(r.d);
  const double t = (z - dot(o - kEye, fr.forward)) / dot(d, fr.forward);
  return o + d * t;
}

/// The film position (pixels) at which the pinhole of this camera images world point p.
std::pair<double, double> film_of(D3 p) {
  const Frame fr;
  const D3 v = p - kEye;
  const double t = std::tan(kVfov * std::numbers::pi / 360), a = double(kW) / kH;
  const double cx = dot(v, fr.right) / dot(v, fr.forward), cy = dot(v, fr.up) / dot(v, fr.forward);
  return {(cx / (t * a) + 1) * kW / 2, (1 - cy / t) * kH / 2};
}

/// Film points across the image, the corners and edges included, none at the centre.
std::vector<Vec2> film_points() {
  return {{0, 0},          {160, 0}, {0, 90}, {160, 90},       {13.7f, 71.2f},
          {150.25f, 8.5f}, {80, 3},  {2, 45}, {120.5f, 60.75f}};
}

/// Lens samples: a grid over [0, 1)^2 with its edges, where the disc mapping reaches the rim.
std::vector<Vec2> lens_samples() {
  std::vector<Vec2> u;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      u.push_back({std::min(i / 8.0f, 0.999999f), std::min(j / 8.0f, 0.999999f)});
  return u;
}

// Tolerance for comparing world points ~10 units from the origin reached through a float ray:
// the ray origin and direction carry a few ulps (~1e-6 relative) and the ray parameter to the
// plane multiplies that by the distance: 2e-5 absolute is some four times the largest error seen.
constexpr double kPointTol = 2e-5;

TEST(GapThinLens, EveryLensRayMeetsThePinholeRayOnThePlaneOfFocus) {
  const auto cam = thin_lens(kAperture);
  const auto pin = pinhole();
  const Frame fr;
  for (const Vec2 film : film_points()) {
    const Ray p = pin->generate_ray({film, {0.5f, 0.5f}, 0});
    // The pinhole ray's point at camera depth focus_distance.
    const D3 focus = D3(p.o) + D3(p.d) * (kFocus / dot(D3(p.d), fr.forward));
    ASSERT_LT(length(D3(p.o) - kEye), 1e-6);
    for (const Vec2 u : lens_samples()) {
      const Ray r = cam->generate_ray({film, u, 0});
      EXPECT_NEAR(length(D3(r.d)), 1.0, 1e-6);
      // Forward-going, so it reaches the plane in front of the lens.
      EXPECT_GT(dot(D3(r.d), fr.forward), 0.0);
      const D3 x = at_depth(r, kFocus);
      EXPECT_LT(length(x - focus), kPointTol)
          << "film (" << film.x << ", " << film.y << "), lens (" << u.x << ", " << u.y << ")";
    }
  }
}

// The ray origins lie on the lens disc: in the plane through the eye perpendicular to the view
// direction, within the aperture radius, reaching its rim, and uniform over its area (chi-square
// of r^2 / A^2 and of the polar angle, each in 16 equiprobable bins over 40,000 samples: 15
// degrees of freedom, quantile 44.26 at significance 1e-4).
TEST(GapThinLens, LensSamplesFillTheApertureDiscUniformly) {
  const auto cam = thin_lens(kAperture);
  const Frame fr;
  double max_r = 0;
  for (const Vec2 film : film_points())
    for (const Vec2 u : lens_samples()) {
      const D3 l = D3(cam->generate_ray({film, u, 0}).o) - kEye;
      EXPECT_NEAR(dot(l, fr.forward), 0.0, 1e-6);
      EXPECT_LE(length(l), kAperture * (1 + 1e-5));
      max_r = std::max(max_r, length(l));
    }
  EXPECT_GT(max_r, kAperture * 0.999);

  const int n = 40000, bins = 16;
  std::vector<int> radial(bins, 0), angular(bins, 0);
  Pcg32 rng(99);
  for (int i = 0; i < n; ++i) {
    const Vec2 u{rng.next_float(), rng.next_float()};
    const D3 l = D3(cam->generate_ray({{37.5f, 61.25f}, u, 0}).o) - kEye;
    const double r2 = dot(l, l) / (kAperture * kAperture);
    const double phi = std::atan2(dot(l, fr.up), dot(l, fr.right));
    ++radial[size_t(std::clamp(int(r2 * bins), 0, bins - 1))];
    ++angular[size_t(std::clamp(int((phi / (2 * std::numbers::pi) + 0.5) * bins), 0, bins - 1))];
  }
  const double expected = double(n) / bins;
  double c_r = 0, c_a = 0;
  for (int b = 0; b < bins; ++b) {
    c_r += (radial[size_t(b)] - expected) * (radial[size_t(b)] - expected) / expected;
    c_a += (angular[size_t(b)] - expected) * (angular[size_t(b)] - expected) / expected;
  }
  EXPECT_LT(c_r, 44.26);
  EXPECT_LT(c_a, 44.26);
}

// A point at depth z off the plane of focus: the ray through lens point L (offset l from the eye)
// meets depth z at the pinhole point plus l (1 - z / focus), so through the pinhole it images
// displaced on the film by (l_right, -l_up) (1/z - 1/focus) H / (2 tan(vfov/2)); over the disc
// that is the circle of confusion of diameter A |1/z - 1/focus| H / tan(vfov/2) around the film
// point, nearer points spreading towards the lens offset and farther ones away from it.
TEST(GapThinLens, DefocusSpreadsOverTheThinLensCircleOfConfusion) {
  const auto cam = thin_lens(kAperture);
  const auto pin = pinhole();
  const Frame fr;
  const double t = std::tan(kVfov * std::numbers::pi / 360);
  for (const double z : {2.5, 4.0, 12.0, 30.0}) {
    const double k = (1 / z - 1 / kFocus) * kH / (2 * t);  // film pixels per unit of lens offset
    const double coc = kAperture * std::fabs(1 / z - 1 / kFocus) * kH / t;
    for (const Vec2 film : film_points()) {
      const Ray p = pin->generate_ray({film, {0.5f, 0.5f}, 0});
      const D3 pz = D3(p.o) + D3(p.d) * (z / dot(D3(p.d), fr.forward));
      double max_shift = 0, mean_x = 0, mean_y = 0;
      const std::vector<Vec2> us = lens_samples();
      for (const Vec2 u : us) {
        const Ray r = cam->generate_ray({film, u, 0});
        const D3 l = D3(r.o) - kEye;
        // In world space: displaced by l (1 - z / focus) from the pinhole ray's point.
        const D3 expect = pz + l * (1 - z / kFocus);
        EXPECT_LT(length(at_depth(r, z) - expect), kPointTol * (1 + z / kFocus))
            << "z " << z << ", film (" << film.x << ", " << film.y << ")";
        // On the film: the displacement of the formula, in pixels.
        const auto [fx, fy] = film_of(at_depth(r, z));
        const double dx = fx - film.x, dy = fy - film.y;
        EXPECT_NEAR(dx, dot(l, fr.right) * k, 1e-3) << "z " << z;
        EXPECT_NEAR(dy, -dot(l, fr.up) * k, 1e-3) << "z " << z;
        max_shift = std::max(max_shift, std::hypot(dx, dy));
        mean_x += dx / double(us.size()), mean_y += dy / double(us.size());
      }
      // The grid's rim samples reach the rim of the disc: the spread is the circle of confusion.
      EXPECT_NEAR(2 * max_shift, coc, 1e-3 * coc + 1e-3) << "z " << z;
      // The symmetric lens grid spreads symmetrically about the film point.
      EXPECT_NEAR(mean_x, 0.0, 1e-3 * coc + 1e-3);
      EXPECT_NEAR(mean_y, 0.0, 1e-3 * coc + 1e-3);
    }
  }
}

// A closed aperture is the pinhole camera: same origin, same direction, off axis included.
TEST(GapThinLens, ZeroApertureIsThePinhole) {
  const auto cam = thin_lens(0.0);
  const auto pin = pinhole();
  for (const Vec2 film : film_points())
    for (const Vec2 u : {Vec2{0.1f, 0.9f}, Vec2{0.7f, 0.3f}}) {
      const Ray r = cam->generate_ray({film, u, 0}), p = pin->generate_ray({film, u, 0});
      EXPECT_LT(length(D3(r.o) - D3(p.o)), 1e-6);
      EXPECT_LT(length(D3(r.d) - D3(p.d)), 1e-6);
    }
}

}  // namespace
}  // namespace penumbra
