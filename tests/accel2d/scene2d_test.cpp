// Reading the laboratory's text format: shapes, rays, and errors that name the line.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/accel2d/random_segments.h"
#include "penumbra/accel2d/scene2d.h"
#include "penumbra/core/error.h"
#include "penumbra/geometry/convex_polygon2d.h"

namespace penumbra::lab2d {
namespace {

/// The message of the Error that `f` throws ("" when it throws none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Scene2D, ParsesSegmentsPolygonsRaysAndComments) {
  const Scene2D s = parse_scene2d(
      "# a comment\n\n1 2 3 4   # trailing comment\npoly 0 0 0 1 1 0\nray 0 0 1 0.5\n", "in.txt");
  ASSERT_EQ(s.shapes.size(), 2u);
  EXPECT_EQ(s.shapes[0].v[1], Vec2d(3, 4));
  EXPECT_EQ(s.shapes[0].line, 3);
  EXPECT_FALSE(s.shapes[1].is_segment());
  EXPECT_GT(signed_area2(s.shapes[1].v), 0) << "made counter-clockwise";
  ASSERT_TRUE(s.ray.has_value());
  EXPECT_EQ(s.ray->d, Vec2d(1, 0.5));
  EXPECT_EQ(s.place(1), "in.txt:4");
}

TEST(Scene2D, BadInputNamesTheLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"0 0 1 1\n0 0 0 0\n", "in.txt:2: zero-length segment"},
      {"0 0 1 1\n\n0 0 1 x\n", "in.txt:3: 'x' is not a finite number"},
      {"0 0 1 nan\n", "in.txt:1: 'nan' is not a finite number"},
      {"0 0 1\n", "in.txt:1: a segment is four numbers"},
      {"poly 0 0 1 0\n", "in.txt:1: a polygon needs"},
      {"poly 0 0 2 0 1 0.1 1 2 0 2\n", "in.txt:1: the polygon is not convex"},
      {"ray 0 0 0 0\n", "in.txt:1: the ray's direction is zero"},
  };
  for (const auto& [text, want] : cases)
    EXPECT_NE(error_of([&] { parse_scene2d(text, "in.txt"); }).find(want), std::string::npos)
        << text << " -> " << error_of([&] { parse_scene2d(text, "in.txt"); });
}

TEST(Scene2D, CrossingTouchingAndOverlappingSegmentsAreRejected) {
  const std::pair<const char*, const char*> cases[] = {
      {"5 5 6 6\n0 0 2 2\n0 2 2 0\n",
       "in.txt:3: the segment crosses or touches the segment at line 2"},
      {"0 0 2 0\n1 0 3 0\n", "in.txt:2: the segment overlaps (collinear) the segment at line 1"},
      {"0 0 2 0\n1 0 1 3\n", "in.txt:2: the segment crosses or touches"},
      {"poly 0 0 2 0 2 2 0 2\npoly 1 1 3 1 3 3 1 3\n",
       "in.txt:2: the shape overlaps the shape at line 1"},
  };
  for (const auto& [text, want] : cases) {
    const Scene2D s = parse_scene2d(text, "in.txt");
    const std::string msg = error_of([&] { check_disjoint(s, false); });
    EXPECT_NE(msg.find(want), std::string::npos) << text << " -> " << msg;
  }
  // Disjoint ones pass, touching polygons too; polygons are refused where segments are required.
  EXPECT_EQ(error_of([] { check_disjoint(parse_scene2d("0 0 1 0\n0 1 1 1\n", "a"), true); }), "");
  const Scene2D touching = parse_scene2d("poly 0 0 1 0 1 1\npoly 1 0 2 0 2 1 1 1\n", "t.txt");
  EXPECT_EQ(error_of([&] { check_disjoint(touching, false); }), "");
  EXPECT_NE(error_of([&] { check_disjoint(touching, true); }).find("t.txt:1: a polygon"),
            std::string::npos);
}

TEST(Scene2D, RandomSegmentsAreDisjointAndFast) {
  for (uint64_t seed : {1, 2}) {
    const Scene2D s = random_segments(20000, seed);
    ASSERT_EQ(s.shapes.size(), 20000u);
    EXPECT_EQ(error_of([&] { check_disjoint(s, true); }), "");
  }
  EXPECT_EQ(error_of([] { check_disjoint(comb_segments(300), true); }), "");
}

}  // namespace
}  // namespace penumbra::lab2d
