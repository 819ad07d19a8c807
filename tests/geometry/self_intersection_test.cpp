// Rays leaving a surface must never hit that surface again (no shadow acne).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "penumbra/core/rng.h"
#include "penumbra/geometry/float_error.h"
#include "penumbra/geometry/triangle.h"

namespace penumbra {
namespace {

// The bit-pattern successors agree with std::nextafter on every kind of float: zeros of both
// signs, denormals, the largest finite values, infinities, NaNs, and random bit patterns.
TEST(NextFloat, MatchesNextafterOnEveryKindOfFloat) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  std::vector<uint32_t> bits = {0x00000000u, 0x80000000u, 0x00000001u, 0x80000001u, 0x007fffffu,
                                0x807fffffu, 0x00800000u, 0x80800000u, 0x3f800000u, 0xbf800000u,
                                0x7f7fffffu, 0xff7fffffu, 0x7f800000u, 0xff800000u, 0x7fc00000u,
                                0xffc00000u, 0x7f800001u, 0xff800001u, 0x7fffffffu};
  Pcg32 rng(11);
  for (int i = 0; i < 1000000; ++i) bits.push_back(rng.next_u32());
  for (const uint32_t b : bits) {
    const float v = std::bit_cast<float>(b);
    const float up = next_float_up(v), down = next_float_down(v);
    if (std::isnan(v)) {
      EXPECT_TRUE(std::isnan(up) && std::isnan(down)) << std::hex << b;
      continue;
    }
    ASSERT_EQ(std::bit_cast<uint32_t>(up), std::bit_cast<uint32_t>(std::nextafter(v, inf)))
        << std::hex << b;
    ASSERT_EQ(std::bit_cast<uint32_t>(down), std::bit_cast<uint32_t>(std::nextafter(v, -inf)))
        << std::hex << b;
  }
}

// The branch-free offset against its definition with the library's nextafter, component by
// component: signed zeros, denormals, the largest floats, infinities and NaN among the points,
// offsets of every sign (normals with zero components, directions on either side), bit for bit.
TEST(SelfIntersection, OffsetOriginMatchesNextafterDefinition) {
  const float specials[] = {0.0f,     -0.0f,    1e-45f,   -1e-45f, 1e-38f,  -1e-38f,
                            1.0f,     -1.0f,    3.4e38f,  -3.4e38f,
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN()};
  Pcg32 rng(9);
  const auto pick = [&](bool special) {
    if (special) return specials[rng.next_bounded(sizeof specials / sizeof specials[0])];
    return (rng.next_float() - 0.5f) * std::ldexp(1.0f, int(rng.next_bounded(40)) - 20);
  };
  const auto same = [](float a, float b) {
    return std::isnan(a) ? std::isnan(b) : std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
  };
  for (int i = 0; i < 1000000; ++i) {
    const bool sp = (i & 3) == 0;
    const Vec3 p{pick(sp), pick(sp), pick(sp)};
    const Vec3 err{std::fabs(pick(false)), std::fabs(pick(false)), std::fabs(pick(false))};
    Vec3 n{pick(false), pick(false), pick(false)};
    for (int a = 0; a < 3; ++a)
      if (rng.next_bounded(3) == 0) n[a] = rng.next_bounded(2) ? 0.0f : -0.0f;
    const Vec3 w{pick(false), pick(false), pick(false)};
    // The definition: p moved by +-n (n . err) to the side of w, then one float further along
    // each component's offset.
    const float dd = dot(abs(n), err);
    Vec3 offset = n * dd;
    if (dot(w, n) < 0.0f) offset = -offset;
    asm("" : "+m"(offset));  // no fused multiply-add: the sum rounds the rounded product
    const Vec3 moved = p + offset;
    const Vec3 got = offset_ray_origin(p, err, n, w);
    for (int a = 0; a < 3; ++a) {
      const float want = offset[a] > 0.0f   ? std::nextafter(moved[a], HUGE_VALF)
                         : offset[a] < 0.0f ? std::nextafter(moved[a], -HUGE_VALF)
                                            : moved[a];
      ASSERT_TRUE(same(got[a], want)) << "i " << i << " axis " << a << " p " << p[a] << " offset "
                                      << offset[a] << " got " << got[a] << " want " << want;
    }
  }
}

// Points exactly on an axis-aligned wall (x = 0, like the Cornell box's green wall) get no offset
// from their (zero) error bound; the triangle test's own bound on t must reject the re-hit.
TEST(SelfIntersection, RaysFromAnAxisAlignedWallDoNotHitIt) {
  const Vec3 a{0, 0, 559.2f}, b{0, 0, 0}, c{0, 548.8f, 0};
  Pcg32 rng(5);
  int hits = 0;
  for (int i = 0; i < 200000; ++i) {
    const float u = rng.next_float(), v = rng.next_float() * (1 - u);
    const Vec3 p = a * (1 - u - v) + b * u + c * v;
    const Vec3 err = (abs(a * (1 - u - v)) + abs(b * u) + abs(c * v)) * gamma(7);
    const Vec3 target{278.0f * rng.next_float() + 1.0f, 548.8f * rng.next_float(),
                      559.2f * rng.next_float()};
    Ray r;
    r.o = offset_ray_origin(p, err, {1, 0, 0}, target - p);
    r.d = target - r.o;
    const PreparedRay pr(r);
    float t, bu, bv;
    if (intersect_triangle(pr, a, b, c, 0.0f, 1.0f, t, bu, bv)) ++hits;
  }
  EXPECT_EQ(hits, 0);
}

// The same for an arbitrarily oriented triangle far from the origin.
TEST(SelfIntersection, RaysFromATiltedTriangleFarAwayDoNotHitIt) {
  const Vec3 a{10000.3f, -2000.7f, 5000.1f}, b{10003.9f, -1998.2f, 5001.7f},
             c{10001.1f, -1996.5f, 4999.0f};
  const Vec3 n = normalize(cross(b - a, c - a));
  Pcg32 rng(6);
  int hits = 0;
  for (int i = 0; i < 200000; ++i) {
    const float u = rng.next_float(), v = rng.next_float() * (1 - u);
    const Vec3 p = a * (1 - u - v) + b * u + c * v;
    const Vec3 err = (abs(a * (1 - u - v)) + abs(b * u) + abs(c * v)) * gamma(7);
    Vec3 d{rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f};
    if (dot(d, n) < 0) d = -d;  // leaving on the front side
    Ray r;
    r.o = offset_ray_origin(p, err, n, d);
    r.d = d;
    const PreparedRay pr(r);
    float t, bu, bv;
    if (intersect_triangle(pr, a, b, c, 0.0f, kInfinity, t, bu, bv)) ++hits;
  }
  EXPECT_EQ(hits, 0);
}

}  // namespace
}  // namespace penumbra
