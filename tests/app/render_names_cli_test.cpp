// `penumbra render` with a wrong registered name: the message says where the name came from —
// the command-line option, or the scene file and its JSON path (issue #18).
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.h"

namespace penumbra {
namespace {

class RenderNamesCli : public CliFixture {};

TEST_F(RenderNamesCli, BadOptionNamesTheOption) {
  for (const std::string option :
       {"--accel octopus", "--integrator pathh", "--sampler halton", "--filter sinc"}) {
    EXPECT_NE(run("render " + scene("cornell-box.json") + " " + option + " -o " + path("o.pfm")),
              0);
    const std::string flag = option.substr(0, option.find(' '));
    EXPECT_NE(err_.find(flag + ": unknown"), std::string::npos) << option << "\n" << err_;
    EXPECT_EQ(err_.find("/render/"), std::string::npos) << err_;
  }
}

TEST_F(RenderNamesCli, BadSceneNameNamesTheFileAndPath) {
  const std::string file = path("s.json");
  std::ofstream(file)
      << R"({"camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},
    "render": {"resolution": [8, 8], "sampler": "halton"},
    "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})";
  EXPECT_NE(run("render " + file + " -o " + path("o.pfm")), 0);
  EXPECT_NE(err_.find(file + ":/render/sampler: unknown sampler 'halton'"), std::string::npos)
      << err_;
}

}  // namespace
}  // namespace penumbra
