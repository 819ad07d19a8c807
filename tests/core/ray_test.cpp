/// Tests of the ray record: which rays a structure may trace (`traceable`, written as one
/// arithmetic test).
#include <gtest/gtest.h>

#include <limits>

#include "penumbra/core/ray.h"

namespace penumbra {
namespace {

Ray make_ray(Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = kInfinity) {
  Ray r;
  r.o = o, r.d = d, r.tmin = tmin, r.tmax = tmax;
  return r;
}

TEST(Ray, TraceableIsAFiniteOriginAFiniteNonZeroDirectionAndAnInterval) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float big = std::numeric_limits<float>::max();
  const float tiny = std::numeric_limits<float>::denorm_min();
  const Vec3 o{0.5f, -2.0f, 3.0f}, d{0.0f, 0.6f, -0.8f};
  EXPECT_TRUE(traceable(make_ray(o, d)));
  // Every coordinate of the origin and the direction, replaced by each non-finite value.
  for (int field = 0; field < 6; ++field)
    for (float bad : {nan, kInfinity, -kInfinity}) {
      Vec3 oo = o, dd = d;
      (field < 3 ? oo : dd)[field % 3] = bad;
      EXPECT_FALSE(traceable(make_ray(oo, dd))) << field << " " << bad;
    }
  // Extreme finite values are traceable: their differences with themselves are exact zeros.
  EXPECT_TRUE(traceable(make_ray({big, -big, big}, {-big, big, tiny})));
  EXPECT_TRUE(traceable(make_ray({-0.0f, 0.0f, tiny}, {0.0f, -0.0f, -tiny})));
  // A zero direction, of either sign.
  EXPECT_FALSE(traceable(make_ray(o, {0.0f, 0.0f, 0.0f})));
  EXPECT_FALSE(traceable(make_ray(o, {-0.0f, 0.0f, -0.0f})));
  // The interval: empty, NaN at either end, a single point, infinite ends.
  EXPECT_FALSE(traceable(make_ray(o, d, 2.0f, 1.0f)));
  EXPECT_FALSE(traceable(make_ray(o, d, nan, 1.0f)));
  EXPECT_FALSE(traceable(make_ray(o, d, 0.0f, nan)));
  EXPECT_TRUE(traceable(make_ray(o, d, 1.0f, 1.0f)));
  EXPECT_TRUE(traceable(make_ray(o, d, -kInfinity, kInfinity)));
}

}  // namespace
}  // namespace penumbra
