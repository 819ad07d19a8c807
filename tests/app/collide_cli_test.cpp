// Tests of the `collide` subcommand, run in-process on the unit cube of tests/data: answers,
// agreement with brute force, the JSON output and the error messages.
#include <gtest/gtest.h>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "penumbra/app/collide_command.h"
#include "penumbra/core/error.h"

namespace penumbra::app {
namespace {

const std::string kCube = std::string(PENUMBRA_TEST_DATA) + "/meshes/cube.obj";

/// Runs `collide ARGS` in a fresh CLI app; returns what it printed on stdout.
std::string collide(const std::string& args) {
  CLI::App app{"test"};
  app.require_subcommand(1);
  add_collide_command(app);
  ::testing::internal::CaptureStdout();
  try {
    app.parse("collide " + args, false);
  } catch (...) {
    ::testing::internal::GetCapturedStdout();
    throw;
  }
  return ::testing::internal::GetCapturedStdout();
}

/// The message of the Error that `collide ARGS` throws ("" when none).
std::string error_of(const std::string& args) {
  try {
    collide(args);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(CollideCommand, OverlappingCubesAgreeWithBruteForce) {
  const std::string out = collide(kCube + " " + kCube + " --translate-b 0.5,0.25,0.125 --brute");
  EXPECT_NE(out.find("intersecting triangle pairs"), std::string::npos) << out;
  EXPECT_NE(out.find("same answer"), std::string::npos) << out;
  EXPECT_EQ(out.find("DIFFERENT"), std::string::npos) << out;
}

TEST(CollideCommand, SeparatedCubesHaveNoPairs) {
  const std::string out = collide(kCube + " " + kCube + " --translate-b 2,0,0 --scale-b 0.5");
  EXPECT_NE(out.find(": 0 found"), std::string::npos) << out;
}

TEST(CollideCommand, JsonListsEveryPairAndTheBruteForceComparison) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("penumbra-collide-" + std::to_string(::getpid()) + ".json");
  // Touching cubes: B's face x = 0 lies on A's face x = 1 after the rotation by 90 degrees about z
  // (which maps the unit cube onto [-1, 0] x [0, 1] x [0, 1]) and the translation by 2 in x.
  collide(kCube + " " + kCube + " --rotate-b 90,0,0,1 --translate-b 2,0,0 --brute --max-print 0 " +
          "--json " + path.string());
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in);
  std::filesystem::remove(path);
  ASSERT_TRUE(j.contains("pairs"));
  const auto& pairs = j["pairs"];
  EXPECT_GT(pairs["count"].get<size_t>(), 0u);
  EXPECT_EQ(pairs["list"].size(), pairs["count"].get<size_t>());
  EXPECT_TRUE(pairs["brute"]["agree"].get<bool>());
  EXPECT_EQ(j["a"]["triangles"].get<size_t>(), 12u);
}

TEST(CollideCommand, SphereDroppedOnTheTopFaceTouchesItsTwoTriangles) {
  const std::string out = collide(kCube + " --sphere 0.5,0.5,3,0.5 --to 0.5,0.5,1.5 --brute");
  EXPECT_NE(out.find(": 2 found"), std::string::npos) << out;
  EXPECT_NE(out.find("  2 3\n"), std::string::npos) << out;
  EXPECT_NE(out.find("same answer"), std::string::npos) << out;
}

TEST(CollideCommand, BoxSweptThroughTheCubeTouchesEveryTriangle) {
  const std::string out = collide(kCube + " --box -3,-0.5,-0.5,-2,1.5,1.5 --to 6,0,0 --brute");
  EXPECT_NE(out.find(": 12 found"), std::string::npos) << out;
  EXPECT_NE(out.find("same answer"), std::string::npos) << out;
}

TEST(CollideCommand, BadInputGivesClearErrors) {
  EXPECT_NE(error_of(kCube + " " + kCube + " --translate-b 1,2").find("expected 3"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " " + kCube + " --translate-b 1,x,2").find("'x' is not a finite"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " " + kCube + " --scale-b 0").find("must not be zero"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " " + kCube + " --rotate-b 10,0,0,0").find("zero length"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " --sphere 0,0,0,-1").find("negative"), std::string::npos);
  EXPECT_NE(error_of(kCube + " --box 1,0,0,0,1,1").find("exceeds"), std::string::npos);
  EXPECT_NE(error_of(kCube + " --sphere 0,0,0,1 --box 0,0,0,1,1,1").find("not both"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " --to 1,2,3").find("needs --sphere or --box"), std::string::npos);
  EXPECT_NE(error_of(kCube).find("give a second mesh"), std::string::npos);
  EXPECT_NE(error_of("/no/such/mesh.obj " + kCube).find("/no/such/mesh.obj"), std::string::npos);
  EXPECT_NE(error_of(kCube + " " + kCube + " --sphere 0,0,0,inf").find("not a finite"),
            std::string::npos);
}

// Coordinates beyond kMaxCoordinate (1e12) are refused as the scene loader refuses them: a pose
// scaling B by 1e300 made every float box infinite and brute force ran for minutes; a sphere of
// radius 1e30 or a translation of 1e39 gave answers from overflowed boxes.
TEST(CollideCommand, CoordinatesBeyondTheLimitAreRefused) {
  EXPECT_NE(error_of(kCube + " " + kCube + " --scale-b 1e300")
                .find("the pose of B (scale 1e+300)"
                      " moves a vertex of triangle 0"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " " + kCube + " --translate-b 2e12,0,0")
                .find("--translate-b: 2e+12 "
                      "is beyond +-1e+12"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " --sphere 0,0,0,1e30").find("--sphere: 1e+30 is beyond"),
            std::string::npos);
  EXPECT_NE(error_of(kCube + " --box 0,0,0,1,1,1 --to 1e13,0,0").find("--to: 1e+13 is beyond"),
            std::string::npos);
  EXPECT_EQ(error_of(kCube + " " + kCube + " --scale-b 1e11 --translate-b 1e11,0,0"), "");
}

}  // namespace
}  // namespace penumbra::app
