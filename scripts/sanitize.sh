#!/usr/bin/env bash
# Builds penumbra with AddressSanitizer and UndefinedBehaviorSanitizer (PENUMBRA_SANITIZE=ON,
# Release optimisation, no benchmarks, no Embree) and runs the whole test suite under them: any
# report (memory error, leak, undefined behaviour) fails its test, since UBSan does not recover.
#   scripts/sanitize.sh [CTEST_ARGS...]      e.g. scripts/sanitize.sh -R Pbrt
# Environment: SANITIZE_BUILD_DIR (default build-sanitize).
# Measured on the 2-core machine: see docs/robustness.md, "Sanitizers".
set -euo pipefail
cd "$(dirname "$0")/.."
build=${SANITIZE_BUILD_DIR:-build-sanitize}
bash scripts/install-deps.sh
start=$(date +%s)
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_SANITIZE=ON \
  -DPENUMBRA_WITH_EMBREE=OFF -DPENUMBRA_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j"$(nproc)"
built=$(date +%s)
# allocator_may_return_null: the tests of refused huge allocations expect std::bad_alloc, which
# ASan otherwise turns into a report; the tests' children under RLIMIT_FSIZE need no change.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build" --output-on-failure -j"$(nproc)" --timeout 1800 "$@"
echo "sanitize.sh: build $((built - start)) s, tests $(($(date +%s) - built)) s"
