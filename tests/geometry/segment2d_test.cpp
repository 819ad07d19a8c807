// The 2D kernels of the laboratory: segment–ray intersection, lines, clipping.
#include <gtest/gtest.h>

#include "penumbra/geometry/convex_polygon2d.h"
#include "penumbra/geometry/segment2d.h"

namespace penumbra {
namespace {

TEST(Segment2d, RayMeetsSegmentAtTheAnalyticParameter) {
  const Segment2 s{{2, -1}, {2, 3}};
  EXPECT_DOUBLE_EQ(intersect({{0, 0}, {1, 0}}, s), 2.0);
  EXPECT_DOUBLE_EQ(intersect({{0, 0}, {4, 2}}, s), 0.5);        // at (2, 1)
  EXPECT_EQ(intersect({{0, 0}, {1, 2}}, s), INFINITY);          // passes above
  EXPECT_EQ(intersect({{0, 0}, {-1, 0}}, s), INFINITY);         // behind
  EXPECT_EQ(intersect({{0, 0}, {1, 0}, 0, 1.5}, s), INFINITY);  // beyond tmax
  EXPECT_DOUBLE_EQ(intersect({{2, -3}, {0, 1}}, s), 2.0);       // collinear: entry
  EXPECT_DOUBLE_EQ(intersect({{2, 0}, {0, 1}}, s), 0.0);        // starts inside
  EXPECT_EQ(intersect({{3, -3}, {0, 1}}, s), INFINITY);         // parallel
  EXPECT_EQ(s.at(0.0), s.a);
  EXPECT_EQ(s.at(1.0), s.b);
}

TEST(Segment2d, LineThroughIsOrientedWithThePositiveSideOnTheLeft) {
  const Line2 l = Line2::through({0, 0}, {2, 0});
  EXPECT_GT(l.eval({1, 1}), 0);
  EXPECT_LT(l.eval({1, -1}), 0);
  EXPECT_DOUBLE_EQ(l.eval({5, 3}), 3.0);  // unit normal: the signed distance
  EXPECT_EQ(side_of_piece(-1, 1, 1e-9), Side::kBoth);
  EXPECT_EQ(side_of_piece(0, 1, 1e-9), Side::kPositive);
  EXPECT_EQ(side_of_piece(1e-12, -1e-12, 1e-9), Side::kOn);
  EXPECT_EQ(orientation({0, 0}, {1, 0}, {0.5, 1e-12}, 1e-9), 0);
  EXPECT_EQ(orientation({0, 0}, {1, 0}, {0.5, -1}, 1e-9), -1);
}

TEST(Segment2d, BoxesAndClipping) {
  const Box2d box{{0, 0}, {2, 1}};
  double t0, t1;
  ASSERT_TRUE(ray_box_interval({{-1, 0.5}, {1, 0}}, box, t0, t1));
  EXPECT_DOUBLE_EQ(t0, 1.0);
  EXPECT_DOUBLE_EQ(t1, 3.0);
  EXPECT_FALSE(ray_box_interval({{-1, 2}, {1, 0}}, box, t0, t1));
  EXPECT_TRUE(segment_overlaps_box({{-1, -1}, {0.5, 0.5}}, box, 0));
  EXPECT_FALSE(segment_overlaps_box({{-1, 0.5}, {-0.1, 3}}, box, 0));
  const std::vector<Vec2d> square{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  const auto half = clip_convex(square, Line2::through({1, 0}, {1, 2}), true, 0);  // x < 1
  EXPECT_DOUBLE_EQ(signed_area2(half), 4.0);
  Segment2 chord;
  ASSERT_TRUE(clip_line(square, Line2::through({0, 1}, {5, 1}), chord));
  EXPECT_DOUBLE_EQ(length(chord.b - chord.a), 2.0);
  EXPECT_TRUE(convex_overlap(square, std::vector<Vec2d>{{1, 1}, {3, 1}, {3, 3}}, 1e-9));
  EXPECT_FALSE(convex_overlap(square, std::vector<Vec2d>{{2, 0}, {3, 0}, {3, 1}}, 1e-9));
  EXPECT_TRUE(is_convex(square, 1e-9));
}

}  // namespace
}  // namespace penumbra
