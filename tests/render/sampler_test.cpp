#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/rng.h"
#include "penumbra/render/sampler/low_discrepancy.h"
#include "penumbra/render/sampler/sampler_registry.h"
#include "penumbra/render/sampler/sobol_sampler.h"
#include "penumbra/render/sampler/stratified_sampler.h"
#include "penumbra/render/sampling.h"

namespace penumbra {
namespace {

// The pixel dimensions and a later 2D dimension: each of the nx x ny strata gets exactly one point.
TEST(JitteredSampler, EachStratumReceivesExactlyOneSample) {
  for (int spp : {16, 12, 7, 64}) {
    StratifiedSampler s(spp, 42, true);
    const int nx = s.strata_x(), ny = s.strata_y();
    ASSERT_EQ(nx * ny, spp);
    for (int pixel = 0; pixel < 5; ++pixel) {
      std::set<int> pixel_strata, lens_strata, time_strata;
      for (int i = 0; i < spp; ++i) {
        s.start_pixel_sample(pixel, 3, i);
        const Vec2 p = s.get_pixel_2d(), lens = s.get_2d();
        const float t = s.get_1d();
        pixel_strata.insert(int(p.x * nx) + nx * int(p.y * ny));
        lens_strata.insert(int(lens.x * nx) + nx * int(lens.y * ny));
        time_strata.insert(int(t * spp));
      }
      EXPECT_EQ(int(pixel_strata.size()), spp);
      EXPECT_EQ(int(lens_strata.size()), spp);
      EXPECT_EQ(int(time_strata.size()), spp);
    }
  }
}

TEST(RegularSampler, PointsAreTheStratumCentres) {
  StratifiedSampler s(16, 1, false);
  for (int i = 0; i < 16; ++i) {
    s.start_pixel_sample(0, 0, i);
    const Vec2 p = s.get_pixel_2d();
    EXPECT_FLOAT_EQ(p.x, (float(i % 4) + 0.5f) / 4.0f);
    EXPECT_FLOAT_EQ(p.y, (float(i / 4) + 0.5f) / 4.0f);
  }
}

TEST(LowDiscrepancy, SobolDimensionsMatchTheirDefinition) {
  // Van der Corput (radical inverse in base 2) and Sobol's second dimension in direct (not
  // Gray-code) order: x_i = XOR of v_k over the set bits k of i, v_1 = 1/2, v_k+1 = v_k ^ v_k / 2.
  const double vdc[8] = {0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  const double s1[8] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
  for (uint32_t i = 0; i < 8; ++i) {
    EXPECT_DOUBLE_EQ(sobol_dim0(i) * 0x1p-32, vdc[i]);
    EXPECT_DOUBLE_EQ(sobol_dim1(i) * 0x1p-32, s1[i]);
  }
  // The radical inverse of i is the binary digits of i mirrored about the point.
  for (uint32_t i = 1; i < 1000; ++i) {
    double r = 0, f = 0.5;
    for (uint32_t k = i; k; k >>= 1, f *= 0.5) r += (k & 1) * f;
    EXPECT_DOUBLE_EQ(sobol_dim0(i) * 0x1p-32, r);
  }
}

// The loop-free second dimension against its definition, on every index a pixel can have up to
// 2^16 spp and on random 32-bit ones; and the scramble built on it against owen_scramble.
TEST(LowDiscrepancy, SobolDim1ReversedIsTheBitReversedSecondDimension) {
  for (uint32_t i = 0; i < (1u << 16); ++i)
    ASSERT_EQ(sobol_dim1_reversed(i), reverse_bits(sobol_dim1(i))) << "i " << i;
  Pcg32 rng(5);
  for (int k = 0; k < 100000; ++k) {
    const uint32_t i = rng.next_u32(), seed = rng.next_u32();
    ASSERT_EQ(sobol_dim1_reversed(i), reverse_bits(sobol_dim1(i))) << "i " << i;
    ASSERT_EQ(owen_scrambled_dim1(i, seed), owen_scramble(sobol_dim1(i), seed)) << "i " << i;
  }
}

/// The Sobol' sampler's values by their definition, one pair at a time (the sampler computes
/// them in batches): pair s (from 1) has seeds lo_s, hi_s and yk_s; its point is the first Sobol'
/// dimension of the index shuffled by lo_s, scrambled by hi_s, and the second scrambled by yk_s.
/// get_2d takes the next pair's point; get_1d takes the second coordinate of the pair the
/// previous unpaired get_1d opened, else opens the next pair and takes its first.
class ReferenceSobol {
 public:
  ReferenceSobol(int spp, uint64_t seed) : spp_(spp), seed_(seed) {
    for (int m = 0; m < 31; ++m)
      if (spp == (1 << m)) log2_spp_ = m;
  }
  void start(int px, int py, int index) {
    pixel_hash_ = hash_combine(seed_, (uint64_t(uint32_t(py)) << 32) | uint32_t(px));
    index_ = uint32_t(index);
    pair_ = 0;
    pending_ = false;
  }
  float get_1d() {
    if (pending_) {
      pending_ = false;
      return pending_y_;
    }
    const Vec2 p = next_pair();
    pending_ = true;
    pending_y_ = p.y;
    return p.x;
  }
  Vec2 get_2d() { return next_pair(); }
  /// Pair p (from 1) of the current pixel sample.
  Vec2 pair(uint32_t p) const {
    const uint32_t g = p * 0x9e3779b9u;
    const uint32_t lo = mix32(uint32_t(pixel_hash_) + g);
    const uint32_t hi = mix32(uint32_t(pixel_hash_ >> 32) + g);
    const uint32_t yk = mix32(uint32_t(pixel_hash_ >> 32) + g + 0x6a09e667u);
    const uint32_t i = shuffled(lo);
    return {fraction_to_float(owen_scramble(sobol_dim0(i), hi)),
            fraction_to_float(owen_scramble(sobol_dim1(i), yk))};
  }

 private:
  Vec2 next_pair() { return pair(++pair_); }
  uint32_t shuffled(uint32_t seed) const {
    if (log2_spp_ == 0) return 0;
    if (log2_spp_ > 0) {
      const int shift = 32 - log2_spp_;
      return owen_scramble(index_ << shift, seed) >> shift;
    }
    return permutation_element(index_, uint32_t(spp_), seed);
  }
  int spp_, log2_spp_ = -1;
  uint64_t seed_, pixel_hash_ = 0;
  uint32_t index_ = 0, pair_ = 0;
  bool pending_ = false;
  float pending_y_ = 0;
};

// Bit for bit against the definition, for random sequences of 1D and 2D requests long enough to
// cross several batches, with spp a power of two, one, and neither.
TEST(SobolSampler, BatchedValuesMatchTheDefinition) {
  Pcg32 rng(17);
  for (int spp : {1, 2, 64, 1024, 3, 100}) {
    SobolSampler sampler(spp, 42);
    ReferenceSobol ref(spp, 42);
    for (int trial = 0; trial < 200; ++trial) {
      const int px = int(rng.next_bounded(512)), py = int(rng.next_bounded(512));
      const int index = int(rng.next_bounded(uint32_t(spp)));
      sampler.start_pixel_sample(px, py, index);
      ref.start(px, py, index);
      const int calls = int(rng.next_bounded(60));
      for (int c = 0; c < calls; ++c) {
        if (rng.next_u32() & 1) {
          ASSERT_EQ(sampler.get_1d(), ref.get_1d()) << "spp " << spp << " call " << c;
        } else {
          const Vec2 a = sampler.get_2d(), b = ref.get_2d();
          ASSERT_EQ(a.x, b.x) << "spp " << spp << " call " << c;
          ASSERT_EQ(a.y, b.y) << "spp " << spp << " call " << c;
        }
      }
    }
  }
}

// A caller that computes a sample's pairs itself (PathLanes, with SobolLanes) hands the sampler
// its state back with resume(): the next draws continue from there, also far beyond the first
// batch of pairs that the sampler never computed, and a pending number is returned first.
TEST(SobolSampler, ResumeContinuesAtThePairGiven) {
  for (int spp : {64, 100}) {
    SobolSampler sampler(spp, 9);
    ReferenceSobol ref(spp, 9);
    sampler.start_pixel_sample(3, 4, 5);
    ref.start(3, 4, 5);
    EXPECT_EQ(sampler.next_pair(), SobolSampler::kFirstPair);
    EXPECT_FALSE(sampler.has_pending());
    (void)sampler.get_1d();
    EXPECT_TRUE(sampler.has_pending());
    EXPECT_EQ(sampler.pending(), ref.pair(1).y);
    EXPECT_EQ(sampler.next_pair(), 2u);
    for (uint32_t skip_to : {40u, 17u, 3u}) {
      sampler.start_pixel_sample(3, 4, 5);
      sampler.resume(skip_to, true, 0.25f);
      EXPECT_EQ(sampler.get_1d(), 0.25f);
      const Vec2 a = sampler.get_2d(), b = ref.pair(skip_to);
      EXPECT_EQ(a.x, b.x) << skip_to;
      EXPECT_EQ(a.y, b.y) << skip_to;
      EXPECT_EQ(sampler.get_1d(), ref.pair(skip_to + 1).x) << skip_to;
      EXPECT_EQ(sampler.next_pair(), skip_to + 2);
    }
  }
}

// SobolLanes against the definition: eight samples of random pixels and indices, their pairs
// computed lane by lane (compute3) and with lanes gathered into one vector (compute), for spp a
// power of two, one, and neither.
TEST(SobolLanes, LaneValuesMatchTheDefinition) {
  Pcg32 rng(23);
  for (int spp : {1, 2, 64, 1024, 3, 100}) {
    std::vector<SobolSampler> samplers(8, SobolSampler(spp, 42));
    std::vector<ReferenceSobol> refs(8, ReferenceSobol(spp, 42));
    SobolLanes lanes(samplers[0]);
    for (int trial = 0; trial < 50; ++trial) {
      for (int k = 0; k < 8; ++k) {
        const int px = int(rng.next_bounded(512)), py = int(rng.next_bounded(512));
        const int index = int(rng.next_bounded(uint32_t(spp)));
        samplers[size_t(k)].start_pixel_sample(px, py, index);
        refs[size_t(k)].start(px, py, index);
        lanes.set(k, samplers[size_t(k)]);
      }
      lanes::U8 first, lane, pair;
      for (int k = 0; k < 8; ++k) {
        first[k] = 1 + rng.next_bounded(200);
        lane[k] = rng.next_bounded(8);
        pair[k] = 1 + rng.next_bounded(200);
      }
      lanes::F8 x[3], y[3];
      lanes.compute3(first, x, y);
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 8; ++k) {
          const Vec2 want = refs[size_t(k)].pair(first[k] + uint32_t(j));
          ASSERT_EQ(x[j][k], want.x) << "spp " << spp << " lane " << k << " pair +" << j;
          ASSERT_EQ(y[j][k], want.y) << "spp " << spp << " lane " << k << " pair +" << j;
        }
      lanes::F8 gx, gy;
      lanes.compute(lane, pair, gx, gy);
      for (int k = 0; k < 8; ++k) {
        const Vec2 want = refs[lane[k]].pair(pair[k]);
        ASSERT_EQ(gx[k], want.x) << "spp " << spp << " slot " << k;
        ASSERT_EQ(gy[k], want.y) << "spp " << spp << " slot " << k;
      }
    }
  }
}

#if defined(__AVX2__)
// The AVX2 lane-wise bit reversal against the scalar one: 0, all ones, every single bit, every
// byte value in every byte position, and many random words.
TEST(LowDiscrepancy, LaneWiseBitReversalMatchesTheScalarOne) {
  std::vector<uint32_t> words = {0u, ~0u, 0x80000001u, 0x0f0f0f0fu, 0xf0f0f0f0u, 0x12345678u};
  for (int b = 0; b < 32; ++b) words.push_back(1u << b), words.push_back(~(1u << b));
  for (uint32_t v = 0; v < 256; ++v)
    for (int pos = 0; pos < 32; pos += 8) words.push_back(v << pos);
  Pcg32 rng(5);
  for (int i = 0; i < 100000; ++i) words.push_back(rng.next_u32());
  while (words.size() % 8) words.push_back(rng.next_u32());
  for (size_t i = 0; i < words.size(); i += 8) {
    U32x8 x;
    for (int k = 0; k < 8; ++k) x[k] = words[i + size_t(k)];
    const U32x8 r = reverse_bits(x);
    for (int k = 0; k < 8; ++k)
      ASSERT_EQ(r[k], reverse_bits(words[i + size_t(k)])) << std::hex << words[i + size_t(k)];
  }
}
#endif

// The concentric map's polynomial sine and cosine against libm over the whole quarter interval:
// within two float ulps of values near 1 (2.4e-7).
TEST(Sampling, QuarterSineAndCosineMatchLibm) {
  const double quarter = 3.14159265358979323846 / 4.0;
  double worst = 0;
  for (int k = -100000; k <= 100000; ++k) {
    const float a = float(quarter * k / 100000.0);
    float s, c;
    sin_cos_quarter(a, s, c);
    worst = std::max(worst, std::fabs(double(s) - std::sin(double(a))));
    worst = std::max(worst, std::fabs(double(c) - std::cos(double(a))));
  }
  EXPECT_LE(worst, 2.4e-7);
}

TEST(LowDiscrepancy, PermutationElementIsAPermutation) {
  for (uint32_t n : {1u, 2u, 7u, 16u, 100u, 1000u}) {
    std::set<uint32_t> seen;
    for (uint32_t i = 0; i < n; ++i) seen.insert(permutation_element(i, n, 12345));
    EXPECT_EQ(seen.size(), n);
    EXPECT_LT(*seen.rbegin(), n);
  }
}

// With spp = 2^m the Owen-scrambled points of a pixel form a (0,m,2)-net in every 2D projection:
// exactly one point in each elementary interval of area 2^-m.
TEST(SobolSampler, EveryDimensionPairIsA0m2Net) {
  const auto sampler = make_sampler("sobol", 64, 7);
  for (int pixel = 0; pixel < 4; ++pixel)
    for (int pair = 0; pair < 4; ++pair) {
      std::vector<Vec2> pts;
      for (int i = 0; i < 64; ++i) {
        sampler->start_pixel_sample(pixel, 0, i);
        Vec2 p;
        for (int d = 0; d <= pair; ++d) p = sampler->get_2d();
        pts.push_back(p);
      }
      for (int k = 0; k <= 6; ++k) {  // intervals of 2^k by 2^(6-k) cells
        const int bx = 1 << k, by = 1 << (6 - k);
        std::set<int> cells;
        for (const Vec2& p : pts) cells.insert(int(p.x * bx) + bx * int(p.y * by));
        EXPECT_EQ(cells.size(), 64u) << "pixel " << pixel << " pair " << pair << " k " << k;
      }
    }
}

// A path vertex's draws: a 2D light pair, a 1D lobe number, a 2D BSDF pair and a 1D roulette
// number. The two 1D numbers share one pair, so across a pixel's 2^m samples they too form a
// (0,m,2)-net, as do both 2D draws, at every vertex.
TEST(SobolSampler, TwoOneDimensionalDrawsShareANet) {
  const auto sampler = make_sampler("sobol", 64, 3);
  for (int pixel = 0; pixel < 3; ++pixel)
    for (int vertex = 0; vertex < 4; ++vertex) {
      std::vector<Vec2> light, bsdf, ones;
      for (int i = 0; i < 64; ++i) {
        sampler->start_pixel_sample(pixel, 2, i);
        for (int v = 0; v <= vertex; ++v) {
          const Vec2 l = sampler->get_2d();
          const float uc = sampler->get_1d();
          const Vec2 b = sampler->get_2d();
          const float rr = sampler->get_1d();
          if (v == vertex) light.push_back(l), bsdf.push_back(b), ones.push_back({uc, rr});
        }
      }
      for (const auto* pts : {&light, &bsdf, &ones})
        for (int k = 0; k <= 6; ++k) {
          const int bx = 1 << k, by = 1 << (6 - k);
          std::set<int> cells;
          for (const Vec2& p : *pts) cells.insert(int(p.x * bx) + bx * int(p.y * by));
          EXPECT_EQ(cells.size(), 64u) << "pixel " << pixel << " vertex " << vertex << " k " << k;
        }
    }
}

// Progressive: with spp = 2^m the first 2^k samples of a pixel (in index order, as passes take
// them) are themselves a (0,k,2)-net in every 2D projection, for every k, because the nested
// uniform shuffle maps indices [0, 2^k) onto an aligned block of 2^k points of the sequence.
TEST(SobolSampler, EveryPowerOfTwoPrefixIsA0k2Net) {
  const auto sampler = make_sampler("sobol", 256, 11);
  for (int pixel = 0; pixel < 3; ++pixel)
    for (int pair = 0; pair < 5; ++pair)
      for (int m = 0; m <= 8; ++m) {
        const int n = 1 << m;
        std::vector<Vec2> pts;
        for (int i = 0; i < n; ++i) {
          sampler->start_pixel_sample(pixel, 1, i);
          Vec2 p;
          for (int d = 0; d <= pair; ++d) p = sampler->get_2d();
          pts.push_back(p);
        }
        for (int k = 0; k <= m; ++k) {
          const int bx = 1 << k, by = 1 << (m - k);
          std::set<int> cells;
          for (const Vec2& p : pts) cells.insert(int(p.x * bx) + bx * int(p.y * by));
          EXPECT_EQ(cells.size(), size_t(n))
              << "pixel " << pixel << " pair " << pair << " prefix " << n << " k " << k;
        }
      }
}

TEST(SamplerRegistry, UnknownNamesListTheValidOnes) {
  try {
    make_sampler("halton7", 4, 0);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("jittered"), std::string::npos);
  }
  EXPECT_THROW(make_sampler("jittered:foo=1", 4, 0), Error);
  EXPECT_NO_THROW(make_sampler("random", 4, 0));
}

/// Root-mean-square error of the sampler's estimate of a smooth integral over [0,1]^2, over many
/// pixels (independent replicates).
double rms_error(const std::string& name, int spp) {
  const auto s = make_sampler(name, spp, 99);
  // f(x, y) = exp(x) sin(pi y / 2) ... integral (e - 1) (2 / pi).
  const double exact = (std::exp(1.0) - 1.0) * 2.0 / 3.14159265358979323846;
  double sum2 = 0;
  const int pixels = 400;
  for (int p = 0; p < pixels; ++p) {
    double est = 0;
    for (int i = 0; i < spp; ++i) {
      s->start_pixel_sample(p, 1, i);
      s->get_pixel_2d();
      const Vec2 u = s->get_2d();
      est += std::exp(double(u.x)) * std::sin(3.14159265358979323846 * u.y / 2.0);
    }
    const double err = est / spp - exact;
    sum2 += err * err;
  }
  return std::sqrt(sum2 / pixels);
}

/// Least-squares slope of log(error) against log(spp).
double convergence_slope(const std::string& name) {
  const int spps[] = {16, 64, 256, 1024};
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int spp : spps) {
    const double x = std::log(double(spp)), y = std::log(rms_error(name, spp));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double n = 4;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Random sampling converges as N^-1/2; jittered sampling of a smooth 2D integrand as N^-1
// (N^-1/2 - 1/d with d = 2). The fitted slopes are checked to a band of about 0.15 around those
// values (400 replicates give the RMS error to about 3.5%, i.e. 0.05 in the log slope).
TEST(Samplers, JitteredErrorFallsFasterThanRandom) {
  const double random = convergence_slope("independent");
  const double jittered = convergence_slope("jittered");
  const double sobol = convergence_slope("sobol");
  EXPECT_NEAR(random, -0.5, 0.15);
  EXPECT_NEAR(jittered, -1.0, 0.15);
  EXPECT_LT(sobol, -0.85);  // Owen-scrambled nets: at least as fast as jittering (up to N^-1.5)
  EXPECT_LT(jittered, random - 0.3);
}

}  // namespace
}  // namespace penumbra
