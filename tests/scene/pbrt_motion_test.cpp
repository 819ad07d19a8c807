// pbrt-v4's animated transforms (TransformTimes, ActiveTransform) as penumbra's moving shapes and
// camera shutter, and the camera's screenwindow.
#include <gtest/gtest.h>

#include <array>

#include "pbrt_test_util.h"

namespace penumbra {
namespace {

using test::has_warning;
using test::pbrt_error;
using test::pbrt_scene;

// A plain LookAt camera mirrors the world (x -> -x, see PbrtTransform); this one has a mirrored
// frame already, so the world is kept as written and the expected transforms read directly.
const char* const kCamera = "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\n";

Vec3 origin_at(const Transform& t) {
  return t.point({0, 0, 0});
}

void expect_near(Vec3 a, Vec3 b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

std::array<double, 2> shutter(const SceneDesc& s) {
  const nlohmann::json& j = s.camera.json().at("shutter");
  return {j[0].get<double>(), j[1].get<double>()};
}

TEST(PbrtMotion, ActiveTransformEndTimeMovesTheShape) {
  const SceneDesc s = pbrt_scene(std::string(kCamera) + R"(WorldBegin
Translate 1 0 0
ActiveTransform EndTime
Translate 0 2 0
ActiveTransform All
Translate 0 0 3
Shape "sphere" "float radius" 0.5
Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]
)");
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  ASSERT_EQ(s.shapes.size(), 2u);
  for (const ShapeDesc& shape : s.shapes) {
    expect_near(origin_at(shape.to_world), {1, 0, 3});
    ASSERT_TRUE(shape.to_world_end.has_value());
    expect_near(origin_at(*shape.to_world_end), {1, 2, 3});
  }
  // pbrt's default times [0, 1] and shutter [0, 1]: the whole motion is exposed.
  EXPECT_EQ(shutter(s), (std::array<double, 2>{0, 1}));
}

TEST(PbrtMotion, StartTimeOnlyAndTheStateIsRestoredByAttributeEnd) {
  const SceneDesc s = pbrt_scene(std::string(kCamera) + R"(WorldBegin
AttributeBegin
  ActiveTransform StartTime
  Translate -1 0 0
  Shape "sphere"
AttributeEnd
Translate 0 0 4
Shape "sphere"
)");
  ASSERT_EQ(s.shapes.size(), 2u);
  expect_near(origin_at(s.shapes[0].to_world), {-1, 0, 0});
  expect_near(origin_at(*s.shapes[0].to_world_end), {0, 0, 0});
  // After AttributeEnd both transforms are active again and equal: a static shape.
  expect_near(origin_at(s.shapes[1].to_world), {0, 0, 4});
  EXPECT_FALSE(s.shapes[1].to_world_end.has_value());
}

TEST(PbrtMotion, TransformTimesAndTheShutterMapToPenumbrasTime) {
  // Transforms at times 2 and 4; the shutter open over [2.5, 3]: a quarter to a half of the way.
  const SceneDesc s = pbrt_scene(R"(TransformTimes 2 4
Scale -1 1 1
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float shutteropen" 2.5 "float shutterclose" 3
WorldBegin
ActiveTransform EndTime
Translate 4 0 0
ActiveTransform All
Shape "sphere"
)");
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  EXPECT_EQ(shutter(s), (std::array<double, 2>{0.25, 0.5}));
  // Reversed shutter times are swapped, as pbrt-v4 does, with a warning.
  const SceneDesc r =
      pbrt_scene(R"(Camera "perspective" "float shutteropen" 1 "float shutterclose" 0.5
WorldBegin
ActiveTransform EndTime
Translate 4 0 0
Shape "sphere"
)");
  EXPECT_TRUE(has_warning(r, "are swapped"));
  EXPECT_EQ(shutter(r), (std::array<double, 2>{0.5, 1}));
}

TEST(PbrtMotion, AStaticSceneHasNoShutter) {
  const SceneDesc s = pbrt_scene(std::string(kCamera) + "WorldBegin\nShape \"sphere\"\n");
  EXPECT_FALSE(s.camera.json().contains("shutter"));
  EXPECT_FALSE(s.shapes.at(0).to_world_end.has_value());
  // An ActiveTransform that changes nothing in the end leaves the shapes static too.
  const SceneDesc t =
      pbrt_scene(std::string(kCamera) + "WorldBegin\nActiveTransform EndTime\nShape \"sphere\"\n");
  EXPECT_FALSE(t.camera.json().contains("shutter"));
}

TEST(PbrtMotion, NamedCoordinateSystemsKeepBothTransforms) {
  const SceneDesc s = pbrt_scene(std::string(kCamera) + R"(WorldBegin
ActiveTransform EndTime
Translate 0 1 0
ActiveTransform All
CoordinateSystem "moving"
Identity
CoordSysTransform "moving"
Shape "sphere"
)");
  ASSERT_EQ(s.shapes.size(), 1u);
  ASSERT_TRUE(s.shapes[0].to_world_end.has_value());
  expect_near(origin_at(*s.shapes[0].to_world_end), {0, 1, 0});
}

TEST(PbrtMotion, WhatCannotMoveGetsItsStartTransformWithAWarning) {
  const SceneDesc s = pbrt_scene(std::string(kCamera) + R"(WorldBegin
ActiveTransform EndTime
Translate 0 1 0
ActiveTransform All
LightSource "point" "rgb I" [1 1 1]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  Shape "sphere"
AttributeEnd
ObjectBegin "thing"
  Shape "sphere"
ObjectEnd
ObjectInstance "thing"
)");
  EXPECT_TRUE(has_warning(s, "a LightSource cannot move"));
  EXPECT_TRUE(has_warning(s, "an emitting shape cannot move"));
  EXPECT_TRUE(has_warning(s, "a shape in an object definition cannot move"));
  EXPECT_TRUE(has_warning(s, "an instance cannot move"));
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_FALSE(s.shapes[0].to_world_end.has_value());
  ASSERT_TRUE(s.shapes[0].emission.has_value());
  expect_near(origin_at(s.shapes[0].to_world), {0, 0, 0});
  expect_near(origin_at(s.instances.at(0).to_world), {0, 0, 0});
  // Nothing moves, so the camera has no shutter.
  EXPECT_FALSE(s.camera.json().contains("shutter"));
}

TEST(PbrtMotion, AMovingCameraIsReportedAndKeptAtItsStart) {
  const SceneDesc s = pbrt_scene(R"(ActiveTransform EndTime
Translate 1 0 0
ActiveTransform All
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
Shape "sphere"
)");
  EXPECT_TRUE(has_warning(s, "the camera moves"));
  const nlohmann::json& p = s.camera.json().at("position");
  EXPECT_NEAR(p[0].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(p[2].get<double>(), -5.0, 1e-6);
}

TEST(PbrtMotion, TurningShapesAreWarnedAboutWithTheShrinkMidway) {
  const SceneDesc s = pbrt_scene(std::string(kCamera) + R"(WorldBegin
ActiveTransform EndTime
Rotate 30 0 1 0
Scale 2 2 2
ActiveTransform All
Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]
)");
  // A turn of 30 degrees: mid-way the chord is cos(15 deg) = 0.966 of the arc's radius.
  EXPECT_TRUE(has_warning(s, "turns by 30 degrees")) << s.warnings.at(0);
  EXPECT_TRUE(has_warning(s, "3.40742 % closer")) << s.warnings.at(0);
  // Translation and scale alone are pbrt's motion exactly: no warning.
  const SceneDesc t = pbrt_scene(std::string(kCamera) + R"(WorldBegin
ActiveTransform EndTime
Translate 1 2 3
Scale 2 3 4
Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]
)");
  EXPECT_TRUE(t.warnings.empty()) << t.warnings.front();
}

TEST(PbrtMotion, MotionThatPenumbraCannotRepresentIsRefusedAtTheShape) {
  const std::string moving = std::string(kCamera) + "WorldBegin\nActiveTransform EndTime\n";
  EXPECT_NE(pbrt_error(moving + "Scale 1 2 1\nShape \"sphere\"\n")
                .find("test.pbrt:7:1: a sphere's transform at the end time must be a similarity"),
            std::string::npos);
  EXPECT_NE(pbrt_error(moving + "Scale -1 1 1\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 "
                                "0 1 0] \"integer indices\" [0 1 2]\n")
                .find("would turn inside out"),
            std::string::npos);
  EXPECT_NE(pbrt_error("TransformTimes 1 1\n")
                .find("test.pbrt:1:1: TransformTimes: the start "
                      "time must be before the end time"),
            std::string::npos);
  EXPECT_NE(pbrt_error("WorldBegin\nTransformTimes 0 1\n").find("is not allowed after WorldBegin"),
            std::string::npos);
  EXPECT_NE(pbrt_error("ActiveTransform Sometimes\n").find("ActiveTransform expects All"),
            std::string::npos);
}

TEST(PbrtCamera, ScreenWindowIsKeptWithTheFovAsItsUnit) {
  // Taller than wide: without a screenwindow pbrt's fov spans x; with one it is the unit of both.
  const SceneDesc s = pbrt_scene(R"(Camera "perspective" "float fov" 40
  "float screenwindow" [0 0.75 -1 1]
Film "rgb" "integer xresolution" 30 "integer yresolution" 80
WorldBegin
)");
  EXPECT_FALSE(has_warning(s, "unused"));
  const nlohmann::json& c = s.camera.json();
  EXPECT_EQ(c.at("screen_window"), (nlohmann::json{0, 0.75, -1, 1}));
  EXPECT_DOUBLE_EQ(c.at("vfov").get<double>(), 40.0);
  const SceneDesc d = pbrt_scene(R"(Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 30 "integer yresolution" 80
WorldBegin
)");
  EXPECT_FALSE(d.camera.json().contains("screen_window"));
  EXPECT_GT(d.camera.json().at("vfov").get<double>(), 80.0);  // the fov of the longer axis
  EXPECT_NE(pbrt_error("Camera \"perspective\" \"float screenwindow\" [0 1 0]\nWorldBegin\n")
                .find("screenwindow takes four numbers"),
            std::string::npos);
  EXPECT_NE(pbrt_error("Camera \"perspective\" \"float screenwindow\" [1 0 0 1]\nWorldBegin\n")
                .find("must have x0 < x1"),
            std::string::npos);
}

}  // namespace
}  // namespace penumbra
