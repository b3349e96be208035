#!/usr/bin/env bash
# Sets up (installs missing Debian packages, builds) and runs every test of the project, then
# a subset of them built with AddressSanitizer and UndefinedBehaviorSanitizer.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SMALLISO_BUILD_DIR:-$root/build}
"$root/scripts/setup.sh"
status=0
(cd "$build" && ctest --output-on-failure -j "$(nproc)" --timeout 900) || status=1
"$root/scripts/check-format.sh" || status=1
# AddressSanitizer + UndefinedBehaviorSanitizer on a subset that keeps CI short: the filter
# tool (and so the filter) under the tool's fault tests, and the label-map filter under the
# comparison of both tools' label maps with it (scripts/sanitize.sh asan runs all).
asan_subset='SmallIsoComponentRobustness\.test_(full_disk_leaves|outputs_whose|corrupt_compressed|header_promising|termination)|SmallIsoComponentLabelCLI\.test_output_and_mask'
# Unoptimised, with line tables only: the tools' dispatch over every pixel type compiles several
# times faster so, and the subset's small inputs run fast enough without optimisation.
echo "test: ASan + UBSan subset (build-asan/)"
SMALLISO_SANITIZE_OPTIMIZATION="-O0 -g1" \
  SMALLISO_SANITIZE_TARGETS="SmallIsoComponentFilter SmallIsoComponentLabelFilter SmallIsoComponentCLITestProbe" \
  "$root/scripts/sanitize.sh" asan -R "$asan_subset" --timeout 900 || status=1
exit $status
