/// The two-level structure (accel/instance_bvh.h): instanced scenes through every registered
/// bottom-level structure against brute force as the bottom level (the same hits), and
/// against the same scene flattened into world space (the same surfaces within rounding), for
/// rotated, non-uniformly scaled, mirrored and translated instances. With brute force at both
/// levels of the reference, any difference comes from the bottom-level structure alone.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "penumbra/accel/instance_bvh.h"
#include "penumbra/accel/registry.h"
#include "penumbra/core/rng.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

/// A closed UV sphere mesh of radius 1 (outward winding), `rings` x `sides` quads split in two.
TriangleMesh ball_mesh(int rings, int sides) {
  TriangleMesh m;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const float th = std::numbers::pi_v<float> * float(i) / float(rings);
      const float ph = 2 * std::numbers::pi_v<float> * float(j) / float(sides);
      m.positions.push_back(
          {std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const uint32_t a = uint32_t(i * sides + j), b = uint32_t(i * sides + (j + 1) % sides);
      const uint32_t c = a + uint32_t(sides), d = b + uint32_t(sides);
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
  return m;
}

/// The object's primitives under `m` appended to `out`: a ball mesh, two parallelograms and
/// (when `spheres`, for similarity transforms only) a sphere.
void add_object(PrimitiveSet& out, const Transform& m, bool spheres) {
  static const TriangleMesh ball = ball_mesh(12, 16);
  out.add_mesh(ball, m, 0);
  const auto quad = [&](Vec3 p, Vec3 e1, Vec3 e2) {
    out.add_quad({m.point(p), m.vector(e1), m.vector(e2)}, 1);
  };
  quad({-2, -2, -1.5f}, {4, 0, 0}, {0, 3, 0});
  quad({1.2f, -1, -1}, {0, 2, 0}, {0, 0.5f, 2});
  if (spheres)
    out.add_sphere({m.point({-1.6f, 1.2f, 0.5f}), 0.6f * length(m.vector({1, 0, 0}))}, 2);
}

/// Instance transforms: translated, rotated, non-uniformly scaled, mirrored, and combinations.
struct Placement {
  Transform to_world;
  bool similarity;
};
std::vector<Placement> placements() {
  std::vector<Placement> p;
  Pcg32 rng(7, 3);
  for (int i = 0; i < 40; ++i) {
    const Vec3 at{float(i % 5) * 5.0f, float((i / 5) % 4) * 5.0f, float(i / 20) * 6.0f};
    const float angle = 360.0f * rng.next_float();
    const Vec3 axis{rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() + 0.1f};
    switch (i % 4) {
      case 0:  // translated only
        p.push_back({translate(at), true});
        break;
      case 1:  // rotated and uniformly scaled
        p.push_back({translate(at) * rotate(angle, axis) * scale(Vec3(1.3f)), true});
        break;
      case 2:  // non-uniform scale
        p.push_back({translate(at) * rotate(angle, axis) * scale({0.5f, 1.7f, 1.1f}), false});
        break;
      default:  // mirrored (negative determinant)
        p.push_back({translate(at) * rotate(angle, axis) * scale({-1.0f, 1.0f, 0.8f}), false});
    }
  }
  return p;
}

/// The instanced scene of placements(): two objects (the shapes without and with the sphere),
/// its flattened twin, and for each flattened primitive its (instance, object primitive).
struct Scene {
  PrimitiveSet objects[2];
  std::vector<Instance> instances;
  PrimitiveSet flat;
  std::vector<std::pair<uint32_t, uint32_t>> flat_origin;
};

const Scene& scene() {
  static const Scene s = [] {
    Scene s;
    add_object(s.objects[0], Transform(), false);
    add_object(s.objects[1], Transform(), true);
    const std::vector<Placement> p = placements();
    for (uint32_t i = 0; i < p.size(); ++i) {
      const uint32_t object = p[i].similarity ? 1 : 0;
      s.instances.push_back({object, p[i].to_world});
      const uint32_t first = s.flat.size();
      add_object(s.flat, p[i].to_world, object == 1);
      for (uint32_t k = first; k < s.flat.size(); ++k) s.flat_origin.push_back({i, k - first});
    }
    return s;
  }();
  return s;
}

/// A built two-level structure over scene() with `name` as the bottom level.
struct TwoLevel {
  std::unique_ptr<Accelerator> bottom[2];
  InstanceBvh top;
  explicit TwoLevel(const std::string& name) {
    std::vector<InstancedObject> objects;
    for (int o = 0; o < 2; ++o) {
      bottom[o] = make_accelerator(name);
      bottom[o]->build(scene().objects[o]);
      objects.push_back({bottom[o].get(), &scene().objects[o]});
    }
    top.build(objects, scene().instances);
  }
};

const std::vector<Ray>& rays() {
  static const std::vector<Ray> r = mixed_rays(scene().flat, 40'000, 5);
  return r;
}

TEST(InstanceBvh, EveryBottomLevelStructureMatchesBruteForce) {
  const TwoLevel reference("brute");
  std::vector<Hit> ref(rays().size());
  for (size_t i = 0; i < rays().size(); ++i) reference.top.intersect(rays()[i], ref[i]);
  size_t hits = 0;
  for (const Hit& h : ref) hits += h.valid();
  ASSERT_GT(hits, rays().size() / 4);  // the rays do meet the instances
  for (const AccelInfo& info : accelerator_list()) {
    const TwoLevel two(info.name);
    size_t other_prim = 0, errors = 0;
    for (size_t i = 0; i < rays().size(); ++i) {
      const Ray& ray = rays()[i];
      Hit h;
      const bool found = two.top.intersect(ray, h);
      // Closest hit: the same t within 1e-5 relative (the bound of the single-level differential
      // tests: a ray through a shared edge may find either triangle, whose t's differ in the
      // last bits), the same instance and primitive but for such ties.
      if (found != ref[i].valid() ||
          (found && std::fabs(h.t - ref[i].t) > 1e-5f * std::max(h.t, ref[i].t))) {
        if (++errors < 5)
          ADD_FAILURE() << info.name << " ray " << i << ": t " << h.t << " vs " << ref[i].t;
        continue;
      }
      if (found && (h.prim != ref[i].prim || h.instance != ref[i].instance)) ++other_prim;
      // Occlusion, unbounded and bounded short of the closest hit.
      if (two.top.occluded(ray) != found) ++errors;
      if (found) {
        Ray shorter = ray;
        shorter.tmax = ref[i].t * 0.999f;
        Hit any;
        EXPECT_EQ(two.top.occluded(shorter), reference.top.intersect(shorter, any))
            << info.name << " ray " << i;
      }
    }
    EXPECT_EQ(errors, 0u) << info.name;
    // Ties at shared edges (frequent among the axis-parallel rays through vertex coordinates).
    EXPECT_LE(other_prim, rays().size() / 400) << info.name;
  }
}

TEST(InstanceBvh, MatchesTheFlattenedScene) {
  const TwoLevel two("bvh");
  auto flat = make_accelerator("brute");
  flat->build(scene().flat);
  size_t disagree = 0, compared = 0;
  for (size_t i = 0; i < rays().size(); ++i) {
    // Only the rays of random origin and direction (mixed_rays: i % 5 < 2). The others start on
    // a surface of the flattened scene or run exactly along its planes and through its vertex
    // coordinates: whether they touch a surface there depends on the last bit, which the
    // rounding of the object-space ray changes.
    if (i % 5 >= 2) continue;
    const Ray& ray = rays()[i];
    Hit a, b;
    const bool fa = two.top.intersect(ray, a), fb = flat->intersect(ray, b);
    if (fa != fb) {  // only a ray grazing an edge or starting on a surface may differ
      ++disagree;
      continue;
    }
    if (!fa) continue;
    ++compared;
    // t within a few float ulps of the scene's magnitude (the object-space ray is the world ray
    // rounded once more); the same instance and object primitive.
    EXPECT_NEAR(a.t, b.t, 1e-5f * std::max(1.0f, b.t)) << "ray " << i;
    const auto [instance, prim] = scene().flat_origin[b.prim];
    if (a.instance != instance || a.prim != prim) ++disagree;
  }
  EXPECT_GT(compared, rays().size() / 10);
  EXPECT_LE(disagree, rays().size() / 1000);
}

// The counting queries of the two levels return the plain queries' answers; an any-hit query
// of a ray that misses does the closest-hit query's work, and one that hits stops having tested
// something.
TEST(InstanceBvh, CountingQueriesAnswerAsThePlainOnes) {
  const TwoLevel two("bvh");
  size_t misses = 0;
  for (const Ray& ray : rays()) {
    TraversalCost closest, any;
    Hit counted, plain;
    const bool hit = two.top.intersect(ray, plain);
    ASSERT_EQ(two.top.intersect_cost(ray, counted, closest), hit);
    if (hit) {
      ASSERT_EQ(counted.t, plain.t);
    }
    ASSERT_EQ(two.top.occluded_cost(ray, any), two.top.occluded(ray));
    ASSERT_EQ(two.top.occluded(ray), hit);
    if (hit) {
      EXPECT_GE(any.prims, 1u);
    } else {
      EXPECT_EQ(any.nodes, closest.nodes);
      EXPECT_EQ(any.prims, closest.prims);
      ++misses;
    }
  }
  EXPECT_GT(misses, rays().size() / 10);
}

TEST(InstanceBvh, StatsCountTheTopLevelOnly) {
  const TwoLevel two("bvh");
  const AccelStats s = two.top.stats();
  EXPECT_EQ(s.prim_refs, scene().instances.size());
  EXPECT_GT(s.bytes, scene().instances.size() * sizeof(Instance));
  EXPECT_LT(s.bytes, scene().instances.size() * 512);
}

TEST(InstanceBvh, CoincidentInstancesGoToTheLowestInstance) {
  // Six placements of one object, apart from each other: instances 1, 2 and 4 at the same
  // transform and 3 and 5 at another. A ray that hits them meets two or three instances at the
  // same t and must get the lowest (hit.h, tie_bound), through every bottom-level structure.
  const Transform a = translate({0, 0, 0}), b = translate({10, 0, 0}) * rotate(30, {0, 0, 1});
  const Transform c = translate({0, 10, 0}) * scale({1, 2, 1});
  const std::vector<Instance> instances = {{0, c}, {0, b}, {0, b}, {0, a}, {0, b}, {0, a}};
  Pcg32 rng(21, 4);
  std::vector<Ray> rays;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 o{rng.next_float() * 30 - 10, rng.next_float() * 30 - 10, rng.next_float() * 8 + 4};
    const Vec3 centre = i % 2 ? Vec3(10, 0, 0) : Vec3(0, 0, 0);
    const Vec3 target = centre + Vec3(rng.next_float() * 3 - 1.5f, rng.next_float() * 3 - 1.5f,
                                      rng.next_float() * 2 - 1);
    rays.push_back({o, target - o});
  }
  size_t lowest = 0;
  for (const std::string& name : std::vector<std::string>{"brute", "bvh", "kdtree", "grid"}) {
    std::unique_ptr<Accelerator> bottom = make_accelerator(name);
    bottom->build(scene().objects[0]);
    InstanceBvh top;
    top.build({{bottom.get(), &scene().objects[0]}}, instances);
    for (size_t i = 0; i < rays.size(); ++i) {
      Hit h;
      if (!top.intersect(rays[i], h)) continue;
      // Test every instance alone: the least (t, instance) is the answer.
      uint32_t want = kNoInstance;
      float want_t = kInfinity;
      for (uint32_t k = 0; k < instances.size(); ++k) {
        InstanceBvh one;
        one.build({{bottom.get(), &scene().objects[0]}}, {instances[k]});
        Hit hk;
        if (one.intersect(rays[i], hk) && hk.t < want_t) want = k, want_t = hk.t;
      }
      ASSERT_EQ(h.instance, want) << name << " ray " << i;
      EXPECT_EQ(h.t, want_t) << name << " ray " << i;
      lowest += name == "bvh" && (want == 1 || want == 3);
    }
  }
  EXPECT_GT(lowest, 1000u);  // the rays do meet the coincident instances
}

TEST(InstanceBvh, EmptyAndUntraceable) {
  InstanceBvh empty;
  empty.build({}, {});
  Ray r{{0, 0, 0}, {0, 0, 1}};
  Hit h;
  EXPECT_FALSE(empty.intersect(r, h));
  EXPECT_FALSE(empty.occluded(r));
  const TwoLevel two("bvh");
  Ray nan{{0, 0, -10}, {std::nanf(""), 0, 1}};
  EXPECT_FALSE(two.top.intersect(nan, h));
  EXPECT_FALSE(two.top.occluded(nan));
}

}  // namespace
}  // namespace penumbra::test
