#!/usr/bin/env bash
# Installs the Debian packages deploysim needs to build, test and plot — only those
# that are missing. Runs apt-get as root, or through sudo when not root.
# Usage: tools/install_deps.sh
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache  # ccache: compiled objects kept in ~/.cache
  libeigen3-dev libboost-dev
  libgtest-dev
  libyaml-cpp-dev libhdf5-dev hdf5-tools
  libsimbody-dev libcli11-dev libfmt-dev
  python3-matplotlib python3-h5py python3-numpy python3-mpmath
  pybind11-dev python3-pybind11 python3-dev python3-pytest python3-pandas  # Python package
  libopenmpi-dev openmpi-bin        # optional MPI sweeps (cmake -DDEPLOYSIM_WITH_MPI=ON)
  clang libfuzzer-14-dev            # fuzz targets (tools/fuzz.sh, cmake -DDEPLOYSIM_FUZZ=ON)
  chromium                          # headless page tests (tools/headless_chromium.py)
  libjs-three ffmpeg                # 3D viewer (three.js r111) and animations (MP4, GIF)
  python3-venv python3-setuptools python3-wheel python3-pip  # pip install . (setup.py)
  python3-yaml                      # the tools behind deploysim.view and deploysim.report
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "install_deps: missing packages (${missing[*]}) and not root, no sudo" >&2
  exit 1
fi

echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
