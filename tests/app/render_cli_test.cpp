// `penumbra render` as a user runs it: the progressive loop's flags, signals and outputs.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "cli_fixture.h"
#include "penumbra/image/image_io.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

class RenderCli : public CliFixture {};

/// No 8 x 8 tile of the image at `p` is black (the render's tiles are 16 x 16; the Cornell box's
/// camera sees past the box along the image's bottom row, so single black pixels are expected).
void expect_no_black_tiles(const std::string& p) {
  const RgbImage img = read_image(p);
  ASSERT_GT(img.width(), 0);
  for (int ty = 0; ty < img.height(); ty += 8)
    for (int tx = 0; tx < img.width(); tx += 8) {
      float brightest = 0.0f;
      for (int y = ty; y < std::min(ty + 8, img.height()); ++y)
        for (int x = tx; x < std::min(tx + 8, img.width()); ++x)
          brightest = std::max(brightest, img.at(x, y).max_channel());
      EXPECT_GT(brightest, 0.0f) << p << ": tile at " << tx << "," << ty;
    }
}

TEST_F(RenderCli, PathTracesTheCornellBoxAndReportsItsRates) {
  ASSERT_EQ(run("render " + scene("cornell-box.json") + " --resolution 32x32 --spp 8 -o " +
                path("out.exr")),
            0)
      << err_;
  expect_no_black_tiles(path("out.exr"));
  for (const char* what : {"path:strategy=mis", "Msamples/s", "Mrays/s", "traversal", "8 spp"})
    EXPECT_NE(err_.find(what), std::string::npos) << what << "\n" << err_;
}

// An instanced scene renders and reports its instances, objects and geometry memory; radiosity
// refuses it by name.
TEST_F(RenderCli, InstancedSceneReportsItsInstances) {
  ASSERT_EQ(run("render " + scene("instances.json") + " --resolution 32x20 --spp 1 -o " +
                path("out.png")),
            0)
      << err_;
  EXPECT_NE(err_.find("49 instances of 1 objects (3674 primitives stored once)"), std::string::npos)
      << err_;
  EXPECT_NE(run("render " + scene("instances.json") +
                " --resolution 16x16 --integrator radiosity -o " + path("r.png")),
            0);
  EXPECT_NE(err_.find("scenes with instanced objects are not supported"), std::string::npos)
      << err_;
}

// An output that cannot be written is refused before the render starts (it used to be found
// only after the whole render), and nothing is created.
TEST_F(RenderCli, UnwritableOutputIsRefusedBeforeRendering) {
  const std::string cb = scene("cornell-box.json") + " --spp 4096 --quiet";
  EXPECT_NE(run("render " + cb + " -o " + path("missing/dir/out.png")), 0);
  EXPECT_NE(err_.find("directory '" + path("missing/dir") + "' does not exist"), std::string::npos)
      << err_;
  EXPECT_EQ(err_.find("render "), std::string::npos) << err_;  // no render summary
  write("file", "x");
  EXPECT_NE(run("render " + cb + " -o " + path("file/out.exr")), 0);
  EXPECT_NE(err_.find("is not a directory"), std::string::npos) << err_;
  EXPECT_NE(run("render " + cb + " -o " + path("a.pfm") + " --variance " + path("no/v.pfm")), 0);
  EXPECT_NE(err_.find("does not exist"), std::string::npos) << err_;
  EXPECT_FALSE(std::filesystem::exists(path("a.pfm")));
}

TEST_F(RenderCli, OutputsThatMustNotBeReplacedAreRefusedBeforeRendering) {
  const std::string cb = scene("cornell-box.json") + " --spp 4096 --quiet";
  // A link to /dev/full: the rename would replace the link, and writing through it cannot work.
  std::filesystem::create_symlink("/dev/full", path("full.png"));
  EXPECT_EQ(run("render " + cb + " -o " + path("full.png")), 1);
  EXPECT_NE(err_.find(path("full.png") + ": cannot write: it is a character device"),
            std::string::npos)
      << err_;
  EXPECT_TRUE(std::filesystem::is_symlink(path("full.png")));
  // A read-only file keeps its bytes.
  write("old.exr", "keep me");
  std::filesystem::permissions(path("old.exr"), std::filesystem::perms::owner_read);
  EXPECT_EQ(run("render " + cb + " -o " + path("old.exr")), 1);
  EXPECT_NE(err_.find("the file exists and is read-only"), std::string::npos) << err_;
  EXPECT_EQ(err_.find("render "), std::string::npos) << err_;  // no render summary
}

