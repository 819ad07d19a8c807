/// The penumbra command-line program: all work happens in app/.
#include <cstdio>
#include <cstdlib>

#include "penumbra/app/cli.h"
#include "penumbra/core/cpu_check.h"

namespace {

/// Stops the program, before any of its code runs, on a CPU without the instruction-set
/// extensions it was compiled for (core/cpu_check.h): priority 101 runs before every C++ static
/// initialiser of the program, which may already use them. Compiled for the x86-64 baseline, and
/// calls only the C library.
[[gnu::constructor(101)]] PENUMBRA_BASELINE_X86 void stop_on_a_cpu_without_the_build_s_isa() {
  const char* missing[penumbra::kMaxCpuFeatures];
  const int n = penumbra::missing_cpu_features(std::getenv("PENUMBRA_CPU_LACKS"), missing);
  if (n == 0) return;
  std::fputs(
      "penumbra: error: this program was compiled for instruction-set extensions that this "
      "CPU does not have:",
      stderr);
  for (int i = 0; i < n; ++i) {
    std::fputs(i ? ", " : " ", stderr);
    std::fputs(missing[i], stderr);
  }
  std::fputs(
      ". It was built for another machine's CPU (-march=native, the default). Build it on "
      "this machine (the README's first command), or configure with -DPENUMBRA_NATIVE=OFF "
      "for a build that runs on any x86-64 CPU.\n",
      stderr);
  std::_Exit(1);  // nothing to clean up: no static object of the program is constructed yet
}

}  // namespace

int main(int argc, char** argv) {
  return penumbra::app::run_cli(argc, argv);
}
