/// pbrt-v4 object instancing: ObjectBegin / ObjectEnd / ObjectInstance become named objects and
/// instances; the instance's transform is the CTM at ObjectInstance (then the world mirror), the
/// shapes keep the full CTM at their definition (which includes the CTM at ObjectBegin).
#include <gtest/gtest.h>

#include "pbrt_test_util.h"

namespace penumbra {
namespace {

using test::has_warning;
using test::pbrt_error;
using test::pbrt_scene;

void expect_near(Vec3 a, Vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST(PbrtInstances, ObjectsAndInstancesComposeTheirTransforms) {
  const SceneDesc s = pbrt_scene(
      "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
      "Translate 0 0 10\n"  // CTM at ObjectBegin
      "ObjectBegin \"thing\"\nTranslate 1 0 0\nShape \"sphere\" \"float radius\" 0.5\n"
      "Material \"conductor\"\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
      "ObjectEnd\n"
      "Shape \"sphere\"\n"  // the CTM is restored: z = 10
      "AttributeBegin\nTranslate 0 3 0\nObjectInstance \"thing\"\nAttributeEnd\n"
      "ObjectInstance \"thing\"\n");
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].name, "thing");
  EXPECT_EQ(s.objects[0].path, "test.pbrt:5:1");
  ASSERT_EQ(s.objects[0].shapes.size(), 2u);
  EXPECT_NE(s.objects[0].shapes[0].material, s.objects[0].shapes[1].material);
  ASSERT_EQ(s.shapes.size(), 1u);
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.instances[0].path, "test.pbrt:14:1");
  // World position of the object's sphere centre: world mirror (x -> -x) of
  // CTM at instance (translate z 10, y 3) * CTM at shape (translate z 10, x 1).
  const Vec3 c0 = s.instances[0].to_world.point(s.objects[0].shapes[0].to_world.point({0, 0, 0}));
  expect_near(c0, {-1, 3, 20});
  const Vec3 c1 = s.instances[1].to_world.point(s.objects[0].shapes[0].to_world.point({0, 0, 0}));
  expect_near(c1, {-1, 0, 20});
  // The plain sphere: the CTM (z = 10) under the world mirror.
  expect_near(s.shapes[0].to_world.point({0, 0, 0}), {0, 0, 10});
  EXPECT_FALSE(has_warning(s, "instancing"));
}

TEST(PbrtInstances, InstancesMayPrecedeTheirDefinition) {
  const SceneDesc s = pbrt_scene(
      "WorldBegin\nObjectInstance \"later\"\nObjectBegin \"later\"\nShape \"sphere\"\n"
      "ObjectEnd\n");
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.instances[0].object, 0u);
}

TEST(PbrtInstances, AreaLightsInObjectsAreWarnedAboutAndDropped) {
  // As pbrt-v4: area lights are not supported with object instancing.
  const SceneDesc s = pbrt_scene(
      "WorldBegin\nObjectBegin \"lamp\"\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
      "Shape \"sphere\"\nObjectEnd\nObjectInstance \"lamp\"\n");
  ASSERT_EQ(s.objects.size(), 1u);
  ASSERT_EQ(s.objects[0].shapes.size(), 1u);
  EXPECT_FALSE(s.objects[0].shapes[0].emission);
  EXPECT_TRUE(
      has_warning(s, "test.pbrt:4:1: area lights are not supported with object instancing"));
}

TEST(PbrtInstances, ErrorsNameTheirPlace) {
  EXPECT_EQ(pbrt_error("WorldBegin\nObjectInstance \"nothing\"\n"),
            "test.pbrt:2:1: ObjectInstance: unknown object \"nothing\"");
  EXPECT_EQ(pbrt_error("WorldBegin\nObjectBegin \"a\"\nShape \"sphere\"\n"),
            "test.pbrt:2:1: ObjectBegin without ObjectEnd");
  EXPECT_EQ(pbrt_error("WorldBegin\nObjectEnd\n"), "test.pbrt:2:1: ObjectEnd without ObjectBegin");
  EXPECT_EQ(pbrt_error("WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\"\n"),
            "test.pbrt:3:1: ObjectBegin inside the definition begun at test.pbrt:2:1");
  EXPECT_EQ(pbrt_error("WorldBegin\nObjectBegin \"a\"\nObjectEnd\nObjectBegin \"a\"\n"),
            "test.pbrt:4:1: ObjectBegin \"a\": the object is already defined at test.pbrt:2:1");
  const std::string nested = pbrt_error(
      "WorldBegin\nObjectBegin \"a\"\nObjectEnd\nObjectBegin \"b\"\nObjectInstance \"a\"\n");
  EXPECT_EQ(nested.rfind("test.pbrt:5:1: ObjectInstance \"a\" inside the definition", 0), 0u)
      << nested;
  EXPECT_NE(pbrt_error("ObjectBegin \"a\"\n").find("test.pbrt:1:1"), std::string::npos);
}

}  // namespace
}  // namespace penumbra
