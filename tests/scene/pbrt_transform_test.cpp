/// Tests of the pbrt transform directives and graphics state against matrices computed by hand:
/// Translate, Scale, Rotate, LookAt, Transform and ConcatTransform (column order), Identity,
/// CoordinateSystem / CoordSysTransform (and "camera"), AttributeBegin/End, ReverseOrientation,
/// and the mirror that makes penumbra's picture pbrt's.
#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "pbrt_test_util.h"

namespace penumbra {
namespace {

using test::pbrt_error;
using test::pbrt_scene;

// A camera whose transform mirrors (Scale -1 1 1), so that penumbra's world is pbrt's world
// unchanged; `world` follows WorldBegin.
SceneDesc unmirrored(const std::string& world) {
  return pbrt_scene("Scale -1 1 1\nCamera \"perspective\"\nWorldBegin\n" + world);
}

void expect_point(const Transform& t, Vec3 p, Vec3 expected) {
  const Vec3 q = t.point(p);
  EXPECT_NEAR(q.x, expected.x, 1e-6) << "x";
  EXPECT_NEAR(q.y, expected.y, 1e-6) << "y";
  EXPECT_NEAR(q.z, expected.z, 1e-6) << "z";
}

TEST(PbrtTransform, TranslateScaleRotateComposeOnTheRight) {
  const SceneDesc s = unmirrored(
      "Translate 1 2 3\nShape \"sphere\"\n"
      "Identity\nScale 2 3 4\nTranslate 1 0 0\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 "
      "0 1 0]\n"
      "Identity\nRotate 90 0 0 1\nShape \"sphere\"\n");
  ASSERT_EQ(s.shapes.size(), 3u);
  const Mat4& t = s.shapes[0].to_world.matrix();
  EXPECT_EQ(t.m[0][3], 1.0);
  EXPECT_EQ(t.m[1][3], 2.0);
  EXPECT_EQ(t.m[2][3], 3.0);
  // CTM = Scale * Translate: the translation acts first, then the scale.
  expect_point(s.shapes[1].to_world, {0, 0, 0}, {2, 0, 0});
  expect_point(s.shapes[1].to_world, {0, 1, 0}, {2, 3, 0});
  // Rotate 90 about +z takes +x to +y (the right-handed matrix, as pbrt writes it).
  expect_point(s.shapes[2].to_world, {1, 0, 0}, {0, 1, 0});
  expect_point(s.shapes[2].to_world, {0, 1, 0}, {-1, 0, 0});
}

TEST(PbrtTransform, MatricesAreGivenColumnByColumn) {
  // The first four numbers are the first column: +x goes to +y; numbers 12-14 translate.
  const SceneDesc s = unmirrored(
      "Transform [0 1 0 0  -1 0 0 0  0 0 1 0  5 6 7 1]\nShape \"sphere\"\n"
      "Translate 1 0 0\nShape \"sphere\"\n"
      "Identity\nTranslate 1 0 0\nConcatTransform [2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1]\n"
      "Shape \"sphere\"\n");
  ASSERT_EQ(s.shapes.size(), 3u);
  expect_point(s.shapes[0].to_world, {0, 0, 0}, {5, 6, 7});
  expect_point(s.shapes[0].to_world, {1, 0, 0}, {5, 7, 7});
  expect_point(s.shapes[0].to_world, {0, 1, 0}, {4, 6, 7});
  // Transform replaces the CTM; Translate then multiplies on the right (in object space).
  expect_point(s.shapes[1].to_world, {0, 0, 0}, {5, 7, 7});
  // ConcatTransform multiplies on the right: T * S.
  expect_point(s.shapes[2].to_world, {1, 1, 1}, {3, 2, 2});
}

TEST(PbrtTransform, ARowMajorReadingIsRefusedAsNotAffine) {
  EXPECT_EQ(pbrt_error("Transform [1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1]"),
            "test.pbrt:1:1: the matrix is not affine (numbers 3, 7, 11, 15 must be 0, 0, 0, 1): "
            "projective transforms are not supported");
  EXPECT_NE(pbrt_error("Transform [0 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1]").find("no inverse"),
            std::string::npos);
}

TEST(PbrtTransform, LookAtIsWorldToCameraWithLeftHandedFrame) {
  // Looking along +x with up +y: camera +x (right) = cross(up, dir) = -z, +y = +y, +z = +x.
  // World-to-camera has rows right, up, dir: world (0, 0, 1) is camera (-1, 0, 0).
  const SceneDesc s = unmirrored(
      "LookAt 0 0 0  1 0 0  0 1 0\nShape \"sphere\"\n"
      "Identity\nLookAt 1 2 3  2 2 3  0 1 0\nShape \"sphere\"\n");
  const Transform& t = s.shapes[0].to_world;
  expect_point(t, {0, 0, 1}, {-1, 0, 0});
  expect_point(t, {1, 0, 0}, {0, 0, 1});
  expect_point(t, {0, 1, 0}, {0, 1, 0});
  expect_point(s.shapes[1].to_world, {1, 2, 3}, {0, 0, 0});
  expect_point(s.shapes[1].to_world, {1, 2, 5}, {-2, 0, 0});
  EXPECT_NE(pbrt_error("LookAt 0 0 0  0 1 0  0 1 0").find("parallel"), std::string::npos);
}

TEST(PbrtTransform, NamedCoordinateSystemsAndCamera) {
  const SceneDesc s = pbrt_scene(
      "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\n"
      "WorldBegin\nTranslate 1 0 0\nCoordinateSystem \"a\"\nIdentity\nTranslate 0 9 0\n"
      "CoordSysTransform \"a\"\nShape \"sphere\"\n"
      "CoordSysTransform \"camera\"\nShape \"sphere\"\n"
      "CoordSysTransform \"nope\"\n");
  ASSERT_EQ(s.shapes.size(), 2u);
  expect_point(s.shapes[0].to_world, {0, 0, 0}, {1, 0, 0});
  // "camera" is camera-to-world: the eye at its origin, the viewing direction along its +z.
  expect_point(s.shapes[1].to_world, {0, 0, 0}, {0, 0, -5});
  expect_point(s.shapes[1].to_world, {0, 0, 1}, {0, 0, -4});
  expect_point(s.shapes[1].to_world, {1, 0, 0}, {-1, 0, -5});  // Scale -1 1 1 mirrors camera x
  EXPECT_TRUE(test::has_warning(s, "test.pbrt:13:1: CoordSysTransform: unknown coordinate system"));
}

TEST(PbrtTransform, AttributesRestoreTheStateAndTransformBeginOnlyTheCtm) {
  const SceneDesc s = unmirrored(
      "AttributeBegin\nTranslate 1 0 0\nReverseOrientation\nAttributeEnd\n"
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
      "TransformBegin\nTranslate 0 1 0\nReverseOrientation\nTransformEnd\n"
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n");
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_TRUE(s.shapes[0].to_world.is_identity());
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[0].geometry).indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_TRUE(s.shapes[1].to_world.is_identity());
  // ReverseOrientation survived TransformEnd: the winding is reversed.
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[1].geometry).indices, (std::vector<uint32_t>{0, 2, 1}));
}

