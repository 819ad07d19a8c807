/// Tests of the pbrt reader's "loopsubdiv" shape: mapped to a subdivided TriangleMesh with limit
/// normals under the shape's transform (world mirror included), its defaults, ReverseOrientation,
/// the non-manifold warnings and the errors at their places.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>

#include "pbrt_test_util.h"

namespace penumbra {
namespace {

using test::has_warning;
using test::pbrt_error;
using test::pbrt_scene;

/// A regular octahedron as pbrt text (outward winding), with `extra` parameters.
std::string octahedron(const std::string& extra) {
  return "Shape \"loopsubdiv\" \"point3 P\" [1 0 0 -1 0 0 0 1 0 0 -1 0 0 0 1 0 0 -1]\n"
         "  \"integer indices\" [0 2 4 2 1 4 1 3 4 3 0 4 2 0 5 1 2 5 3 1 5 0 3 5]" +
         extra + "\n";
}

TEST(PbrtLoopSubdiv, OctahedronBecomesASmoothMeshWithLimitNormals) {
  const SceneDesc s = pbrt_scene("Camera \"perspective\"\nWorldBegin\nTranslate 2 0 0\n" +
                                 octahedron(" \"integer levels\" 2"));
  ASSERT_EQ(s.shapes.size(), 1u);
  const auto& m = std::get<TriangleMesh>(s.shapes[0].geometry);
  EXPECT_EQ(m.triangle_count(), 8u * 16u);
  EXPECT_EQ(m.positions.size(), 2u + 8u * 16u / 2u);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    EXPECT_LT(length(m.positions[v]), 1.0f);                        // inside the control hull
    EXPECT_GT(dot(m.normals[v], normalize(m.positions[v])), 0.9f);  // outward, nearly radial
  }
  // Object space with the CTM as the transform, then the world mirror (x negated).
  EXPECT_EQ(s.shapes[0].to_world.point({0, 0, 0}), Vec3(-2, 0, 0));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // pbrt's default: 3 levels.
  const SceneDesc d = pbrt_scene("WorldBegin\n" + octahedron(""));
  EXPECT_EQ(std::get<TriangleMesh>(d.shapes[0].geometry).triangle_count(), 8u * 64u);
}

TEST(PbrtLoopSubdiv, ReverseOrientationTurnsTheNormalsInwards) {
  const SceneDesc s =
      pbrt_scene("WorldBegin\nReverseOrientation\n" + octahedron(" \"integer levels\" 1"));
  const auto& m = std::get<TriangleMesh>(s.shapes[0].geometry);
  for (size_t v = 0; v < m.positions.size(); ++v)
    EXPECT_LT(dot(m.normals[v], m.positions[v]), 0.0f);
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const Vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
               c = m.positions[m.indices[t + 2]];
    EXPECT_LT(dot(cross(b - a, c - a), a + b + c), 0.0f);  // the winding turned too
  }
}

TEST(PbrtLoopSubdiv, NonManifoldEdgesAreWarnedAboutAndBadInputIsAnError) {
  const SceneDesc s = pbrt_scene(
      "WorldBegin\nShape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0.5 1 0 0.5 -1 0 0.5 0 1]\n"
      "  \"integer indices\" [0 1 2 1 0 3 0 1 4] \"integer levels\" 1\n");
  EXPECT_EQ(std::get<TriangleMesh>(s.shapes[0].geometry).triangle_count(), 12u);
  EXPECT_TRUE(has_warning(s, "test.pbrt:2:1: loopsubdiv: 1 edges are shared by more than two"));
  const std::string tri = "Shape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0] ";
  EXPECT_EQ(pbrt_error("WorldBegin\n" + tri + "\"integer indices\" [0 1 2] \"integer levels\" 11"),
            "test.pbrt:2:77: Shape \"loopsubdiv\": loop subdivision: \"levels\" 11 is outside "
            "[0, 10]");
  EXPECT_EQ(pbrt_error("WorldBegin\n" + tri + "\"integer indices\" [0 1 1]"),
            "test.pbrt:2:1: Shape \"loopsubdiv\": loop subdivision: triangle 0 repeats vertex 1");
  EXPECT_EQ(pbrt_error("WorldBegin\n" + tri),
            "test.pbrt:2:1: Shape \"loopsubdiv\" needs \"integer indices\"");
  EXPECT_EQ(pbrt_error("WorldBegin\nShape \"loopsubdiv\" \"integer indices\" [0 1 2]"),
            "test.pbrt:2:1: Shape \"loopsubdiv\" needs \"point3 P\"");
  EXPECT_NE(pbrt_error("WorldBegin\n" + tri + "\"integer indices\" [0 1 3]").find("out of range"),
            std::string::npos);
}

}  // namespace
}  // namespace penumbra
