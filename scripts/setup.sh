#!/usr/bin/env bash
# Installs the Debian 12 packages pbs needs (only those missing, with sudo when not root) and builds
# pbs in Release into build/. Warnings are errors when CI=true.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake ninja-build g++ pkg-config libglm-dev libembree-dev libopenimageio-dev libpng-dev openimageio-tools
          libtinygltf-dev libsimdjson-dev nlohmann-json3-dev libtbb-dev libgtest-dev libcli11-dev libmeshoptimizer-dev
          libcpp-httplib-dev libjpeg62-turbo-dev   # pbs view: its HTTP server and its moving frames
          chromium chromium-driver                 # pbs view's browser test (headless Chromium)
          libosmesa6   # libosmesa6: Mesa llvmpipe, the peer `pbs bench raster` measures against
          clang libclang-rt-14-dev   # scripts/fuzz.sh: clang with libFuzzer (-fsanitize=fuzzer)
          clang-format               # scripts/format.sh: the formatting CI checks
          slurm-wlm munge)           # tests/cluster: a one-node Slurm on localhost runs the surfelize job array
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  as_root=()
  [ "$(id -u)" -eq 0 ] || as_root=(sudo)
  echo "setup: installing ${missing[*]}"
  "${as_root[@]}" apt-get update -qq
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
cmake --preset release -DPBS_WERROR="$werror" >/dev/null  # CMakePresets.json: build/, Release
cmake --build --preset release -j"$(nproc)"
