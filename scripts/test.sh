#!/usr/bin/env bash
# Builds penumbra in Release and runs the whole test suite (the README's second command; .ci/run
# runs it, then the fuzz smoke step).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)"
