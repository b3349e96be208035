#!/usr/bin/env bash
# Installs the Debian packages the project needs (only those missing) and builds it.
# Usage: scripts/setup.sh            (build directory: $SMALLISO_BUILD_DIR, default ./build)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SMALLISO_BUILD_DIR:-$root/build}

packages=(
  build-essential cmake ninja-build pkg-config
  libinsighttoolkit5-dev  # ITK 5.2.1
  libgtest-dev            # GoogleTest
  zlib1g-dev              # the tools' streamed image files
  python3                 # test helpers (XML and JSON checks)
  clang-format            # the format check of scripts/test.sh
  gnuplot-nox             # SmallIsoComponentReport --plot
  libvtk9-dev libx11-dev  # isosurfaces, piece counts and --render (optional for the module)
  xvfb libgl1-mesa-dri    # off-screen rendering on a machine without a display
  # The smalliso Python package (NumPy and Dask), its tests and its benchmark
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3-dask python3-distributed python3-zarr python3-skimage
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing missing Debian packages: ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
    sudo=sudo
  fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# SlicerExecutionModel, for the test that reads the filter's --xml with Slicer's own parser: a source
# tree, archive or build tree named by $SMALLISO_SLICER_EXECUTION_MODEL, else the archive in the
# folder of third-party sources beside the repository when there is one.
sem=${SMALLISO_SLICER_EXECUTION_MODEL:-}
if [ -z "$sem" ]; then
  sem=$(ls "$root"/../shared/vendor/SlicerExecutionModel-*.tar.gz 2>/dev/null | head -n 1 || true)
fi
if [ -n "$sem" ]; then
  echo "setup: Slicer's parser test uses SlicerExecutionModel from $sem"
else
  echo "setup: no SlicerExecutionModel found (set SMALLISO_SLICER_EXECUTION_MODEL): the Slicer parser test will be skipped"
fi

echo "setup: configuring and building in $build"
# Debian's interpreter, which has Debian's Python packages (another python3 may come first on PATH).
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=ON \
  -DPython3_EXECUTABLE="${SMALLISO_PYTHON:-/usr/bin/python3}" \
  -DSmallIsoComponent_SLICER_EXECUTION_MODEL="$sem" >"$build.configure.log" 2>&1 || {
  cat "$build.configure.log" >&2; exit 1; }
cmake --build "$build" -j "$(nproc)"
