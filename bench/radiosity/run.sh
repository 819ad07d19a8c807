#!/bin/sh
# Hierarchical radiosity with and without clustering: top-level patches, clusters, nodes,
# leaves, links, memory and time at 1 and 2 threads, on the Cornell box and on the bunny room
# (bench/radiosity/bunny-room.json), as `penumbra radiosity` reports them.
#
#   bench/radiosity/run.sh [BUILD_DIR] [all]     (from the repository root; BUILD_DIR: build)
#
# With `all`, also the bunny room at patch=8 (about 165,000 display elements) and without
# clustering (18 million links, 1.5 GB and about two minutes a run).
set -eu
build=${1:-build}
more=${2:-}
out=${TMPDIR:-/tmp}/radiosity-bench.ply

run() {  # scene threads extra-parameters
  echo "== $1, $2 thread(s), radiosity:hierarchy=true$3"
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -f "wall %e s, max RSS %M KiB" "$build/penumbra" radiosity "$1" -o "$out" \
      --threads "$2" --integrator "radiosity:hierarchy=true$3" 2>&1 | grep -v "per iteration"
  else
    "$build/penumbra" radiosity "$1" -o "$out" --threads "$2" \
      --integrator "radiosity:hierarchy=true$3" 2>&1 | grep -v "per iteration"
  fi
}

for threads in 1 2; do
  run scenes/cornell-box.json "$threads" ""                 # 48 patches: no clusters (auto)
  run scenes/cornell-box.json "$threads" ",clusters=true"
  run bench/radiosity/bunny-room.json "$threads" ""         # 7,372 patches: clusters (auto)
done
if [ "$more" = all ]; then
  for threads in 1 2; do run bench/radiosity/bunny-room.json "$threads" ",patch=8"; done
  for threads in 1 2; do run bench/radiosity/bunny-room.json "$threads" ",clusters=false"; done
fi
