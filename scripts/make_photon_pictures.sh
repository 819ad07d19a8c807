#!/usr/bin/env bash
# Renders the photon-mapping pictures of docs/photon-mapping.md: the Cornell box, the caustic
# scene and the Cornell box with caustics by path, photon and sppm at equal render time, and the
# photon maps shown directly. Run from the repository root after a Release build.
set -euo pipefail
bin=${PENUMBRA:-build/penumbra}
t=${TIME_LIMIT:-20}
out=docs/images
for scene in cornell-box caustic cornell-box-caustics; do
  for integrator in path photon sppm; do
    "$bin" render scenes/$scene.json -q --integrator $integrator --spp 1000000 --time-limit "$t" \
      -o $out/$scene-$integrator-${t}s.png
  done
done
"$bin" render scenes/cornell-box.json -q --integrator photon:show=global --spp 16 \
  -o $out/cornell-box-photon-global-map.png
"$bin" render scenes/cornell-box-caustics.json -q --integrator photon:show=global --spp 16 \
  -o $out/cornell-box-caustics-photon-global-map.png
"$bin" render scenes/cornell-box-caustics.json -q --integrator photon:show=caustic --spp 16 \
  -o $out/cornell-box-caustics-photon-caustic-map.png
"$bin" render scenes/caustic.json -q --integrator photon:show=caustic --spp 16 \
  -o $out/caustic-photon-caustic-map.png
