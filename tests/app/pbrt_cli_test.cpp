/// End-to-end tests of `penumbra render scene.pbrt`: the pbrt reader is chosen by extension, its
/// warnings are printed, and its errors name FILE:LINE:COLUMN and exit non-zero.
#include <gtest/gtest.h>

#include "cli_fixture.h"
#include "penumbra/image/image_io.h"

namespace penumbra {
namespace {

class PbrtCli : public CliFixture {};

TEST_F(PbrtCli, RendersAPbrtSceneAndPrintsItsWarnings) {
  const std::string scene = std::string(PENUMBRA_TEST_DATA) + "/pbrt/two-spheres.pbrt";
  ASSERT_EQ(run("render " + scene + " --spp 2 -q -o " + path("out.pfm")), 0) << err_;
  const RgbImage img = read_image(path("out.pfm"));
  EXPECT_EQ(img.width(), 48);  // the Film's resolution
  EXPECT_EQ(img.height(), 32);
  EXPECT_NE(err_.find("warning: " + scene + ":6:1: Film filename \"two-spheres.exr\" ignored"),
            std::string::npos)
      << err_;
}

TEST_F(PbrtCli, ErrorsNameTheirPlaceAndExitNonZero) {
  write("bad.pbrt", "WorldBegin\n  Shape \"sphere\" \"float radius\" \"big\"\n");
  EXPECT_NE(run("render " + path("bad.pbrt") + " -q -o " + path("out.pfm")), 0);
  EXPECT_NE(err_.find(path("bad.pbrt") + ":2:33: parameter \"float radius\": expected a number"),
            std::string::npos)
      << err_;
}

}  // namespace
}  // namespace penumbra
