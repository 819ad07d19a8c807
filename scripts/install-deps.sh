#!/usr/bin/env bash
# Installs penumbra's build and test dependencies from Debian 12 packages. Idempotent: packages
# already installed are not fetched again, so a second run needs no network.
#   scripts/install-deps.sh          what the build and the tests need
#   scripts/install-deps.sh --fuzz   also clang with libFuzzer and the sanitizer runtimes, for
#                                    scripts/fuzz.sh (the CI's fuzz step)
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  python3   # the test that compiles every instruction-set branch (scripts/check_isa.py)
  libtbb-dev nlohmann-json3-dev libcli11-dev libfmt-dev libopenexr-dev libpng-dev
  libjpeg62-turbo-dev   # image/jpeg.cpp: JPEG textures (glTF's usual image type)
  libtinygltf-dev   # header only: scene/gltf_model.cpp compiles the implementation
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev   # optional: only the accel-bench comparison row uses it
)
if [[ ${1:-} == --fuzz ]]; then
  packages+=(clang libclang-rt-14-dev)  # Debian 12's clang 14; libFuzzer is in the runtime package
elif [[ -n ${1:-} ]]; then
  echo "install-deps.sh: unknown option '$1' (valid: --fuzz)" >&2
  exit 2
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "installing: ${missing[*]}" >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