TEST_F(RenderCli, AllocationsBeyondTheMemoryLimitAreRefusedNamingTheOption) {
  const std::string cb = scene("cornell-box.json") + " --quiet -o " + path("out.png");
  EXPECT_EQ(run("render " + cb + " --resolution 65536x65536"), 1);
  EXPECT_NE(err_.find("--resolution 65536x65536: the film needs "), std::string::npos) << err_;
  EXPECT_NE(err_.find("more than the memory limit"), std::string::npos) << err_;
  EXPECT_EQ(run("render " + cb + " --resolution 2048x2048 --max-memory 100M"), 1);
  EXPECT_NE(err_.find("memory limit of 100.0 MiB (set by --max-memory)"), std::string::npos)
      << err_;
  EXPECT_EQ(run("render " + cb + " --max-memory 12Q"), 1);
  EXPECT_NE(err_.find("--max-memory: '12Q' is not a memory size"), std::string::npos) << err_;
  EXPECT_FALSE(std::filesystem::exists(path("out.png")));
  // The limit is the option's only effect when the render fits in it.
  ASSERT_EQ(run("render " + cb + " --resolution 16x16 --spp 1 --max-memory 1G"), 0) << err_;
  EXPECT_TRUE(std::filesystem::exists(path("out.png")));
}

TEST_F(RenderCli, TimeLimitStopsAndReportsTheSppReached) {
  ASSERT_EQ(run("render " + scene("cornell-box.json") +
                " --resolution 32x32 --spp 1000000 --time-limit 1 -o " + path("out.pfm")),
            0)
      << err_;
  EXPECT_NE(err_.find("time limit"), std::string::npos) << err_;
  // The Cornell box samples with Sobol' points made for --spp: the user is told.
  EXPECT_NE(err_.find("keeps a prefix"), std::string::npos) << err_;
  expect_no_black_tiles(path("out.pfm"));
}

TEST_F(RenderCli, VarianceAndTargetErrorAreWritten) {
  ASSERT_EQ(run("render " + scene("cornell-box.json") +
                " --resolution 24x24 --spp 100000 --target-error 0.2 --variance " +
                path("var.exr") + " -o " + path("out.exr")),
            0)
      << err_;
  EXPECT_NE(err_.find("error target"), std::string::npos) << err_;
  EXPECT_NE(err_.find("mean relative error"), std::string::npos) << err_;
  const RgbImage var = read_image(path("var.exr"));
  EXPECT_EQ(var.width(), 24);
  EXPECT_GT(var.at(12, 12).g, 0.0f);
  // A PNG cannot hold a variance: refused before any work.
  EXPECT_NE(run("render " + scene("cornell-box.json") + " --variance " + path("v.png") + " -o " +
                path("o.exr")),
            0);
  EXPECT_NE(err_.find("--variance"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(path("o.exr")));
}

TEST_F(RenderCli, CheckpointsWriteTheImageWhileRendering) {
  ASSERT_EQ(run("render " + scene("cornell-box.json") +
                " --resolution 32x32 --spp 1000000 --time-limit 2.5 --checkpoint 0.5 -o " +
                path("out.png")),
            0)
      << err_;
  EXPECT_NE(err_.find("checkpoint:"), std::string::npos) << err_;
  EXPECT_TRUE(fs::exists(path("out.png")));
}

// SIGINT and SIGTERM stop a long render within about a second; the image of every finished
// sample is written (no black tiles) and the exit status is 130.
TEST_F(RenderCli, InterruptWritesTheFinishedSamplesAndExits130) {
  for (const int sig : {SIGINT, SIGTERM}) {
    const std::string out = path("interrupted-" + std::to_string(sig) + ".pfm");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      const std::string cli = PENUMBRA_CLI;
      freopen("/dev/null", "w", stderr);
      execl(cli.c_str(), cli.c_str(), "render", scene("cornell-box.json").c_str(), "--resolution",
            "48x48", "--spp", "1000000", "-o", out.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    const auto sent = std::chrono::steady_clock::now();
    kill(pid, sig);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    EXPECT_LT(waited, 2.0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    ASSERT_TRUE(fs::exists(out));
    expect_no_black_tiles(out);
  }
}

}  // namespace
}  // namespace penumbra