TEST(PbrtTransform, ReverseOrientationFollowsNormalsWhenGiven) {
  // With N, pbrt turns the geometric normal to the shading normal (negated by
  // ReverseOrientation): here N points to -z, against the counter-clockwise winding.
  const SceneDesc s = unmirrored(
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 -1 0 0 -1 0 0 "
      "-1]\n"
      "ReverseOrientation\n"
      "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 -1 0 0 -1 0 0 "
      "-1]\n");
  const auto& a = std::get<TriangleMesh>(s.shapes[0].geometry);
  const auto& b = std::get<TriangleMesh>(s.shapes[1].geometry);
  EXPECT_EQ(a.indices, (std::vector<uint32_t>{0, 2, 1}));
  EXPECT_EQ(b.indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(b.normals[0], Vec3(0, 0, 1));
}

TEST(PbrtTransform, APlainCameraMirrorsTheWorldSoThePicturesAgree) {
  // pbrt's image right is camera +x = cross(up, dir) = world +x here; penumbra's is
  // cross(forward, up) = world -x. The importer negates world x (shapes, lights, camera).
  const SceneDesc s = pbrt_scene(
      "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
      "Translate 1 0 0\nShape \"sphere\" \"float radius\" 0.5\n"
      "LightSource \"point\" \"point3 from\" [2 0 0]\n");
  expect_point(s.shapes[0].to_world, {0, 0, 0}, {-1, 0, 0});
  EXPECT_EQ(s.lights[0].get_vec3("position", {}), Vec3(-3, 0, 0));
  const Vec3 eye = s.camera.get_vec3("position", {}), at = s.camera.get_vec3("look_at", {});
  const Vec3 up = s.camera.get_vec3("up", {});
  EXPECT_EQ(eye, Vec3(0, 0, -5));
  // Our image right: cross(forward, up); the sphere (pbrt +x) must lie on the right.
  const Vec3 right = cross(normalize(at - eye), up);
  EXPECT_GT(dot(right, s.shapes[0].to_world.point({0, 0, 0}) - eye), 0.5f);
  // The same camera mirrored by Scale -1 1 1: no world mirror, and the sphere is on the left.
  const SceneDesc m = pbrt_scene(
      "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
      "Translate 1 0 0\nShape \"sphere\" \"float radius\" 0.5\n");
  expect_point(m.shapes[0].to_world, {0, 0, 0}, {1, 0, 0});
  const Vec3 right_m = cross(normalize(m.camera.get_vec3("look_at", {}) - eye), up);
  EXPECT_LT(dot(right_m, m.shapes[0].to_world.point({0, 0, 0}) - eye), -0.5f);
}

}  // namespace
}  // namespace penumbra
