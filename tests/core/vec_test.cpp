/// Tests of Vec3's component access by a run-time index (an indexed load at run time, selects in
/// constant evaluation): both forms must name the same component.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

#include "penumbra/core/vec.h"

namespace penumbra {
namespace {

// Constant evaluation takes the selects.
static_assert(Vec3(1.0f, 2.0f, 3.0f)[0] == 1.0f && Vec3(1.0f, 2.0f, 3.0f)[1] == 2.0f &&
              Vec3(1.0f, 2.0f, 3.0f)[2] == 3.0f);
constexpr Vec3 written_through_index() {
  Vec3 v;
  v[2] = 5.0f, v[0] = 4.0f;
  return v;
}
static_assert(written_through_index() == Vec3(4.0f, 0.0f, 5.0f));

/// An index the compiler cannot see (as a ray's permutation or a split axis is).
int opaque(int i) {
  volatile int v = i;
  return v;
}

TEST(Vec3, RunTimeIndexReadsAndWritesTheNamedComponent) {
  const Vec3 v{-0.0f, 7.5f, -3.25f};
  const float expect[3] = {v.x, v.y, v.z};
  for (int i = 0; i < 3; ++i) {
    // Bit for bit: the sign of -0 too.
    EXPECT_EQ(std::bit_cast<uint32_t>(v[opaque(i)]), std::bit_cast<uint32_t>(expect[i])) << i;
    Vec3 w{1.0f, 2.0f, 3.0f};
    w[opaque(i)] = 9.0f;
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(w[opaque(k)], k == i ? 9.0f : float(k + 1)) << i << " " << k;
  }
}

}  // namespace
}  // namespace penumbra
