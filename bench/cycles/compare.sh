#!/usr/bin/env bash
# Compares penumbra's path tracer with Blender Cycles on the Cornell box
# (docs/cycles-comparison.md).
#
#   bash bench/cycles/compare.sh [--install] [--spp 64] [--threads N] [--integrator path]
#        [--ref-spp 4096] [--reference penumbra|cycles|both] [--repeats K] [--resolution WxH]
#        [--out report.md] [--workdir DIR] [--penumbra build/penumbra] [--blender blender] ...
#
# --install installs Debian's blender and python3-numpy with apt-get (sudo when not root) if they
# are missing; without it a missing package is an error. Every other flag goes to run_compare.py
# (`bash bench/cycles/compare.sh --help` lists them). Optional: neither the build nor the tests
# need it.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"

# Debian's python3, which sees Debian's python3-numpy (a python3 earlier on PATH, e.g. pyenv's,
# may not).
py=/usr/bin/python3
[[ -x "$py" ]] || py=python3

install=0
args=()
for a in "$@"; do
  if [[ "$a" == "--install" ]]; then install=1; else args+=("$a"); fi
done

for a in ${args[@]+"${args[@]}"}; do
  [[ "$a" == "-h" || "$a" == "--help" ]] && exec "$py" "$here/run_compare.py" --help
done

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }

packages=(blender python3-numpy)
missing=()
for p in "${packages[@]}"; do installed "$p" || missing+=("$p"); done

if ((${#missing[@]})); then
  if ((install)); then
    sudo=""
    [[ $(id -u) -ne 0 ]] && sudo="sudo"
    echo "compare.sh: installing ${missing[*]} (apt-get)" >&2
    $sudo apt-get update
    $sudo apt-get install -y --no-install-recommends "${missing[@]}"
  else
    echo "compare.sh: missing Debian package(s): ${missing[*]}." >&2
    echo "  Run again with --install," \
      "or: sudo apt-get install --no-install-recommends ${missing[*]}" >&2
    exit 1
  fi
fi

if ! "$py" -c "import numpy" 2>/dev/null; then
  echo "compare.sh: $py cannot import numpy (Debian package python3-numpy)" >&2
  exit 1
fi

# A --blender or --penumbra given on the command line is checked by run_compare.py itself.
if [[ " ${args[*]-} " != *" --blender "* ]] && ! command -v blender >/dev/null; then
  echo "compare.sh: blender is not on PATH (install it with --install, or pass --blender PATH)" >&2
  exit 1
fi
if [[ " ${args[*]-} " != *" --penumbra "* && ! -x "$repo/build/penumbra" ]]; then
  echo "compare.sh: $repo/build/penumbra not found; build it first:" >&2
  echo "  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release && cmake --build build" >&2
  exit 1
fi

exec "$py" "$here/run_compare.py" ${args[@]+"${args[@]}"}
