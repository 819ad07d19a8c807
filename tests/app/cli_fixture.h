#pragma once
// A fixture for end-to-end tests of the penumbra program: a fresh directory per test and a way
// to run the program and read what it printed.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace penumbra {

/// A fresh directory for one test, removed afterwards; runs the program (PENUMBRA_CLI).
class CliFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("penumbra-" + std::string(info->test_suite_name()) + "-" + std::to_string(::getpid()) +
            "-" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Runs the program with `args`; returns its exit code, stdout in out_, stderr in err_.
  int run(const std::string& args) {
    const std::string cmd = std::string(PENUMBRA_CLI) + " " + args + " > " + path("stdout.txt") +
                            " 2> " + path("stderr.txt") + " < /dev/null";
    const int status = std::system(cmd.c_str());
    out_ = slurp(path("stdout.txt"));
    err_ = slurp(path("stderr.txt"));
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  /// The whole content of file `p` (empty when it cannot be read).
  static std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  /// A file in the test's directory.
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Writes `text` to a file in the test's directory.
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name, std::ios::binary) << text;
  }
  /// A bundled scene (or mesh) under scenes/.
  static std::string scene(const std::string& name) {
    return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name;
  }

  std::filesystem::path dir_;
  std::string out_, err_;
};

}  // namespace penumbra
