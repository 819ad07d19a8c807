#include "penumbra/accel/small_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace penumbra::test {
namespace {

// Every order of up to eight distinct keys, and every sequence of up to eight drawn from three
// values (ties), comes out sorted: the networks of three and four and the insertion sort.
TEST(SmallSort, SortsEveryOrderOfUpToEightKeys) {
  for (int n = 0; n <= 8; ++n) {
    std::vector<uint64_t> perm(static_cast<size_t>(n));
    std::iota(perm.begin(), perm.end(), uint64_t(100));
    do {
      std::vector<uint64_t> key = perm;
      sort_small(key.data(), n);
      ASSERT_TRUE(std::is_sorted(key.begin(), key.end())) << n;
      ASSERT_TRUE(std::is_permutation(key.begin(), key.end(), perm.begin())) << n;
    } while (std::next_permutation(perm.begin(), perm.end()));
    int tuples = 1;
    for (int i = 0; i < n; ++i) tuples *= 3;
    for (int t = 0; t < tuples; ++t) {
      std::vector<uint64_t> key(static_cast<size_t>(n));
      for (int i = 0, r = t; i < n; ++i, r /= 3) key[size_t(i)] = uint64_t(r % 3);
      std::vector<uint64_t> want = key;
      std::sort(want.begin(), want.end());
      sort_small(key.data(), n);
      ASSERT_EQ(key, want) << n << " " << t;
    }
  }
}

// distance_key orders by distance (negative, zero, positive, infinite), then by lane, and gives
// the lane back.
TEST(SmallSort, DistanceKeysFollowTheDistancesThenTheLanes) {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> d = {-inf,   -3e30f, -2.5f, -1e-40f, -0.0f, 0.0f,
                                1e-40f, 1e-3f,  1.0f,  1.5f,    3e30f, inf};
  for (size_t a = 0; a < d.size(); ++a)
    for (size_t b = 0; b < d.size(); ++b)
      for (int la = 0; la < 8; ++la)
        for (int lb = 0; lb < 8; ++lb) {
          const uint64_t ka = distance_key(d[a], la), kb = distance_key(d[b], lb);
          EXPECT_EQ(key_lane(ka), la);
          if (a != b)
            EXPECT_EQ(ka < kb, a < b) << d[a] << " " << d[b];
          else
            EXPECT_EQ(ka < kb, la < lb) << d[a];
        }
}

}  // namespace
}  // namespace penumbra::test
