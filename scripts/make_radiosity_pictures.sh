#!/usr/bin/env bash
# Renders the radiosity pictures of docs/radiosity.md (256 x 256, the Cornell box) and the
# solvers' convergence plot. Usage: bash scripts/make_radiosity_pictures.sh [build/penumbra]
set -euo pipefail
cd "$(dirname "$0")/.."
P=${1:-build/penumbra}
S=scenes/cornell-box.json
I=docs/images
"$P" render $S -o $I/cornell-box-radiosity.png --integrator radiosity --spp 256 --quiet
"$P" render $S -o $I/cornell-box-radiosity-gouraud.png --integrator radiosity:final_gather=false,form_factors=hemicube --spp 16 --quiet
"$P" render $S -o $I/cornell-box-radiosity-mesh.png --integrator radiosity:show=elements --spp 4 --quiet
"$P" render $S -o $I/cornell-box-radiosity-adaptive.png --integrator radiosity:final_gather=false,form_factors=hemicube,adapt=2 --spp 16 --quiet
"$P" render $S -o $I/cornell-box-radiosity-adaptive-mesh.png --integrator radiosity:show=elements,form_factors=hemicube,adapt=2 --spp 4 --quiet
"$P" render $S -o $I/cornell-box-radiosity-hierarchy.png --integrator radiosity:final_gather=false,hierarchy=true --spp 16 --quiet
python3 bench/radiosity/convergence.py --penumbra "$P" --scene $S --svg $I/radiosity-convergence.svg
