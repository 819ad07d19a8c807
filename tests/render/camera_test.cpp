#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "penumbra/core/error.h"
#include "penumbra/render/camera/pinhole_camera.h"
#include "penumbra/render/camera/thin_lens_camera.h"

namespace penumbra {
namespace {

// The Cornell box reference convention: camera at (278, 273, -800) looking along +z, so image
// right is world -x and image up is world +y.
TEST(PinholeCamera, FollowsTheCornellPixelConvention) {
  const PinholeCamera cam({278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.307648f, 256, 256);
  const Ray centre = cam.generate_ray({{128, 128}, {}, 0});
  EXPECT_NEAR(centre.d.x, 0.0f, 1e-6f);
  EXPECT_NEAR(centre.d.y, 0.0f, 1e-6f);
  EXPECT_NEAR(centre.d.z, 1.0f, 1e-6f);
  const Ray left = cam.generate_ray({{0, 128}, {}, 0});
  EXPECT_GT(left.d.x, 0.0f);  // the left of the image looks towards +x (the red wall)
  const Ray top = cam.generate_ray({{128, 0}, {}, 0});
  EXPECT_GT(top.d.y, 0.0f);
  // The top edge lies at half the vertical field of view.
  const double half = std::atan2(double(top.d.y), double(top.d.z)) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(half, 39.307648 / 2, 1e-4);
}

TEST(PinholeCamera, WideImagesKeepTheVerticalFieldOfView) {
  const PinholeCamera cam({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 90.0f, 200, 100);
  const Ray right = cam.generate_ray({{200, 50}, {}, 0});
  EXPECT_NEAR(right.d.x / right.d.z, -2.0f, 1e-5f);  // tan(45 deg) * aspect 2, image right = -x
  const Ray bottom = cam.generate_ray({{100, 100}, {}, 0});
  EXPECT_NEAR(bottom.d.y / bottom.d.z, -1.0f, 1e-5f);
}

SceneParams camera_params(const nlohmann::json& extra, const char* type = "pinhole") {
  nlohmann::json j = {{"type", type},
                      {"position", {1, 2, 3}},
                      {"look_at", {2, 2, 7}},
                      {"up", {0, 1, 0}},
                      {"vfov", 50}};
  if (extra.is_object()) j.update(extra);
  return SceneParams(j, "cam.json", "/camera");
}

// A window shifted to the right half of the default one, at half the width, sees exactly what
// the right half of the full image sees: the same rays at the corresponding film positions.
TEST(PinholeCamera, AScreenWindowIsTheMatchingPartOfTheImagePlane) {
  const int w = 40, h = 30;
  const double a = double(2 * w) / double(h);  // the full image is 2w x h
  const PinholeCamera full(camera_params({}), 2 * w, h);
  const PinholeCamera right(camera_params({{"screen_window", {0.0, a, -1.0, 1.0}}}), w, h);
  // The top-left quarter: x in [-a, 0], y in [0, 1], at half the width and height.
  const PinholeCamera quarter(camera_params({{"screen_window", {-a, 0.0, 0.0, 1.0}}}), w, h / 2);
  for (float y : {0.0f, 0.25f, 7.5f, 14.0f})
    for (float x : {0.0f, 0.5f, 13.25f, 39.99f}) {
      const Vec3 d = right.generate_ray({{x, 2 * y}, {}, 0}).d;
      const Vec3 e = full.generate_ray({{x + float(w), 2 * y}, {}, 0}).d;
      EXPECT_NEAR(d.x, e.x, 2e-6f) << x << "," << y;
      EXPECT_NEAR(d.y, e.y, 2e-6f);
      EXPECT_NEAR(d.z, e.z, 2e-6f);
      const Vec3 q = quarter.generate_ray({{x, y}, {}, 0}).d;
      const Vec3 f = full.generate_ray({{x, y}, {}, 0}).d;
      EXPECT_NEAR(q.x, f.x, 2e-6f) << x << "," << y;
      EXPECT_NEAR(q.y, f.y, 2e-6f);
      EXPECT_NEAR(q.z, f.z, 2e-6f);
    }
  // The thin lens focuses through the same window: its rays meet the pinhole's focal point.
  const ThinLensCamera lens(camera_params({{"screen_window", {0.0, a, -1.0, 1.0}},
                                           {"aperture_radius", 0.2},
                                           {"focus_distance", 3.0}},
                                          "thin_lens"),
                            w, h);
  const Ray r = lens.generate_ray({{10, 5}, {0.9f, 0.1f}, 0});
  const Ray p = right.generate_ray({{10, 5}, {}, 0});
  const Vec3 fwd = normalize(Vec3{1, 0, 4});
  const Vec3 fp = p.o + p.d * (3.0f / dot(p.d, fwd));
  const Vec3 fr = r.o + r.d * (dot(fp - r.o, fwd) / dot(r.d, fwd));
  EXPECT_NEAR(length(fr - fp), 0.0f, 1e-4f);
  EXPECT_GT(length(r.o - p.o), 0.01f);  // a point of the lens off its centre
}

TEST(PinholeCamera, TheDefaultWindowGivesTheSameBitsAsNone) {
  const PinholeCamera none(camera_params({}), 64, 48);
  const double a = 64.0 / 48.0;
  const PinholeCamera given(camera_params({{"screen_window", {-a, a, -1.0, 1.0}}}), 64, 48);
  for (float y : {0.0f, 11.3f, 47.9f})
    for (float x : {0.0f, 31.7f, 63.2f}) {
      const Vec3 d = none.generate_ray({{x, y}, {}, 0}).d,
                 e = given.generate_ray({{x, y}, {}, 0}).d;
      EXPECT_NEAR(d.x, e.x, 1e-6f);
      EXPECT_NEAR(d.y, e.y, 1e-6f);
    }
}

TEST(PinholeCamera, MalformedScreenWindowsAreRefusedNamingTheKey) {
  for (const nlohmann::json& bad :
       {nlohmann::json{0, 1, 0}, nlohmann::json{1, 0, -1, 1}, nlohmann::json{-1, 1, 1, 1},
        nlohmann::json{-1, 1, -1, 1e9}, nlohmann::json{-1, 1, -1, "1"}, nlohmann::json(2)}) {
    try {
      PinholeCamera cam(camera_params({{"screen_window", bad}}), 8, 8);
      ADD_FAILURE() << "accepted " << bad.dump();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("cam.json:/camera/screen_window"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace penumbra
