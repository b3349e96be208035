#!/usr/bin/env bash
# Builds the module, its tests and the tools with a sanitizer in a build directory of its own
# and runs tests there; fails when a test fails or a sanitizer reported anything.
# Usage: scripts/sanitize.sh asan [CTEST_ARGS...]   AddressSanitizer + UndefinedBehaviorSanitizer
#                                                   (build-asan/), every test by default
#        scripts/sanitize.sh tsan [CTEST_ARGS...]   ThreadSanitizer (build-tsan/), the
#                                                   multi-threaded tests by default
# CTEST_ARGS replace the default selection (e.g. -R 'SmallIsoComponentBehaviour\.').
# $SMALLISO_SANITIZE_TARGETS (target names, space-separated) builds only those, for a selection
# that needs no others; by default asan builds everything and tsan the GoogleTest driver.
# Build directory: $SMALLISO_SANITIZE_DIR, default ./build-asan or ./build-tsan.
# Optimisation and debug flags: $SMALLISO_SANITIZE_OPTIMIZATION, default "-O1 -g".
# Suppressions (each with its reason) are in scripts/sanitizers/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
kind=${1:-}
shift || true
case "$kind" in
  asan)
    # UBSan's checks stay recoverable so that its suppressions apply (a check built not to
    # recover stops the process even when its report is suppressed); halt_on_error below still
    # stops at the first report that is not.
    flags="-fsanitize=address,undefined"
    sanitizer=address
    # Every test; the longest ones at -O1 under ASan take a few minutes.
    selection=(--timeout 1800)
    targets=""
    ;;
  tsan)
    flags="-fsanitize=thread"
    sanitizer=thread
    # The tests that run work units in parallel: the differential tests (1, 2 and 7 work
    # units per volume, and the sweep in slabs with its labelling thread), the invariants (the
    # output for several numbers of work units), the work team, the streaming sweep and
    # filter (two work units: a slab labelled while the one before is merged), and the label
    # filter (1 to 7 work units, each linking and repairing slabs of lines).
    selection=(-R 'SmallIsoComponent(Differential|WorkTeam|Invariants|StreamingSweep|StreamingImageFilter|LabelImageFilter)\.' --timeout 3600)
    targets=SmallIsoComponentGTestDriver
    ;;
  *)
    echo "usage: scripts/sanitize.sh asan|tsan [CTEST_ARGS...]" >&2
    exit 2
    ;;
esac
[ $# -eq 0 ] || selection=("$@")
targets=${SMALLISO_SANITIZE_TARGETS:-$targets}
build=${SMALLISO_SANITIZE_DIR:-$root/build-$kind}
suppressions=$root/scripts/sanitizers

source "$root/scripts/packages.sh"
smalliso_install_missing "${smalliso_packages[@]}"

echo "sanitize: configuring and building ($kind) in $build"
# No build type: -O1 -g keeps the tests fast enough and the reports' stacks readable.
optimization=${SMALLISO_SANITIZE_OPTIMIZATION:--O1 -g}
# Debian's interpreter, as in setup.sh: the Python tests need Debian's packages.
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE= -DBUILD_TESTING=ON \
  -DPython3_EXECUTABLE="${SMALLISO_PYTHON:-/usr/bin/python3}" -DSmallIsoComponent_SANITIZER=$sanitizer \
  -DCMAKE_C_FLAGS="$flags -fno-omit-frame-pointer $optimization" \
  -DCMAKE_CXX_FLAGS="$flags -fno-omit-frame-pointer $optimization" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" \
  >"$build.configure.log" 2>&1 || { cat "$build.configure.log" >&2; exit 1; }
# shellcheck disable=SC2086 # the target names are words
cmake --build "$build" -j "$(nproc)" ${targets:+--target $targets}

# Reports go to files as well as failing the process, so that one a test tolerates (a tool
# expected to fail) is still counted.
logs=$build/sanitizer-reports
rm -rf "$logs"
mkdir -p "$logs"
export ASAN_OPTIONS="detect_leaks=1:log_path=$logs/asan:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$suppressions/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$logs/ubsan:suppressions=$suppressions/ubsan.supp"
export TSAN_OPTIONS="halt_on_error=0:log_path=$logs/tsan:suppressions=$suppressions/tsan.supp:second_deadlock_stack=1"

status=0
(cd "$build" && ctest --output-on-failure -j "$(nproc)" "${selection[@]}") || status=1
if compgen -G "$logs/*" >/dev/null; then
  echo "sanitize: $kind reported problems:" >&2
  for report in "$logs"/*; do
    echo "== $report" >&2
    head -n 60 "$report" >&2
  done
  status=1
else
  echo "sanitize: $kind: no reports"
fi
exit $status
