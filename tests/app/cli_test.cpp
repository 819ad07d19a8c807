// End-to-end tests of the penumbra program: flags, outputs, errors, determinism.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "penumbra/accel/registry.h"
#include "penumbra/core/target.h"
#include "penumbra/image/pfm.h"

#include "cli_fixture.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

/// End-to-end tests share the fixture of cli_fixture.h.
using CliTest = CliFixture;

TEST_F(CliTest, HelpListsEverySubcommandAndRenderFlag) {
  ASSERT_EQ(run("--help"), 0);
  EXPECT_NE(out_.find("render"), std::string::npos);
  EXPECT_NE(out_.find("accel-bench"), std::string::npos);
  EXPECT_NE(out_.find("collide"), std::string::npos);
  ASSERT_EQ(run("render --help"), 0);
  for (const char* flag :
       {"--spp", "--threads", "--seed", "--accel", "--integrator", "--resolution", "--output"})
    EXPECT_NE(out_.find(flag), std::string::npos) << flag;
}

TEST_F(CliTest, ACpuWithoutTheBuildsExtensionsStopsTheProgramWithAMessage) {
  // PENUMBRA_CPU_LACKS makes the start-up check (core/cpu_check.h) take the named extensions
  // as missing; every x86-64 build uses SSE2.
#if defined(__x86_64__)
  const std::string out = path("out.png");
  EXPECT_EQ(run("render " + scene("cornell-box.json") + " -o " + out + " --spp 1"), 0) << err_;
  std::filesystem::remove(out);
  const std::string env = "env PENUMBRA_CPU_LACKS=sse2,avx512f ";
  const std::string cmd = std::string("sh -c '") + env + PENUMBRA_CLI + " render " +
                          scene("cornell-box.json") + " -o " + out + " --spp 1'";
  const int status = std::system((cmd + " > " + path("o.txt") + " 2> " + path("e.txt")).c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string err = slurp(path("e.txt"));
  EXPECT_NE(err.find("penumbra: error: this program was compiled for instruction-set extensions "
                     "that this CPU does not have: sse2"),
            std::string::npos)
      << err;
#if defined(__AVX512F__)
  EXPECT_NE(err.find("sse2, avx512f"), std::string::npos) << err;
#endif
  EXPECT_NE(err.find("-DPENUMBRA_NATIVE=OFF"), std::string::npos) << err;
  EXPECT_TRUE(slurp(path("o.txt")).empty());
  EXPECT_FALSE(std::filesystem::exists(out));
#else
  GTEST_SKIP() << "the check is for x86-64 builds";
#endif
}

TEST_F(CliTest, SameSeedGivesIdenticalBytesAtAnyThreadCount) {
  const std::string common = scene("cornell-box.json") + " --resolution 64x48 --spp 3 ";
  ASSERT_EQ(run("render " + common + "--seed 9 --threads 1 -o " + path("a.pfm")), 0) << err_;
  ASSERT_EQ(run("render " + common + "--seed 9 --threads 2 -o " + path("b.pfm")), 0) << err_;
  const std::string a = slurp(path("a.pfm")), b = slurp(path("b.pfm"));
  ASSERT_GT(a.size(), 64u * 48u * 12u);
  EXPECT_TRUE(a == b);
  ASSERT_EQ(run("render " + common + "--seed 10 --threads 2 -o " + path("c.pfm")), 0) << err_;
  EXPECT_FALSE(a == slurp(path("c.pfm")));  // the seed matters
}

TEST_F(CliTest, SummaryReportsTimeRaysAndAccelStatistics) {
  ASSERT_EQ(run("render " + scene("cornell-box.json") + " --resolution 32x32 --spp 1 -o " +
                path("out.png")),
            0)
      << err_;
  EXPECT_TRUE(fs::exists(path("out.png")));
  EXPECT_NE(err_.find("Mrays/s"), std::string::npos) << err_;
  EXPECT_NE(err_.find("nodes"), std::string::npos) << err_;
  EXPECT_NE(err_.find("render:"), std::string::npos) << err_;  // plain progress lines off a tty
  // The code the structure runs (isa=auto's choice, registry.h).
  EXPECT_NE(err_.find(std::string("accel bvh (") + make_accelerator("bvh")->vectors() + " code): "),
            std::string::npos)
      << err_;
  if (isa_levels().empty()) return;
  ASSERT_EQ(run("render " + scene("cornell-box.json") +
                " --resolution 16x16 --spp 1 --accel kdtree:isa=sse2 -o " + path("sse2.png")),
            0)
      << err_;
  EXPECT_NE(err_.find("accel kdtree:sah,isa=sse2 (SSE2 code): "), std::string::npos) << err_;
}

TEST_F(CliTest, EveryImageFormatIsWritten) {
  for (const char* ext : {"png", "exr", "pfm"}) {
    const std::string out = path(std::string("img.") + ext);
    ASSERT_EQ(run("render " + scene("cornell-box.json") + " --resolution 16x16 -q -o " + out), 0)
        << err_;
    EXPECT_GT(fs::file_size(out), 16u);
  }
}

TEST_F(CliTest, BadInputFailsWithAMessageAndNoOutput) {
  const std::string out = path("never.png");
  struct Case {
    std::string args, expect;
  };
  write("bad.json",
        "{\"camera\": {\"type\": \"pinhole\", \"position\": [0,0,0], \"look_at\": "
        "[0,0,1]}, \"shapes\": [{\"type\": \"sphere\", \"radus\": 1}]}");
  write("syntax.json", "{\n  \"camera\": {\n    \"type\": \"pinhole\",,\n  }\n}\n");
  const Case cases[] = {
      {"render " + path("missing.json") + " -o " + out, "missing.json"},
      {"render " + path("bad.json") + " -o " + out, "/shapes/0"},
      {"render " + path("syntax.json") + " -o " + out, "syntax.json:3"},
      {"render " + scene("cornell-box.json") + " --accel nope -o " + out, "valid: brute"},
      {"render " + scene("cornell-box.json") + " --integrator nope -o " + out, "whitted"},
      {"render " + scene("cornell-box.json") + " --resolution 12 -o " + out, "WxH"},
      {"render " + scene("cornell-box.json") + " -o " + path("x.jpg"), ".png"},
      {"render " + scene("cornell-box.json") + " --spp 0 -o " + out, "spp"},
  };
  for (const Case& c : cases) {
    EXPECT_NE(run(c.args), 0) << c.args;
    EXPECT_NE(err_.find(c.expect), std::string::npos) << c.args << "\n" << err_;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

// Numeric options are read as the user wrote them, in decimal and in range: CLI11 alone took
// --seed -1 as 2^64 - 1, 2^64 as the largest seed, --spp 010 as 8 (octal), and NaN as a positive
// --time-limit (a render that never stopped) or --target-error (never reached).
TEST_F(CliTest, NumericOptionsAreDecimalFiniteAndInRange) {
  const std::string out = path("never.png");
  const std::string render = "render " + scene("cornell-box.json") + " --resolution 8x8 -o " + out;
  const std::pair<std::string, std::string> refused[] = {
      {render + " --seed -1",
       "--seed: expected a decimal integer in [0, 18446744073709551615], "
       "got '-1'"},
      {render + " --seed 18446744073709551616", "got '18446744073709551616'"},
      {render + " --spp 0x10", "--spp: expected a decimal integer in [1, 16777216], got '0x10'"},
      {render + " --spp 99999999999999999999", "--spp: expected a decimal integer"},
      {render + " --threads -2", "--threads: expected a decimal integer in [1, 4096]"},
      {render + " --max-depth 1.5", "--max-depth: expected a decimal integer"},
      {render + " --time-limit nan",
       "--time-limit: expected a finite number greater than 0, "
       "got 'nan'"},
      {render + " --time-limit inf", "--time-limit: expected a finite number greater than 0"},
      {render + " --checkpoint 0", "--checkpoint: expected a finite number greater than 0"},
      {render + " --target-error nan", "--target-error: expected a finite number greater"},
      {"accel-bench " + scene("meshes/bunny.obj") + " --rays -1", "--rays: expected"},
      {"accel-bench " + scene("meshes/bunny.obj") + " --image 8", "--image: expected"},
      {"collide " + scene("meshes/bunny.obj") + " --max-print -1", "--max-print: expected"},
      {"bsp2d --random 10 --seed -1", "--seed: expected a decimal integer"},
  };
  for (const auto& [args, expect] : refused) {
    EXPECT_NE(run(args), 0) << args;
    EXPECT_NE(err_.find(expect), std::string::npos) << args << "\n" << err_;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
  // A leading zero is decimal: --spp 010 renders 10 samples, not 8.
  ASSERT_EQ(run(render + " --spp 010 --integrator raycast"), 0) << err_;
  EXPECT_NE(err_.find("(10 spp of 10, complete)"), std::string::npos) << err_;
  // The largest seed is accepted.
  ASSERT_EQ(run(render + " --spp 1 --seed 18446744073709551615 --integrator raycast"), 0) << err_;
}

// accel-bench on a scene and on a mesh writes one JSON row per structure (Embree's too when it
// was found at configure time) with the documented keys, and one run per thread count.
TEST_F(CliTest, AccelBenchWritesAJsonRowPerStructure) {
  // Brute force traces the 1024 x 1024 primary rays too: only over the 38 Cornell triangles.
  for (const std::string& input : {scene("cornell-box.json") + " --accel bvh,brute",
                                   scene("meshes/bunny.obj") + " --accel bvh,bvh:sweep"}) {
    ASSERT_EQ(run("accel-bench " + input + " --threads 1 --repeat 1 --rays 2000 --json " +
                  path("bench.json")),
              0)
        << err_;
    const auto rows = nlohmann::json::parse(slurp(path("bench.json")));
    ASSERT_TRUE(rows.is_array());
    size_t structures = 0;
    for (const auto& row : rows) {
      for (const char* key : {"accel", "mesh", "triangles", "build_ms", "build_threads", "bytes"})
        EXPECT_TRUE(row.contains(key)) << key << " in " << row.dump();
      // The vectors of the structure's code: for Embree, the program's (the program and this
      // test share the flags); for a structure, the copy isa=auto picks on this CPU.
      if (row["accel"] == "embree") {
        EXPECT_EQ(row["vectors"], compiled_vectors()) << row.dump();
        continue;
      }
      EXPECT_EQ(row["vectors"], make_accelerator("bvh")->vectors()) << row.dump();
      ++structures;
      for (const char* key : {"nodes", "depth", "refs_per_prim"})
        EXPECT_TRUE(row.contains(key)) << key << " in " << row.dump();
      EXPECT_GE(row["refs_per_prim"].get<double>(), 1.0);  // a BVH or brute: each triangle once
      EXPECT_EQ(row["build_threads"], 1);
      ASSERT_EQ(row["runs"].size(), 1u) << row.dump();
      const auto& run = row["runs"][0];
      EXPECT_EQ(run["threads"], 1);
      for (const char* key :
           {"primary_mrays", "incoherent_mrays", "occlusion_mrays", "bounce_mrays", "shadow_mrays"})
        EXPECT_GT(run[key].get<double>(), 0.0) << key;
    }
    EXPECT_EQ(structures, 2u);
    EXPECT_NE(out_.find("Mrays/s"), std::string::npos) << out_;
    EXPECT_NE(out_.find(std::string("; program compiled for ") + compiled_vectors() + "\n"),
              std::string::npos)
        << out_;
  }
  // isa=sse2, where the build holds that copy: its row says so, and so does the header.
  if (!isa_levels().empty()) {
    ASSERT_EQ(
        run("accel-bench " + scene("meshes/bunny.obj") +
            " --accel bvh:isa=sse2 --threads 1 --repeat 1 --rays 100 --json " + path("isa.json")),
        0)
        << err_;
    const auto rows = nlohmann::json::parse(slurp(path("isa.json")));
    bool seen = false;
    for (const auto& row : rows) {
      if (row["accel"] != "bvh:isa=sse2") continue;
      EXPECT_EQ(row["vectors"], "SSE2");
      seen = true;
    }
    EXPECT_TRUE(seen) << rows.dump();
    EXPECT_NE(out_.find("structures' code: SSE2 (bvh:isa=sse2)\n"), std::string::npos) << out_;
  }
  // --image sets the primary rays: 32 x 32 of them.
  ASSERT_EQ(run("accel-bench " + scene("meshes/bunny.obj") +
                " --accel bvh --threads 1 --repeat 1 --rays 100 --image 32"),
            0)
      << err_;
  EXPECT_NE(out_.find("rays: 1024 primary (32x32 pinhole)"), std::string::npos) << out_;
  EXPECT_EQ(run("accel-bench " + scene("cornell-box.json") + " --accel brute --rays 100 --json " +
                path("brute.json")),
            0);
  EXPECT_NE(slurp(path("brute.json")).find("\"brute\""), std::string::npos);
  EXPECT_NE(run("accel-bench " + scene("cornell-box.json") + " --accel nope"), 0);
  EXPECT_NE(err_.find("valid:"), std::string::npos) << err_;
}

// --versus prints and writes every other structure's throughput over the named one's: the
// quotients of their ratios to Embree when it ran, else of their rates; the named structure and
// Embree get none. A name that is not among --accel, or no structure at all, is refused.
TEST_F(CliTest, AccelBenchVersusDividesByTheNamedStructure) {
  const std::string common =
      "accel-bench " + scene("meshes/bunny.obj") + " --threads 1 --repeat 1 --rays 2000 --image 32";
  ASSERT_EQ(run(common + " --accel bvh,kdtree,grid --versus kdtree --json " + path("vs.json")), 0)
      << err_;
  EXPECT_NE(out_.find("bvh                    over kdtree:sah at 1 thread: primary "),
            std::string::npos)
      << out_;
  EXPECT_NE(out_.find("grid                   over kdtree:sah at 1 thread"), std::string::npos);
  EXPECT_EQ(out_.find("kdtree:sah             over"), std::string::npos) << out_;
  const auto rows = nlohmann::json::parse(slurp(path("vs.json")));
  const nlohmann::json* base = nullptr;
  for (const auto& row : rows)
    if (row["accel"] == "kdtree:sah") base = &row;
  ASSERT_NE(base, nullptr) << rows.dump();
  EXPECT_FALSE(base->contains("versus"));
  EXPECT_FALSE((*base)["runs"][0].contains("over_versus"));
  size_t others = 0;
  for (const auto& row : rows) {
    if (&row == base) continue;
    if (row["accel"] == "embree") {
      EXPECT_FALSE(row.contains("versus")) << row.dump();
      continue;
    }
    ++others;
    EXPECT_EQ(row["versus"], "kdtree:sah") << row.dump();
    const auto& run = row["runs"][0];
    const auto& b = (*base)["runs"][0];
    const auto& over = run["over_versus"];
    const bool paired = run.contains("incoherent_vs_embree");
    EXPECT_EQ(over["through_embree"], paired);
    for (const char* set : {"primary", "incoherent", "occlusion", "bounce", "shadow"}) {
      const std::string key = std::string(set) + (paired ? "_vs_embree" : "_mrays");
      EXPECT_DOUBLE_EQ(over[set].get<double>(), run[key].get<double>() / b[key].get<double>())
          << set << " in " << row.dump();
    }
  }
  EXPECT_EQ(others, 2u);
  EXPECT_NE(run(common + " --accel bvh --versus kdtree"), 0);
  EXPECT_NE(err_.find("--versus kdtree: not one of the structures of --accel"), std::string::npos)
      << err_;
  EXPECT_NE(run(common + " --accel bvh --versus nope"), 0);
  EXPECT_NE(err_.find("--versus: unknown acceleration structure 'nope'"), std::string::npos)
      << err_;
}

// --batch traces through the batch queries (and Embree's stream API): the JSON says so, and the
// incoherent hits are the single queries' (the same count of differences from Embree's).
TEST_F(CliTest, AccelBenchBatchQueriesFindTheSingleQueriesHits) {
  const std::string common = "accel-bench " + scene("meshes/bunny.obj") +
                             " --accel bvh:interleave=on --threads 1 --repeat 1 --rays 3000 "
                             "--image 32 --json ";
  ASSERT_EQ(run(common + path("single.json")), 0) << err_;
  ASSERT_EQ(run(common + path("batch.json") + " --batch"), 0) << err_;
  EXPECT_NE(out_.find("batch queries"), std::string::npos) << out_;
  const auto single = nlohmann::json::parse(slurp(path("single.json")));
  const auto batch = nlohmann::json::parse(slurp(path("batch.json")));
  ASSERT_EQ(single.size(), batch.size());
  for (size_t r = 0; r < batch.size(); ++r) {
    EXPECT_EQ(single[r]["queries"], "single");
    EXPECT_EQ(batch[r]["queries"], "batch");
    if (batch[r]["accel"] == "embree") continue;
    EXPECT_EQ(batch[r]["interleaved batches"], 1.0);
    EXPECT_GT(batch[r]["runs"][0]["incoherent_mrays"].get<double>(), 0.0);
    if (batch[r].contains("embree_mismatches")) {
      EXPECT_EQ(batch[r]["embree_mismatches"], single[r]["embree_mismatches"]);
    }
  }
}

// --embree-robust builds Embree's scene in its robust mode: its row and every row's
// `embree_mode` say so, the ratios are against it, and its hits still agree with ours (the same
// rays; at most 1 % of them differing, hit against miss or t). Without Embree the flag is
// accepted and nothing names a mode.
TEST_F(CliTest, AccelBenchComparesWithEmbreeInItsRobustMode) {
  const std::string common = "accel-bench " + scene("meshes/bunny.obj") +
                             " --accel bvh --threads 1 --repeat 1 --rays 3000 --image 32 --json ";
  ASSERT_EQ(run(common + path("robust.json") + " --embree-robust"), 0) << err_;
  const std::string robust_out = out_;
  ASSERT_EQ(run(common + path("default.json")), 0) << err_;
  const auto robust = nlohmann::json::parse(slurp(path("robust.json")));
  const auto plain = nlohmann::json::parse(slurp(path("default.json")));
  ASSERT_EQ(robust.size(), plain.size());
  if (robust.size() == 1) {  // built without Embree
    EXPECT_FALSE(robust[0].contains("embree_mode")) << robust.dump();
    return;
  }
  ASSERT_EQ(robust.size(), 2u);
  EXPECT_EQ(robust[0]["accel"], "embree:robust");
  EXPECT_EQ(plain[0]["accel"], "embree");
  EXPECT_NE(robust_out.find("robust mode"), std::string::npos) << robust_out;
  for (size_t r = 0; r < 2; ++r) {
    EXPECT_EQ(robust[r]["embree_mode"], "robust") << robust[r].dump();
    EXPECT_EQ(plain[r]["embree_mode"], "default") << plain[r].dump();
  }
  EXPECT_GT(robust[1]["runs"][0]["incoherent_vs_embree"].get<double>(), 0.0);
  EXPECT_LE(robust[1]["embree_mismatches"].get<int>(), 30) << robust[1].dump();
}

// Meshes that would give NaN statistics or trip Embree are refused before any build, naming
// the file and the vertex; collide checks its meshes the same way.
TEST_F(CliTest, AccelBenchAndCollideRefuseEmptyAndOutOfRangeMeshes) {
  write("empty.obj", "v 0 0 0\nv 1 0 0\n");
  EXPECT_NE(run("accel-bench " + path("empty.obj") + " --accel bvh --rays 100"), 0);
  EXPECT_NE(err_.find("empty.obj: the mesh has no triangles"), std::string::npos) << err_;
  write("huge.obj", "v 0 0 0\nv 1e20 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NE(run("accel-bench " + path("huge.obj") + " --accel bvh --rays 100"), 0);
  EXPECT_NE(err_.find("huge.obj:vertex 1: (1e+20, 0, 0)"), std::string::npos) << err_;
  EXPECT_NE(run("collide " + path("huge.obj") + " --sphere 0,0,0,1"), 0);
  EXPECT_NE(err_.find("huge.obj:vertex 1"), std::string::npos) << err_;
  EXPECT_NE(run("collide " + path("empty.obj") + " --sphere 0,0,0,1"), 0);
  EXPECT_NE(err_.find("no triangles"), std::string::npos) << err_;
}

// A mesh's warnings (here an OBJ polygon that is not planar) are printed by every command that
// reads it: render and accel-bench through a scene, accel-bench and collide directly.
TEST_F(CliTest, MeshWarningsArePrintedByRenderAccelBenchAndCollide) {
  write("bent.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0.5\nv -1 1 0\nf 1 2 3 4\n");
  write("bent.json",
        R"({"camera": {"type": "pinhole", "position": [0, 0, 5], "look_at": [0, 0, 0]},
            "materials": {"m": {"type": "diffuse"}},
            "lights": [{"type": "point", "position": [0, 0, 5], "intensity": [10, 10, 10]}],
            "shapes": [{"type": "obj", "file": "bent.obj", "material": "m"}]})");
  const std::string warning =
      "warning: " + path("bent.obj") + ":line 5: face of 4 vertices is not planar";
  ASSERT_EQ(run("render " + path("bent.json") + " --resolution 8x8 --spp 1 -o " + path("o.pfm")), 0)
      << err_;
  EXPECT_NE(err_.find(warning), std::string::npos) << err_;
  for (const char* input : {"bent.json", "bent.obj"}) {
    ASSERT_EQ(run("accel-bench " + path(input) + " --accel bvh --rays 100"), 0) << err_;
    EXPECT_NE(err_.find(warning), std::string::npos) << input << ": " << err_;
  }
  ASSERT_EQ(run("collide " + path("bent.obj") + " " + path("bent.obj") + " --translate-b 0,0,1"), 0)
      << err_;
  EXPECT_NE(err_.find(warning), std::string::npos) << err_;
  EXPECT_NE(err_.find(warning, err_.find(warning) + 1), std::string::npos)  // once per mesh
      << err_;
}

// --repeat N takes medians of N runs; with Embree each structure also gets the median ratio of
// its incoherent throughput to Embree's over runs paired with one of Embree's.
TEST_F(CliTest, AccelBenchRepeatsAndPairsRunsWithEmbree) {
  ASSERT_EQ(run("accel-bench " + scene("cornell-box.json") +
                " --accel bvh --threads 1 --repeat 3 --rays 500 --json " + path("r.json")),
            0)
      << err_;
  EXPECT_NE(out_.find("medians of 3 run(s)"), std::string::npos) << out_;
  EXPECT_NE(out_.find("x embree"), std::string::npos) << out_;
  const auto rows = nlohmann::json::parse(slurp(path("r.json")));
  const bool embree = rows.size() == 2;
  for (const auto& row : rows) {
    const auto& r = row["runs"][0];
    // Embree's own row has no ratio; a structure has all three exactly when Embree ran.
    const bool expect_ratio = embree && row["accel"] != "embree";
    for (const char* key : {"primary_vs_embree", "incoherent_vs_embree", "occlusion_vs_embree"}) {
      EXPECT_EQ(r.contains(key), expect_ratio) << key << " in " << row.dump();
      if (expect_ratio) {
        EXPECT_GT(r[key].get<double>(), 0.0) << key;
      }
    }
    // The structure's own counts per ray of each set (not Embree's, which does not count); the
    // incoherent set's also as nodes_per_ray and prims_per_ray.
    const bool ours = row["accel"] != "embree";
    EXPECT_EQ(row.contains("nodes_per_ray"), ours) << row.dump();
    EXPECT_EQ(row.contains("prims_per_ray"), ours) << row.dump();
    EXPECT_EQ(row.contains("per_ray"), ours) << row.dump();
    if (ours) {
      EXPECT_EQ(row["nodes_per_ray"], row["per_ray"]["incoherent"]["nodes"]);
      EXPECT_EQ(row["prims_per_ray"], row["per_ray"]["incoherent"]["prims"]);
      for (const char* set : {"primary", "incoherent", "occlusion", "bounce", "shadow"}) {
        const auto& c = row["per_ray"][set];
        EXPECT_GT(c["nodes"].get<double>(), 0.0) << set;
        EXPECT_GT(c["prims"].get<double>(), 0.0) << set;
        EXPECT_LE(c["prims"].get<double>(), 38.0) << set;  // the box's 38 triangles at most
      }
      // The incoherent rays split by hit and miss: the groups' means weighted by their sizes
      // are the whole set's, for the closest-hit and the any-hit queries.
      const double hits = row["incoherent_hits"].get<double>(), all = 500.0;
      EXPECT_GT(hits, 0.0);
      EXPECT_LE(hits, all);
      for (const char* set : {"incoherent", "occlusion"})
        for (const char* what : {"nodes", "prims"}) {
          const auto& p = row["per_ray"];
          const double split = hits * p[std::string(set) + "_hit"][what].get<double>() +
                               (all - hits) * p[std::string(set) + "_miss"][what].get<double>();
          EXPECT_NEAR(split, all * p[set][what].get<double>(), 1e-9 * all * 38.0)
              << set << " " << what;
        }
    }
  }
  EXPECT_NE(out_.find("per ray, nodes visited / primitive tests: primary"), std::string::npos)
      << out_;
  EXPECT_NE(out_.find("incoherent rays: "), std::string::npos) << out_;
  for (const char* bad : {"0", "x", "101"})
    EXPECT_NE(run("accel-bench " + scene("cornell-box.json") + " --accel bvh --repeat " + bad), 0)
        << bad;
}

// With several thread counts accel-bench prints one table with a group of throughput columns per
// count (sorted, duplicates merged), builds on the largest, and writes one run per count.
TEST_F(CliTest, AccelBenchMeasuresEveryThreadCountInOneTable) {
  ASSERT_EQ(
      run("accel-bench " + scene("cornell-box.json") +
          " --accel bvh,bvh:median --threads 2,1,2 --repeat 1 --rays 500 --json " + path("t.json")),
      0)
      << err_;
  for (const char* column :
       {"build ms", "MiB", "nodes", "depth", "refs/prim", "primary", "incoher.", "occlus.",
        "vs embree", "1 thread, Mrays/s", "2 threads, Mrays/s", "build ms at 2 threads"})
    EXPECT_NE(out_.find(column), std::string::npos) << column << "\n" << out_;
  EXPECT_LT(out_.find("1 thread, Mrays/s"), out_.find("2 threads, Mrays/s"));
  EXPECT_NE(out_.find("bvh:median "), std::string::npos) << out_;
  const auto rows = nlohmann::json::parse(slurp(path("t.json")));
  for (const auto& row : rows) {
    EXPECT_EQ(row["build_threads"], 2) << row.dump();
    ASSERT_EQ(row["runs"].size(), 2u) << row.dump();
    EXPECT_EQ(row["runs"][0]["threads"], 1);
    EXPECT_EQ(row["runs"][1]["threads"], 2);
  }
  // The default is 1 and all cores; bad counts are errors naming the item.
  ASSERT_EQ(run("accel-bench " + scene("cornell-box.json") + " --accel bvh --repeat 1 --rays 100"),
            0)
      << err_;
  EXPECT_NE(out_.find("1 thread, Mrays/s"), std::string::npos) << out_;
  for (const char* bad : {"0", "1,x", "1,", "-2", "5000"}) {
    EXPECT_NE(run("accel-bench " + scene("cornell-box.json") + " --accel bvh --threads " + bad), 0)
        << bad;
    EXPECT_NE(err_.find("is not a thread count"), std::string::npos) << bad << ": " << err_;
  }
}

// The scene of every distribution effect (docs/rendering.md, "All effects together") renders
// from the command line with sane brightness. Closing its shutter changes only what the moving
// ball reaches (its smear, shadow and reflections): the time is a sample dimension of its own, so
// every other pixel, the sky above the horizon included, stays bit-identical.
TEST_F(CliTest, DistributionSceneBlursOnlyWhatMoves) {
  const std::string args = " --resolution 64x48 --spp 4 --threads 2 -q -o ";
  ASSERT_EQ(run("render " + scene("distribution.json") + args + path("open.pfm")), 0) << err_;
  std::string text = slurp(scene("distribution.json"));
  const std::string shutter = "\"shutter\": [0, 1]";
  const auto at = text.find(shutter);
  ASSERT_NE(at, std::string::npos);
  write("still.json", text.replace(at, shutter.size(), "\"shutter\": [0, 0]"));
  ASSERT_EQ(run("render " + path("still.json") + args + path("still.pfm")), 0) << err_;
  const RgbImage open = read_pfm(path("open.pfm")), still = read_pfm(path("still.pfm"));
  ASSERT_EQ(open.width(), 64);
  ASSERT_EQ(open.height(), 48);
  double sum = 0;
  int differ = 0, differ_in_sky = 0;
  for (int y = 0; y < open.height(); ++y)
    for (int x = 0; x < open.width(); ++x) {
      const Rgb a = open.at(x, y), b = still.at(x, y);
      ASSERT_TRUE(std::isfinite(a.r) && std::isfinite(a.g) && std::isfinite(a.b)) << x << "," << y;
      sum += a.luminance();
      if (a.r != b.r || a.g != b.g || a.b != b.b) {
        ++differ;
        if (y < open.height() / 4) ++differ_in_sky;
      }
    }
  const double mean = sum / double(open.size());
  EXPECT_GT(mean, 0.05);  // 0.18 measured
  EXPECT_LT(mean, 1.0);
  EXPECT_GT(differ, int(open.size() / 100));  // 6.5% measured: the smear, shadow, reflections
  EXPECT_LT(differ, int(open.size() / 4));
  EXPECT_EQ(differ_in_sky, 0);
}

// Ctrl-C stops the render, keeps the finished tiles in a complete image file and exits with 130.
TEST_F(CliTest, InterruptWritesFinishedWorkAndExits130) {
  const std::string out = path("partial.pfm"), err = path("err.txt");
  const std::string cmd = std::string(PENUMBRA_CLI) + " render " + scene("whitted.json") +
                          " --spp 1024 --threads 2 -o " + out + " 2> " + err;
  pid_t pid = 0;
  const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
  // exec replaces the shell, so the signal reaches penumbra itself.
  const std::string exec_cmd = "exec " + cmd;
  argv[2] = exec_cmd.c_str();
  ASSERT_EQ(posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ), 0);
  // Wait until rendering has started (the first progress line), then interrupt.
  for (int i = 0; i < 600 && slurp(err).find("render:") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_EQ(kill(pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(err);
  EXPECT_NE(slurp(err).find("interrupted"), std::string::npos);
  // A complete PFM of the full size: header plus 640 x 480 RGB floats.
  const std::string pfm = slurp(out);
  const std::string header = "PF\n640 480\n-1.0\n";
  ASSERT_GE(pfm.size(), header.size());
  EXPECT_EQ(pfm.size(), pfm.find("\n", pfm.find("\n", 3) + 1) + 1 + 640u * 480u * 12u);
  for (const auto& entry : fs::directory_iterator(dir_))  // no temporary file left behind
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace penumbra
