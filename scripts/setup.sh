#!/usr/bin/env bash
# Installs the Debian packages the project needs (only those missing) and builds it.
# Usage: scripts/setup.sh            (build directory: $SMALLISO_BUILD_DIR, default ./build)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SMALLISO_BUILD_DIR:-$root/build}

source "$root/scripts/packages.sh"
smalliso_install_missing "${smalliso_packages[@]}"

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
