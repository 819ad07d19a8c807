/// Tests of the compressed 8-wide node (bvh:nodes=compressed): every decoded child box contains
/// the exact one at every scale and offset, the quantisation is as tight as its grid allows,
/// empty slots stay empty, and the structure's parameters are checked.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "penumbra/accel/registry.h"
#include "penumbra/accel/wide_node.h"
#include "penumbra/core/error.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

WideNode<8> empty_node() {
  WideNode<8> n{};
  for (int i = 0; i < 8; ++i)
    for (int a = 0; a < 3; ++a) n.box[2 * a][i] = kInf, n.box[2 * a + 1][i] = -kInf;
  return n;
}

/// A node of `children` random boxes inside [offset, offset + size]^3.
WideNode<8> random_node(std::mt19937& rng, int children, float offset, float size) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  WideNode<8> n = empty_node();
  for (int i = 0; i < children; ++i) {
    for (int a = 0; a < 3; ++a) {
      float x = offset + size * u(rng), y = offset + size * u(rng);
      if (u(rng) < 0.1f) y = x;  // flat boxes occur (axis-aligned triangles)
      n.box[2 * a][i] = std::min(x, y), n.box[2 * a + 1][i] = std::max(x, y);
    }
    n.child[i] = 100 + i, n.count[i] = i % 3;
  }
  return n;
}

TEST(CompressedNode, DecodedBoxesContainTheExactOnesAtEveryScaleAndOffset) {
  std::mt19937 rng(7);
  int checked = 0;
  for (float size : {1e-20f, 1e-6f, 1.0f, 3.0e5f, 1e12f}) {
    for (float offset : {0.0f, -1.0f, 1e3f, -7e6f, 1e12f}) {
      for (int trial = 0; trial < 200; ++trial) {
        const int children = 1 + trial % 8;
        const WideNode<8> n = random_node(rng, children, offset, size);
        const CompressedNode c = compress_node(n);
        EXPECT_EQ(c.valid, (1u << children) - 1);
        for (int i = 0; i < children; ++i) {
          for (int a = 0; a < 3; ++a) {
            ASSERT_LE(c.decode(a, c.q[2 * a][i]), n.box[2 * a][i])
                << "size " << size << " offset " << offset << " child " << i << " axis " << a;
            ASSERT_GE(c.decode(a, c.q[2 * a + 1][i]), n.box[2 * a + 1][i])
                << "size " << size << " offset " << offset << " child " << i << " axis " << a;
            ++checked;
          }
          EXPECT_EQ(c.child[i], n.child[i]);
          EXPECT_EQ(c.count[i], n.count[i]);
        }
      }
    }
  }
  EXPECT_EQ(checked, 5 * 5 * 200 * 3 * 4.5);  // children 1..8 in turn: 4.5 on average
}

TEST(CompressedNode, QuantisationIsWithinOneGridStepOfTheExactPlanes) {
  // Near the origin the float rounding of the decode is far below the grid step, so each plane
  // lies within one step of its exact value, and the step is the smallest power of two whose
  // 255 steps span the node (times at most 2, when rounding falls short of the last plane).
  std::mt19937 rng(11);
  for (int trial = 0; trial < 500; ++trial) {
    const WideNode<8> n = random_node(rng, 8, 0.5f, 2.0f);
    const CompressedNode c = compress_node(n);
    for (int a = 0; a < 3; ++a) {
      float lo = kInf, hi = -kInf;
      for (int i = 0; i < 8; ++i)
        lo = std::min(lo, n.box[2 * a][i]), hi = std::max(hi, n.box[2 * a + 1][i]);
      const double step = c.step(a);
      EXPECT_EQ(c.origin[a], lo);
      EXPECT_GE(255.0 * step, double(hi) - lo);
      EXPECT_LE(255.0 * step, 4.0 * (double(hi) - lo));
      for (int i = 0; i < 8; ++i) {
        EXPECT_LT(double(n.box[2 * a][i]) - c.decode(a, c.q[2 * a][i]), step * 1.001);
        EXPECT_LT(double(c.decode(a, c.q[2 * a + 1][i])) - n.box[2 * a + 1][i], step * 1.001);
      }
    }
  }
}

TEST(CompressedNode, EmptySlotsAreNotValid) {
  WideNode<8> n = empty_node();
  for (int a = 0; a < 3; ++a) n.box[2 * a][3] = 1.0f, n.box[2 * a + 1][3] = 2.0f;
  n.child[3] = 42, n.count[3] = 5;
  const CompressedNode c = compress_node(n);
  EXPECT_EQ(c.valid, 1u << 3);
  EXPECT_EQ(c.child[3], 42u);
  EXPECT_EQ(c.count[3], 5u);
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(c.decode(a, c.q[2 * a][3]), 1.0f);
    EXPECT_GE(c.decode(a, c.q[2 * a + 1][3]), 2.0f);
  }
  EXPECT_EQ(compress_node(empty_node()).valid, 0u);
}

TEST(CompressedNode, HalvesTheNodeMemoryAndKeepsTheTree) {
  const PrimitiveSet prims = random_soup(20000, 5).prims;
  auto full = make_accelerator("bvh:width=8");  // the same tree as the compressed nodes'
  auto compressed = make_accelerator("bvh:nodes=compressed");
  full->build(prims);
  compressed->build(prims);
  EXPECT_EQ(compressed->name(), "bvh:nodes=compressed");
  const AccelStats f = full->stats(), c = compressed->stats();
  EXPECT_EQ(c.nodes, f.nodes);
  EXPECT_EQ(c.leaves, f.leaves);
  EXPECT_EQ(c.max_depth, f.max_depth);
  const size_t inner = f.nodes - f.leaves;
  EXPECT_EQ(f.bytes - c.bytes, inner * 128);  // 256-byte nodes become 128-byte ones
}

TEST(CompressedNode, ParametersAreChecked) {
  EXPECT_NO_THROW(make_accelerator("bvh:nodes=full"));
  EXPECT_NO_THROW(make_accelerator("bvh:nodes=compressed,leaf=4"));
  for (const char* bad : {"bvh:nodes=tiny", "bvh:nodes=compressed,width=4",
                          "bvh:width=2,nodes=compressed", "bvh4:nodes=compressed"}) {
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
  }
}

}  // namespace
}  // namespace penumbra::test
