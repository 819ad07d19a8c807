/// accel-bench's path-tracer workload (app/bench_rays.h): bounce rays leave the surface on the
/// camera's side with a cosine distribution, shadow rays end just short of a point on the light,
/// and the sets do not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/app/bench_rays.h"
#include "penumbra/core/parallel.h"

namespace penumbra::app {
namespace {

// A floor square [-1, 1]^2 at y = 0 (triangles 0, 1) and a light square [-0.25, 0.25]^2 at
// y = 1 (triangles 2, 3), and camera rays straight down onto the floor from y = 0.5.
struct Fixture {
  PrimitiveSet prims;
  std::vector<Ray> camera;
  std::vector<Hit> hits;
  Fixture() {
    TriangleMesh m;
    m.positions = {{-1, 0, -1},         {1, 0, -1},         {1, 0, 1},         {-1, 0, 1},
                   {-0.25f, 1, -0.25f}, {0.25f, 1, -0.25f}, {0.25f, 1, 0.25f}, {-0.25f, 1, 0.25f}};
    m.indices = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6};
    prims.add_mesh(m, Transform(), 0);
    for (int j = 0; j < 200; ++j)
      for (int i = 0; i < 200; ++i) {
        const Vec3 o(-0.995f + 0.01f * float(i), 0.5f, -0.995f + 0.01f * float(j));
        camera.push_back({o, {0, -1, 0}});
        Hit h;
        h.t = 0.5f;
        h.prim = (i > j) ? 0 : 1;  // which floor triangle does not matter to the normal
        hits.push_back(h);
      }
    hits[7] = Hit{};  // a miss: no rays from it
  }
};

TEST(BenchRays, BounceRaysAreCosineDistributedAboutTheNormalOnTheCamerasSide) {
  const Fixture f;
  const PathRays rays = path_rays(f.prims, f.camera, f.hits, 42, {2, 3});
  ASSERT_EQ(rays.bounce.size(), f.camera.size() - 1);
  double sum = 0;
  for (const Ray& r : rays.bounce) {
    ASSERT_GT(r.o.y, 0.0f);  // moved off the floor towards the camera
    ASSERT_LT(r.o.y, 1e-3f);
    ASSERT_GT(r.d.y, 0.0f);
    ASSERT_NEAR(length(r.d), 1.0f, 1e-5f);
    sum += r.d.y;
  }
  // E[cos] = 2/3 for a cosine distribution, variance 1/2 - 4/9 = 1/18 (uniform would give 1/2).
  const double n = double(rays.bounce.size());
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 4.0 * std::sqrt(1.0 / 18.0 / n));
}

TEST(BenchRays, ShadowRaysEndJustShortOfTheLight) {
  const Fixture f;
  for (const bool emitters : {true, false}) {
    const PathRays rays =
        path_rays(f.prims, f.camera, f.hits, 42,
                  emitters ? std::vector<uint32_t>{2, 3} : std::vector<uint32_t>{});
    ASSERT_EQ(rays.shadow.size(), f.camera.size() - 1);  // every floor point faces the light
    // Without emitters: the square of side 0.5 |diagonal| at 0.25 |diagonal| above the bounds.
    const float diag = length(f.prims.bounds().diagonal());
    const float y = emitters ? 1.0f : 1.0f + 0.25f * diag, half = emitters ? 0.25f : 0.25f * diag;
    for (const Ray& r : rays.shadow) {
      const Vec3 end = r.o + r.d * (r.tmax / (1 - 1e-4f));
      ASSERT_NEAR(end.y, y, 1e-4f);
      ASSERT_LE(std::abs(end.x), half + 1e-4f);
      ASSERT_LE(std::abs(end.z), half + 1e-4f);
      ASSERT_LT(r.tmax, length(end - r.o));  // short of the light itself
    }
  }
}

TEST(BenchRays, TheSetsDoNotDependOnTheThreadCount) {
  const Fixture f;
  const auto make = [&](int threads) {
    const ThreadLimit limit(threads);
    return path_rays(f.prims, f.camera, f.hits, 7, {2, 3});
  };
  const PathRays a = make(1), b = make(2);
  ASSERT_EQ(a.bounce.size(), b.bounce.size());
  ASSERT_EQ(a.shadow.size(), b.shadow.size());
  for (size_t i = 0; i < a.bounce.size(); ++i) {
    ASSERT_EQ(a.bounce[i].d.x, b.bounce[i].d.x);
    ASSERT_EQ(a.bounce[i].d.z, b.bounce[i].d.z);
  }
  for (size_t i = 0; i < a.shadow.size(); ++i) ASSERT_EQ(a.shadow[i].tmax, b.shadow[i].tmax);
}

}  // namespace
}  // namespace penumbra::app
