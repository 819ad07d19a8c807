/// End-to-end tests of `penumbra convert`: a pbrt scene becomes a JSON scene with PLY meshes
/// that `penumbra render` reads; bad outputs are refused before anything is written.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_fixture.h"
#include "penumbra/image/image_io.h"

namespace penumbra {
namespace {

class ConvertCli : public CliFixture {};

TEST_F(ConvertCli, PbrtBecomesAJsonSceneThatRendersLikeIt) {
  const std::string scene = std::string(PENUMBRA_TEST_DATA) + "/pbrt/two-spheres.pbrt";
  ASSERT_EQ(run("convert " + scene + " -o " + path("two.json")), 0) << err_;
  EXPECT_NE(err_.find("wrote " + path("two.json")), std::string::npos) << err_;
  EXPECT_TRUE(std::filesystem::is_directory(path("two-meshes")));
  ASSERT_EQ(run("render " + scene + " --spp 2 -q -o " + path("a.pfm")), 0) << err_;
  ASSERT_EQ(run("render " + path("two.json") + " --spp 2 -q -o " + path("b.pfm")), 0) << err_;
  const RgbImage a = read_image(path("a.pfm")), b = read_image(path("b.pfm"));
  ASSERT_EQ(a.width(), b.width());
  size_t differing = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) differing += !(a.at(x, y) == b.at(x, y));
  EXPECT_EQ(differing, 0u);
}

TEST_F(ConvertCli, BadOutputsAreRefusedAndNothingIsWritten) {
  const std::string scene = std::string(PENUMBRA_TEST_DATA) + "/pbrt/two-spheres.pbrt";
  EXPECT_NE(run("convert " + scene + " -o " + path("two.pbrt")), 0);
  EXPECT_NE(err_.find("name it *.json"), std::string::npos) << err_;
  EXPECT_NE(run("convert " + scene + " -o " + path("x.json") + " --mesh-dir ../up"), 0);
  EXPECT_NE(err_.find("--mesh-dir ../up: must be a folder below"), std::string::npos) << err_;
  EXPECT_NE(run("convert " + path("missing.pbrt") + " -o " + path("y.json")), 0);
  EXPECT_FALSE(std::filesystem::exists(path("y.json")));
  EXPECT_FALSE(std::filesystem::exists(path("y-meshes")));
}

}  // namespace
}  // namespace penumbra
