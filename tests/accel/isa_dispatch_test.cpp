/// Structures compiled for several instruction-set levels and chosen when the program runs
/// (registry.h, `isa=`): each level's copy builds the same tree and answers every query with the
/// same bits as the build's own code, reports its level, and a level the CPU lacks, or one not
/// compiled in, is refused with the reason.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "penumbra/accel/registry.h"
#include "penumbra/core/error.h"
#include "penumbra/core/target.h"
#include "test_scenes.h"

namespace penumbra::test {
namespace {

/// What compiled_vectors() names a level's code.
std::string level_vectors(const std::string& level) {
  return level == "sse2" ? "SSE2" : level == "avx2" ? "AVX2" : "AVX-512";
}

/// `spec` with isa=`level` added to its parameters.
std::string with_isa(const std::string& spec, const std::string& level) {
  return spec + (spec.find(':') == std::string::npos ? ":" : ",") + "isa=" + level;
}

/// Sets PENUMBRA_CPU_LACKS for a scope.
struct CpuLacks {
  explicit CpuLacks(const char* list) { setenv("PENUMBRA_CPU_LACKS", list, 1); }
  ~CpuLacks() { unsetenv("PENUMBRA_CPU_LACKS"); }
};

/// True when the CPU runs level `level`'s code (make_accelerator refuses it otherwise).
bool cpu_runs(const std::string& level) {
  try {
    make_accelerator("bvh:isa=" + level);
    return true;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("which this CPU lacks"), std::string::npos) << e.what();
    return false;
  }
}

TEST(IsaDispatch, ListsTheLevelsTheBuildCompiled) {
  // PENUMBRA_TEST_ISA_LEVELS: CMake's list (sse2, avx2 and avx512 on x86-64 with
  // PENUMBRA_ISA_DISPATCH, the default; none elsewhere).
  std::string listed;
  for (const std::string& level : isa_levels()) listed += (listed.empty() ? "" : ",") + level;
  EXPECT_EQ(listed, PENUMBRA_TEST_ISA_LEVELS);
#if defined(__x86_64__)
  EXPECT_TRUE(listed.empty() || listed == "sse2,avx2,avx512") << listed;
#endif
}

/// Every bit of two structures' answers to `rays`: closest hits, any hits and batches.
void expect_same_answers(const Accelerator& a, const Accelerator& b, const std::vector<Ray>& rays) {
  const auto bits = [](float x) { return std::bit_cast<uint32_t>(x); };
  size_t differ = 0;
  for (const Ray& ray : rays) {
    Hit ha, hb;
    const bool fa = a.intersect(ray, ha), fb = b.intersect(ray, hb);
    if (fa != fb || bits(ha.t) != bits(hb.t) || bits(ha.u) != bits(hb.u) ||
        bits(ha.v) != bits(hb.v) || ha.prim != hb.prim || a.occluded(ray) != b.occluded(ray))
      ++differ;
  }
  EXPECT_EQ(differ, 0u) << a.name() << " against " << b.name();
  std::vector<Hit> hits_a(rays.size()), hits_b(rays.size());
  std::vector<uint8_t> blocked_a(rays.size()), blocked_b(rays.size());
  a.intersect_batch(rays, hits_a, BatchOrder::kIncoherent);
  b.intersect_batch(rays, hits_b, BatchOrder::kIncoherent);
  a.occluded_batch(rays, blocked_a, BatchOrder::kIncoherent);
  b.occluded_batch(rays, blocked_b, BatchOrder::kIncoherent);
  size_t batch_differ = 0;
  for (size_t i = 0; i < rays.size(); ++i)
    if (bits(hits_a[i].t) != bits(hits_b[i].t) || hits_a[i].prim != hits_b[i].prim ||
        blocked_a[i] != blocked_b[i])
      ++batch_differ;
  EXPECT_EQ(batch_differ, 0u) << a.name() << " against " << b.name() << " (batches)";
}

TEST(IsaDispatch, EveryLevelBuildsAndAnswersAsTheBuildsOwnCode) {
  const std::vector<TestScene> scenes = {random_soup(3000, 11), mixed_shapes(12), torus(40, 60)};
  // Explicit widths, since each level has its own default (4 without AVX, else 16); the
  // interleaved batches forced on, which the default leaves off below 16 MiB.
  const char* specs[] = {"bvh:width=4,interleave=on",
                         "bvh:width=8",
                         "bvh:width=16,interleave=on",
                         "bvh:nodes=compressed",
                         "bvh2",
                         "kdtree",
                         "grid",
                         "octree",
                         "bsp"};
  int levels_run = 0;
  for (const std::string& level : isa_levels()) {
    if (!cpu_runs(level)) continue;
    ++levels_run;
    for (const TestScene& scene : scenes) {
      const std::vector<Ray> rays = mixed_rays(scene.prims, 4000, 99);
      for (const char* spec : specs) {
        SCOPED_TRACE(scene.name + ", " + spec + ", isa=" + level);
        const auto native = make_accelerator(with_isa(spec, "native"));
        const auto copy = make_accelerator(with_isa(spec, level));
        native->build(scene.prims);
        copy->build(scene.prims);
        EXPECT_STREQ(copy->vectors(), level_vectors(level).c_str());
        EXPECT_STREQ(native->vectors(), compiled_vectors());
        EXPECT_NE(copy->name().find("isa=" + level), std::string::npos) << copy->name();
        // The same tree: the builds use no arithmetic whose result depends on the level.
        const AccelStats sa = native->stats(), sb = copy->stats();
        EXPECT_EQ(sa.nodes, sb.nodes);
        EXPECT_EQ(sa.leaves, sb.leaves);
        EXPECT_EQ(sa.max_depth, sb.max_depth);
        EXPECT_EQ(sa.prim_refs, sb.prim_refs);
        expect_same_answers(*native, *copy, rays);
      }
    }
  }
  // Every x86-64 CPU has SSE2.
  if (!isa_levels().empty()) {
    EXPECT_GE(levels_run, 1);
  }
}

TEST(IsaDispatch, AutoTakesTheWidestLevelTheCpuHasBeyondTheBuildsTarget) {
  if (isa_levels().empty()) GTEST_SKIP() << "no levels compiled in";
  // The build's own target: its rank against the levels'.
  const std::string own = compiled_vectors();
  const bool own_avx512 = own == "AVX-512", own_avx2 = own_avx512 || own == "AVX2";
  // The widest level the CPU runs (make_accelerator refuses the others).
  const std::string best = cpu_runs("avx512") ? "avx512" : cpu_runs("avx2") ? "avx2" : "sse2";
  const auto expect = [&](const std::string& widest_available) {
    if (widest_available == "avx512") return own_avx512 ? "native" : "avx512";
    if (widest_available == "avx2") return own_avx2 ? "native" : "avx2";
    return "native";  // SSE2 is the least any build targets
  };
  // As make_accelerator, with whatever PENUMBRA_CPU_LACKS the test runs under, and more.
  const char* env = std::getenv("PENUMBRA_CPU_LACKS");
  const auto also = [&](const std::string& more) { return env ? env + ("," + more) : more; };
  EXPECT_EQ(isa_auto(env), expect(best));
  EXPECT_EQ(isa_auto(also("avx512f").c_str()), expect(best == "avx512" ? "avx2" : best));
  EXPECT_EQ(isa_auto(also("avx2,avx512f").c_str()), "native");
  // The structure isa=auto makes runs that level's code.
  const auto bvh = make_accelerator("bvh");
  const std::string chosen = isa_auto(env);
  EXPECT_STREQ(bvh->vectors(), chosen == "native" ? own.c_str() : level_vectors(chosen).c_str());
}

TEST(IsaDispatch, RefusesAnUnknownLevelAndOneTheCpuLacks) {
  try {
    make_accelerator("kdtree:isa=avx1024");
    FAIL() << "isa=avx1024 accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("parameter 'isa' must be one of auto, native"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'avx1024'"), std::string::npos) << msg;
    for (const std::string& level : isa_levels()) EXPECT_NE(msg.find(level), std::string::npos);
  }
  // An unknown structure is that, whatever its isa; a copy's own errors reach the caller.
  try {
    make_accelerator("kdtre:isa=avx1024");
    FAIL() << "kdtre accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown acceleration structure 'kdtre'"),
              std::string::npos)
        << e.what();
  }
  if (isa_levels().empty()) return;
  try {
    make_accelerator("bvh:isa=sse2,width=3");
    FAIL() << "width=3 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'width' must be 2, 4, 8 or 16"), std::string::npos)
        << e.what();
  }
  const CpuLacks lacks("avx512bw,avx2");
  for (const char* spec : {"bvh:isa=avx512", "grid:isa=avx2"}) {
    try {
      make_accelerator(spec);
      ADD_FAILURE() << spec << " accepted on a CPU taken to lack it";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("which this CPU lacks"), std::string::npos) << msg;
      EXPECT_NE(
          msg.find(std::string(spec).find("avx512") != std::string::npos ? "avx512bw" : "avx2"),
          std::string::npos)
          << msg;
    }
  }
  // isa=auto never picks a level the CPU lacks, and SSE2 stays available.
  EXPECT_NO_THROW(make_accelerator("bvh"));
  EXPECT_NO_THROW(make_accelerator("bvh:isa=sse2"));
}

}  // namespace
}  // namespace penumbra::test
