// `penumbra radiosity` as a user runs it: the solved mesh as PLY, reused by a render, and clear
// errors for bad outputs and for a solution of another scene.
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "penumbra/image/image_io.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

class RadiosityCli : public CliFixture {};

TEST_F(RadiosityCli, WritesTheSolutionAndARenderReusesIt) {
  const std::string ply = path("cornell.ply");
  ASSERT_EQ(run("radiosity " + scene("cornell-box.json") + " -o " + ply), 0) << err_;
  for (const char* what : {"elements", "form factors", "row sums", "reciprocity", "iterations"})
    EXPECT_NE(err_.find(what), std::string::npos) << what << "\n" << err_;
  std::ifstream f(ply, std::ios::binary);
  std::string magic;
  std::getline(f, magic);
  EXPECT_EQ(magic, "ply");
  ASSERT_GT(fs::file_size(ply), 10000u);

  // The same image from the saved solution as from a fresh solve.
  ASSERT_EQ(run("render " + scene("cornell-box.json") +
                " --resolution 16x16 --spp 2 --integrator radiosity:final_gather=false -o " +
                path("solved.pfm")),
            0)
      << err_;
  ASSERT_EQ(run("render " + scene("cornell-box.json") +
                " --resolution 16x16 --spp 2 --integrator radiosity:final_gather=false,solution=" +
                ply + " -o " + path("loaded.pfm")),
            0)
      << err_;
  EXPECT_TRUE(read_image(path("solved.pfm")) == read_image(path("loaded.pfm")));

  // Another scene's solution is refused, naming the file, and no image is written.
  EXPECT_NE(run("render " + scene("caustic.json") +
                " --resolution 16x16 --spp 1 --integrator radiosity:solution=" + ply + " -o " +
                path("other.png")),
            0);
  EXPECT_NE(err_.find(ply), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(path("other.png")));
}

TEST_F(RadiosityCli, RefusesAnOutputThatIsNotPly) {
  EXPECT_NE(run("radiosity " + scene("cornell-box.json") + " -o " + path("x.png")), 0);
  EXPECT_NE(err_.find(".ply"), std::string::npos) << err_;
}

}  // namespace
}  // namespace penumbra
