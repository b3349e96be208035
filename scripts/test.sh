#!/usr/bin/env bash
# Sets up (installs missing Debian packages, builds) and runs every test of the project.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SMALLISO_BUILD_DIR:-$root/build}
"$root/scripts/setup.sh"
status=0
(cd "$build" && ctest --output-on-failure -j "$(nproc)" --timeout 900) || status=1
"$root/scripts/check-format.sh" || status=1
exit $status
