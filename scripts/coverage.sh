#!/usr/bin/env bash
# Builds the project with gcc's line coverage (--coverage, -O1) in a build directory of its
# own, runs the whole test suite there, and prints the line coverage of include/ and src/
# (gcovr, installed if missing); fails when a test fails or the coverage is below 90 %.
# Usage: scripts/coverage.sh        (build directory: $SMALLISO_COVERAGE_DIR, default ./build-coverage)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SMALLISO_COVERAGE_DIR:-$root/build-coverage}
minimum=90

source "$root/scripts/packages.sh"
smalliso_install_missing "${smalliso_packages[@]}" gcovr

echo "coverage: configuring and building in $build"
# No build type: the flags below are the only optimisation flags.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE= -DBUILD_TESTING=ON \
  -DCMAKE_CXX_FLAGS="--coverage -O1" -DCMAKE_EXE_LINKER_FLAGS=--coverage -DCMAKE_SHARED_LINKER_FLAGS=--coverage \
  >"$build.configure.log" 2>&1 || { cat "$build.configure.log" >&2; exit 1; }
cmake --build "$build" -j "$(nproc)"

# Counts from an earlier run would add up with this one's.
find "$build" -name '*.gcda' -delete
(cd "$build" && ctest --output-on-failure -j "$(nproc)" --timeout 1800)

gcovr --root "$root" --object-directory "$build" --filter "$root/include/" --filter "$root/src/" \
  --print-summary --fail-under-line "$minimum"
