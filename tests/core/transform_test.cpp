/// Tests of affine transforms: inverses, rotations and the look-at camera frame.
#include <gtest/gtest.h>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/core/transform.h"

namespace penumbra {
namespace {

void expect_near(Vec3 a, Vec3 b, float eps = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

TEST(Transform, ComposedTransformsInvert) {
  Pcg32 rng(3, 4);
  for (int i = 0; i < 100; ++i) {
    const Vec3 axis(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() + 0.1f);
    const Transform t =
        translate({1, -2, 3}) * rotate(360.0f * rng.next_float(), axis) * scale({0.5f, 2.0f, 3.0f});
    const Vec3 p(rng.next_float(), rng.next_float(), rng.next_float());
    expect_near(t.inverted().point(t.point(p)), p);
    expect_near(t.inverted().vector(t.vector(p)), p);
    const Mat4 id = t.matrix() * inverse(t.matrix());
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) EXPECT_NEAR(id.m[r][c], r == c ? 1.0 : 0.0, 1e-12);
  }
}

TEST(Transform, RotationIsRightHandedAndKeepsLengths) {
  expect_near(rotate(90, {0, 0, 1}).vector({1, 0, 0}), {0, 1, 0});
  expect_near(rotate(90, {1, 0, 0}).vector({0, 1, 0}), {0, 0, 1});
  expect_near(rotate(90, {0, 2, 0}).vector({0, 0, 1}), {1, 0, 0});
  const Vec3 v = rotate(37, {1, 2, 3}).vector({4, 5, 6});
  EXPECT_NEAR(length(v), length(Vec3(4, 5, 6)), 1e-5f);
  EXPECT_THROW(rotate(10, {0, 0, 0}), Error);
}

TEST(Transform, NormalsStayPerpendicularUnderNonUniformScale) {
  const Transform t = scale({1, 4, 1}) * rotate(30, {0, 0, 1});
  const Vec3 tangent = t.vector({1, -1, 0}), n = t.normal({1, 1, 0});
  EXPECT_NEAR(dot(tangent, n), 0.0f, 1e-5f);
  EXPECT_FALSE(t.swaps_handedness());
  EXPECT_TRUE(scale({-1, 1, 1}).swaps_handedness());
}

TEST(Transform, LookAtBuildsTheCameraFrame) {
  const Vec3 eye{1, 2, 3}, target{4, 2, -1}, up{0, 1, 0};
  const Transform cam = look_at(eye, target, up);
  expect_near(cam.point({0, 0, 0}), eye);
  expect_near(cam.vector({0, 0, 1}), normalize(target - eye));             // forward
  expect_near(cam.vector({1, 0, 0}), normalize(cross(target - eye, up)));  // image right
  const Vec3 cam_up = cam.vector({0, 1, 0});
  EXPECT_GT(dot(cam_up, up), 0.0f);
  EXPECT_NEAR(dot(cam_up, target - eye), 0.0f, 1e-5f);
  expect_near(cam.inverted().point(target), {0, 0, length(target - eye)}, 1e-4f);
  EXPECT_THROW(look_at(eye, eye, up), Error);
  EXPECT_THROW(look_at(eye, eye + up, up), Error);
}

TEST(Transform, BoundsContainTheTransformedCorners) {
  const Transform t = rotate(45, {0, 0, 1}) * translate({1, 0, 0});
  const Bounds3 b = t.bounds(Bounds3({0, 0, 0}, {1, 1, 1}));
  for (int i = 0; i < 8; ++i) {
    const Vec3 c = t.point({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    EXPECT_TRUE(b.contains(c) || length(c - min(max(c, b.lo), b.hi)) < 1e-5f);
  }
}

}  // namespace
}  // namespace penumbra
