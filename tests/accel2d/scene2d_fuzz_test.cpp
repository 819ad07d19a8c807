// Inputs of the 2D text format found under the fuzz target (fuzz/fuzz_scene2d.cpp, issue #18).
#include <gtest/gtest.h>

#include <string>

#include "penumbra/accel2d/scene2d.h"
#include "penumbra/core/error.h"

namespace penumbra::lab2d {
namespace {

// Coordinates near the double range made the scene's extent infinite: the bucket grid of
// check_disjoint converted NaN to int (UBSan: "-nan is outside the range of representable
// values of type 'int'"), and the side tests overflowed (disjoint segments reported as
// overlapping). Coordinates are now bounded at load, and the grid clamps before converting.
TEST(Scene2dFuzz, CoordinatesBeyondTheBoundAreRefusedAtLoad) {
  try {
    parse_scene2d("0 0 1 1\n-1.7e308 0 1.7e308 0\n", "f.txt");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "f.txt:2: '-1.7e308' is beyond the largest coordinate, ±1e+150 (products of "
                 "coordinates must stay finite)");
  }
  const Scene2D s = parse_scene2d("-1e150 0 1e150 0\n-1e140 1e149 1e140 1e148\n", "f.txt");
  EXPECT_NO_THROW(check_disjoint(s, false));
  const Scene2D crossing = parse_scene2d("-1e150 0 1e150 0\n0 -1e150 0 1e150\n", "f.txt");
  EXPECT_THROW(check_disjoint(crossing, false), Error);
}

TEST(Scene2dFuzz, BinaryDataIsNamedWithoutRawBytes) {
  try {
    parse_scene2d(std::string("0 0 1 1\n\x7f"
                              "ELF\x02\x01",
                              14),
                  "b.txt");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "b.txt: binary data at byte 8 (0x7f): expected text");
  }
}

}  // namespace
}  // namespace penumbra::lab2d
