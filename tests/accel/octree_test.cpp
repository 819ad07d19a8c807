/// Tests of the octree: parameters, the tree invariants (eight consecutive children, child masks,
/// exact leaf membership), the rule that stops subdividing when nothing is separated, rays in
/// node boundary planes, the mailbox and determinism across thread counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "penumbra/accel/build/prim_box_overlap.h"
#include "penumbra/accel/octree.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/parallel.h"
#include "penumbra/core/rng.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

Octree build_octree(const std::string& spec, const PrimitiveSet& prims) {
  Octree o(ParamList::parse(spec));
  o.build(prims);
  return o;
}

/// `b` grown by eight overlap pads on each side.
Bounds3 grown(const Bounds3& b) {
  Bounds3 g = b;
  for (int a = 0; a < 3; ++a) {
    const float pad = 8.0f * float(kOverlapPad) * (std::fabs(b.lo[a]) + std::fabs(b.hi[a]));
    g.lo[a] -= pad, g.hi[a] += pad;
  }
  return g;
}

/// A leaf as found by walking the tree: its box, depth and primitives.
struct LeafInfo {
  Bounds3 box;
  int depth;
  std::vector<uint32_t> prims;
};

/// Walks the tree checking the layout; returns the leaves.
std::vector<LeafInfo> walk(const Octree& o) {
  std::vector<LeafInfo> leaves;
  const auto nodes = o.nodes();
  const auto ids = o.leaf_ids();
  struct Item {
    uint32_t node;
    Vec3 lo;
    int depth;
  };
  std::vector<Item> stack{{0, o.root_bounds().lo, 0}};
  std::vector<int> seen(nodes.size(), 0);
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    EXPECT_LT(it.node, nodes.size());
    ++seen[it.node];
    const OctreeNode& n = nodes[it.node];
    if (!n.inner()) {
      EXPECT_LE(size_t(n.index) + n.count(), ids.size());
      const float s = o.size_at(it.depth);
      leaves.push_back({{it.lo, it.lo + Vec3(s)},
                        it.depth,
                        {ids.begin() + n.index, ids.begin() + n.index + n.count()}});
      continue;
    }
    EXPECT_LE(size_t(n.index) + 8, nodes.size()) << "eight consecutive children";
    for (unsigned c = 0; c < 8; ++c) {
      const OctreeNode& ch = nodes[n.index + c];
      const bool nonempty = ch.inner() || ch.count() > 0;
      EXPECT_EQ(bool(n.child_mask() >> c & 1u), nonempty) << "child mask";
      stack.push_back({n.index + c, o.child_lo(it.lo, it.depth, c), it.depth + 1});
    }
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; }))
      << "every node is reached exactly once";
  return leaves;
}

TEST(Octree, ParametersAreParsedAndRejectedStrictly) {
  EXPECT_EQ(make_accelerator("octree")->name(), "octree");
  EXPECT_EQ(make_accelerator("octree:depth=16,leaf=8")->name(), "octree:depth=16,leaf=8");
  for (const char* good :
       {"octree:leaf=1", "octree:depth=20", "octree:mailbox=0", "octree:trav=0", "octree:copy=0"})
    EXPECT_NO_THROW(make_accelerator(good)) << good;
  for (const char* bad : {"octree:leaf=0", "octree:depth=0", "octree:depth=21", "octree:mailbox=3",
                          "octree:leaf=x", "octree:size=4", "octree:trav=-1"})
    EXPECT_THROW(make_accelerator(bad), Error) << bad;
}

