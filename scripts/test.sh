#!/usr/bin/env bash
# Builds penumbra in Release and runs the whole test suite (what CI runs).
# PENUMBRA_FUZZ_SECONDS=N also runs each libFuzzer target N seconds on its committed corpus
# (scripts/fuzz.sh; about 20 is a useful smoke run) when clang with libFuzzer is installed. It is
# off by default: the fuzz build and 7 targets add several minutes to a suite that already takes
# about 10 on 2 cores (docs/robustness.md has the measurements).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
if [[ ${PENUMBRA_FUZZ_SECONDS:-0} -gt 0 ]]; then
  if command -v clang++ >/dev/null; then
    FUZZ_JOBS=$(nproc) bash scripts/fuzz.sh "$PENUMBRA_FUZZ_SECONDS"
  else
    echo "test.sh: clang++ not found, fuzz step skipped"
  fi
fi
