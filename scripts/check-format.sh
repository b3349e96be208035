#!/usr/bin/env bash
# Fails when a C++ file of the project is not formatted as .clang-format (ITK's style) says,
# and lists the files. `scripts/check-format.sh --fix` formats them in place instead.
# Needs clang-format 14 or newer (Debian: clang-format).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
command -v clang-format >/dev/null || { echo "check-format: clang-format is not installed (Debian: clang-format)" >&2; exit 2; }
mapfile -t files < <(git ls-files -- '*.h' '*.hxx' '*.cxx' '*.cpp')
if [[ ${1:-} == --fix ]]; then
  clang-format -i "${files[@]}"
  exit 0
fi
unformatted=()
for f in "${files[@]}"; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || unformatted+=("$f")
done
if ((${#unformatted[@]})); then
  echo "check-format: ${#unformatted[@]} file(s) differ from .clang-format (run scripts/check-format.sh --fix):" >&2
  printf '  %s\n' "${unformatted[@]}" >&2
  exit 1
fi
echo "check-format: ${#files[@]} C++ files formatted as .clang-format says"
