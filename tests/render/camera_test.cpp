#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "penumbra/render/camera/pinhole_camera.h"

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

}  // namespace
}  // namespace penumbra