TEST(Octree, LeavesHoldExactlyTheOverlappingPrimitives) {
  for (const TestScene& s : {mixed_shapes(3), coplanar_grid(6, 6), room_with_boxes(8, 4),
                             degenerate_triangles(5), thin_and_large(6), random_soup(800, 7)}) {
    for (const char* spec : {"octree", "octree:leaf=2,depth=6"}) {
      SCOPED_TRACE(s.name + " " + spec);
      const Octree o = build_octree(spec, s.prims);
      const auto leaves = walk(o);
      size_t refs = 0, nonempty = 0;
      int max_depth = 0;
      for (const LeafInfo& l : leaves) {
        // Every primitive overlapping the leaf is listed (ascending); a listed one overlaps it
        // at least within a few pads (box shortcuts may keep one that misses by less).
        EXPECT_TRUE(std::is_sorted(l.prims.begin(), l.prims.end()));
        for (uint32_t id = 0; id < s.prims.size(); ++id) {
          if (s.prims.prim_bounds(id).empty()) continue;
          if (!referenced_by_structures(s.prims, id)) {  // never hit: left out
            EXPECT_FALSE(std::binary_search(l.prims.begin(), l.prims.end(), id)) << "prim " << id;
            continue;
          }
          const bool listed = std::binary_search(l.prims.begin(), l.prims.end(), id);
          if (prim_box_overlap(s.prims, id, l.box)) {
            ASSERT_TRUE(listed) << "prim " << id << " missing from a leaf at depth " << l.depth;
          } else if (listed) {
            ASSERT_TRUE(prim_box_overlap(s.prims, id, grown(l.box))) << "prim " << id;
          }
        }
        refs += l.prims.size();
        nonempty += !l.prims.empty();
        max_depth = std::max(max_depth, l.depth);
      }
      const AccelStats st = o.stats();
      EXPECT_EQ(st.nodes, o.nodes().size());
      EXPECT_EQ(st.leaves, nonempty);
      EXPECT_EQ(st.prim_refs, refs);
      EXPECT_EQ(st.max_depth, size_t(max_depth));
    }
  }
}

