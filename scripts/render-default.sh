#!/usr/bin/env bash
# Builds penumbra in Release and renders the bundled default scene, the Cornell box.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
./build/penumbra render scenes/cornell-box.json -o cornell-box.png
