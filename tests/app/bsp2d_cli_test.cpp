// End-to-end tests of `penumbra bsp2d`: the path output, the SVG, the experiment, and errors that
// name FILE:LINE with a non-zero exit.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_fixture.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

/// End-to-end tests share the fixture of cli_fixture.h.
using Bsp2DCliTest = CliFixture;

const char* kExample =
    "# the example of tests/accel2d/segment_bsp_test.cpp\n"
    "0 0 4 0\n1 2 1 4\n3 1 3 3\n0 -2 4 -2\n2 -4 2 -3\n";

TEST_F(Bsp2DCliTest, PrintsSizeHitAndPathAndWritesAWellFormedSvg) {
  write("ex.txt", kExample);
  ASSERT_EQ(
      run("bsp2d " + path("ex.txt") + " --order first --ray 0.5,0.5,1,0.4 --svg " + path("ex.svg")),
      0)
      << err_;
  EXPECT_NE(out_.find("7 nodes (3 internal, 4 leaves), depth 2, 5 fragments"), std::string::npos)
      << out_;
  EXPECT_NE(out_.find("hit: s3 at t = 2.5"), std::string::npos) << out_;
  EXPECT_NE(out_.find("path: l1 l2 empty l2 s3\n"), std::string::npos) << out_;
  const std::string svg = slurp(path("ex.svg"));
  ASSERT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // Well-formed enough: every opened group is closed, the three labelled lines and the ray are in.
  size_t open = 0, close = 0;
  for (size_t at = svg.find("<g "); at != std::string::npos; at = svg.find("<g ", at + 1)) ++open;
  for (size_t at = svg.find("</g>"); at != std::string::npos; at = svg.find("</g>", at + 1))
    ++close;
  EXPECT_EQ(open, close);
  for (const char* label : {">l1<", ">l2<", ">l3<", ">s5<", "id=\"ray\""})
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  EXPECT_FALSE(fs::exists(path("ex.svg") + ".tmp"));
}

TEST_F(Bsp2DCliTest, EveryStructureAnswersTheSameHitOnRandomSegments) {
  std::string want;
  for (const char* s : {"bsp", "bsp:order=fewest-cuts", "quadtree", "kdtree", "grid", "brute"}) {
    ASSERT_EQ(run(std::string("bsp2d --random 500 --seed 3 --ray 0,10,1,0.3 --structure ") + s), 0)
        << s << ": " << err_;
    const size_t at = out_.find("hit: ");
    ASSERT_NE(at, std::string::npos);
    const std::string hit = out_.substr(at, out_.find('\n', at) - at);
    EXPECT_NE(hit, "hit: none");
    if (want.empty()) want = hit;
    EXPECT_EQ(hit, want) << s;
  }
}

TEST_F(Bsp2DCliTest, ObjectVariantNamesObjects) {
  write("obj.txt", "poly 0 0 2 0 2 2 0 2\npoly 3 0 5 0 4 2\npoly 6 0 8 0 8 2 6 2\nray -1 1 1 0\n");
  ASSERT_EQ(run("bsp2d " + path("obj.txt") + " --structure objects"), 0) << err_;
  EXPECT_NE(out_.find("hit: O1 at t = 1"), std::string::npos) << out_;
  EXPECT_NE(out_.find("path: l1 "), std::string::npos) << out_;
}

TEST_F(Bsp2DCliTest, SmallExperimentPrintsTheTableAndThePlot) {
  ASSERT_EQ(run("bsp2d --experiment fragments --max-n 300 --seeds 2 --svg " + path("plot.svg")), 0)
      << err_;
  EXPECT_NE(out_.find("frag/nln"), std::string::npos);
  EXPECT_NE(out_.find("comb     first            300     1     45150.0"), std::string::npos)
      << out_;
  const std::string svg = slurp(path("plot.svg"));
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST_F(Bsp2DCliTest, BadInputExitsNonZeroNamingFileAndLine) {
  const std::pair<const char*, const char*> cases[] = {
      {"0 0 1 1\n2 2 2 2\n", ":2: zero-length segment"},
      {"0 0 1 1\n\n0 0 one 1\n", ":3: 'one' is not a finite number"},
      {"0 0 2 2\n0 2 2 0\n", ":2: the segment crosses or touches the segment at line 1"},
      {"0 0 2 0\n# c\n1 0 3 0\n", ":3: the segment overlaps (collinear) the segment at line 1"},
  };
  for (const auto& [text, want] : cases) {
    write("bad.txt", text);
    EXPECT_EQ(run("bsp2d " + path("bad.txt")), 1) << text;
    EXPECT_NE(err_.find(path("bad.txt") + want), std::string::npos) << err_;
  }
  EXPECT_EQ(run("bsp2d " + path("missing.txt")), 1);
  EXPECT_NE(err_.find("missing.txt: cannot open"), std::string::npos) << err_;
  EXPECT_EQ(run("bsp2d --random 10 --ray 1,2,3"), 1);
  EXPECT_NE(err_.find("--ray"), std::string::npos) << err_;
  EXPECT_EQ(run("bsp2d --random 10 --structure octree"), 1);
  EXPECT_NE(err_.find("valid: bsp"), std::string::npos) << err_;
  EXPECT_EQ(run("bsp2d --random 10 --structure grid --order first"), 1);
  EXPECT_NE(run("bsp2d"), 0);
}

}  // namespace
}  // namespace penumbra