TEST(Octree, PrimitivesThroughOnePointDoNotBlowUp) {
  // 400 triangles fanning out from one vertex, and 300 copies of one triangle: subdividing
  // cannot separate them, and the build must stop instead of multiplying references.
  PrimitiveSet fan, copies;
  TriangleMesh m, c;
  Pcg32 rng(41, 2);
  const Vec3 apex(0.3f, 0.4f, 0.6f);
  for (int i = 0; i < 400; ++i) {
    m.positions.push_back(apex);
    for (int k = 0; k < 2; ++k)
      m.positions.push_back({rng.next_float(), rng.next_float(), rng.next_float()});
  }
  for (int i = 0; i < 300; ++i)
    c.positions.insert(c.positions.end(), {Vec3(0, 0, 0), Vec3(1, 0.2f, 0), Vec3(0.3f, 1, 0.5f)});
  for (TriangleMesh* t : {&m, &c})
    for (uint32_t i = 0; i < t->positions.size(); ++i) t->indices.push_back(i);
  fan.add_mesh(m, Transform(), 0);
  copies.add_mesh(c, Transform(), 0);
  const Octree a = build_octree("octree:leaf=1,depth=20", fan);
  EXPECT_LT(a.stats().prim_refs, 40u * 400u);
  EXPECT_LE(double(a.stats().prim_refs), kOctreeMaxRefsPerPrim * 400);
  EXPECT_LT(a.stats().nodes, 100'000u);
  const Octree b = build_octree("octree:leaf=1,depth=20", copies);
  EXPECT_EQ(b.stats().nodes, 1u) << "identical primitives: the root stays a leaf";
  for (const PrimitiveSet* p : {&fan, &copies}) {
    auto o = make_accelerator("octree:leaf=1,depth=20"), brute = make_accelerator("brute");
    o->build(*p);
    brute->build(*p);
    for (const Ray& r : mixed_rays(*p, 3000, 9)) {
      Hit h1, h2;
      ASSERT_EQ(o->intersect(r, h1), brute->intersect(r, h2));
      EXPECT_EQ(h1.t, h2.t);
    }
  }
}

TEST(Octree, RaysInNodeBoundaryPlanesMatchBrute) {
  // Rays lying exactly in the octree's split planes (taken from the built tree), through shared
  // edges and coplanar quads, and through a triangle lying in the root's mid plane.
  TestScene s = coplanar_grid(8, 8);
  const Octree probe = build_octree("octree", s.prims);
  const Vec3 mid = probe.root_bounds().lo + Vec3(probe.size_at(1));
  TriangleMesh m;
  m.positions = {{mid.x, 1.2f, 0.3f}, {mid.x, 6.7f, 0.3f}, {mid.x, 3.3f, 0.9f}};
  m.indices = {0, 1, 2};
  s.prims.add_mesh(m, Transform(), 3);
  for (const char* spec : {"octree", "octree:leaf=1", "octree:leaf=2,depth=4"}) {
    const Octree o = build_octree(spec, s.prims);
    ASSERT_EQ(o.root_bounds().lo + Vec3(o.size_at(1)), mid) << "the new triangle keeps the root";
    Pcg32 rng(5, 6);
    const auto plane = [&](int axis) {  // a split plane at depth 1..3
      const int d = 1 + int(rng.next_bounded(3));
      const int k = int(rng.next_bounded(1u << d));
      return o.root_bounds().lo[axis] + float(k) * o.size_at(d);
    };
    std::vector<Ray> rays;
    for (int i = 0; i < 20000; ++i) {
      const float fx = rng.next_float() * 8.5f, fy = rng.next_float() * 8.5f;
      const float dx = rng.next_float() - 0.5f, dy = rng.next_float() - 0.5f;
      switch (i % 4) {
        case 0:
          rays.push_back({{plane(0), plane(1), -1.0f}, {0, 0, 1}});
          break;
        case 1:
          rays.push_back({{plane(0), fy, 3.0f}, {0, dy, -1}});
          break;
        case 2:
          rays.push_back({{fx, plane(1), -2.0f}, {dx, 0, 1}});
          break;
        default:
          rays.push_back({{-1.0f, fy, 0.5f}, {1, dy, 0.1f * dx}});
          break;
      }
    }
    auto brute = make_accelerator("brute");
    brute->build(s.prims);
    size_t differ = 0;
    for (const Ray& r : rays) {
      Hit a, b;
      o.intersect(r, a);
      brute->intersect(r, b);
      differ += a.valid() != b.valid() || a.t != b.t || o.occluded(r) != b.valid();
    }
    EXPECT_EQ(differ, 0u) << spec;
  }
}

TEST(Octree, MailboxAndCopyDoNotChangeResults) {
  const TestScene s = random_soup(3000, 21);
  const auto rays = mixed_rays(s.prims, 20000, 22);
  auto ref = make_accelerator("octree");
  ref->build(s.prims);
  for (const char* spec : {"octree:mailbox=0", "octree:mailbox=8", "octree:mailbox=64",
                           "octree:copy=0", "octree:leaf=1"}) {
    auto o = make_accelerator(spec);
    o->build(s.prims);
    size_t differ = 0;
    for (const Ray& r : rays) {
      Hit a, b;
      o->intersect(r, a);
      ref->intersect(r, b);
      differ += a.valid() != b.valid() || a.t != b.t;
    }
    EXPECT_EQ(differ, 0u) << spec;
  }
}

TEST(Octree, BuildDoesNotDependOnTheThreadCount) {
  const TestScene s = torus(120, 60);  // large enough for the chunked split of big nodes
  std::vector<OctreeNode> nodes[2];
  std::vector<uint32_t> ids[2];
  for (int k = 0; k < 2; ++k) {
    const ThreadLimit limit(k == 0 ? 1 : 0);
    const Octree o = build_octree("octree", s.prims);
    for (const OctreeNode& n : o.nodes()) nodes[k].push_back(n);
    ids[k].assign(o.leaf_ids().begin(), o.leaf_ids().end());
  }
  ASSERT_EQ(nodes[0].size(), nodes[1].size());
  for (size_t i = 0; i < nodes[0].size(); ++i) {
    EXPECT_EQ(nodes[0][i].index, nodes[1][i].index);
    EXPECT_EQ(nodes[0][i].info, nodes[1][i].info);
  }
  EXPECT_EQ(ids[0], ids[1]);
}

}  // namespace
}  // namespace penumbra::test
