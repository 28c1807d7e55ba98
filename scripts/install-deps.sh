#!/usr/bin/env bash
# Installs the Debian 12 packages effigi builds against. Idempotent: apt-get runs
# only when a package is missing, so a second `make render` costs a dpkg query.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  libembree-dev        # Embree 3: the default accelerator
  libopenimageio-dev   # bitmap textures, envmaps, non-EXR references (loaded only where used)
  openimageio-tools    # oiiotool: region means and relMSE in the bench/ scripts
  libopenexr-dev       # EXR output
  libglm-dev           # vector math
  libosd-dev           # OpenSubdiv (subdivision surfaces)
  catch2               # unit tests (v2)
  libtbb-dev           # parallel tiles
  libpugixml-dev       # XML scenes
  libtinyobjloader-dev # OBJ meshes
  libfmt-dev           # formatting
  zlib1g-dev           # Mitsuba .serialized meshes
  libopenvdb-dev libboost-dev  # .vdb grid volumes (volume/vdbvolume only; OpenVDB's headers need Boost's)
  clang-14 libfuzzer-14-dev libclang-rt-14-dev  # `make fuzz`: libFuzzer + ASan/UBSan (the fuzz preset)
  libopenmpi-dev openmpi-bin  # `mpirun -np N effigi render` (CMake option EFFIGI_MPI; docs/cluster.md)
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module effigi (python/) and its tests
  libcpp-httplib-dev   # `effigi render --preview`: the live page's HTTP server (apps/effigi/preview_server.cpp)
  chromium             # tests/test_preview.cpp: loads the preview page headless and checks its screenshot
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The Python module's tests need numpy and pytest in the Python that `python3` runs (the
# one CMake builds the module for): Debian's gets them from the packages above, another
# one (pyenv, a virtual environment) from pip.
if command -v python3 >/dev/null && ! python3 -c "import numpy, pytest" 2>/dev/null; then
  echo "install-deps: installing numpy and pytest with pip for $(command -v python3)" >&2
  python3 -m pip install --quiet numpy pytest
fi
