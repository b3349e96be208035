#!/usr/bin/env bash
# Builds the libFuzzer targets with Clang (AddressSanitizer + UndefinedBehaviorSanitizer) in a
# build directory of its own and runs one of them for a while.
# Usage: scripts/fuzz.sh read|filter [SECONDS]      (default 60 seconds)
#   read    arbitrary bytes as a NRRD, MetaImage or NIfTI file through the tools' reading,
#           filtering and writing (test/fuzz/sicFuzzImageFile.cxx)
#   filter  the filter on fuzzed small volumes against the brute-force reference
#           (test/fuzz/itkSmallIsoComponentFuzzFilter.cxx)
# The committed seed corpus (test/fuzz/corpus-NAME) is copied into the build directory, where
# the inputs libFuzzer adds go; a crash's input lands in build-fuzz/artifacts-NAME/, and the
# log (executions, cov:, ft:) in build-fuzz/fuzz-NAME.log.
# Build directory: $SMALLISO_FUZZ_DIR, default ./build-fuzz.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${SMALLISO_FUZZ_DIR:-$root/build-fuzz}
name=${1:-}
seconds=${2:-60}
case "$name" in
  read) target=SmallIsoComponentFuzzRead; max_len=16384 ;;
  filter) target=SmallIsoComponentFuzzFilter; max_len=2048 ;;
  *) echo "usage: scripts/fuzz.sh read|filter [SECONDS]" >&2; exit 2 ;;
esac

source "$root/scripts/packages.sh"
smalliso_install_missing "${smalliso_packages[@]}" clang

flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -O1 -g"
# Debian's ITK was configured with GCC, and its itk_compiler_detection.h accepts GCC alone. Clang
# speaks GCC's dialect: a copy of that header that takes GCC's branch for Clang too is included
# first (its include guard then skips ITK's own), and Clang says it is GCC 5, the newest version
# that header asks about (newer ones would make glibc's headers use attributes Clang lacks). The
# copy's own includes (compilers/...) are found in ITK's include directory, also when CMake tries
# the compiler before it knows of ITK.
itk_include=$(ls -d /usr/include/ITK-* | sort -V | tail -n 1)
mkdir -p "$build"
detection=$build/itk_compiler_detection_clang.h
# Rewritten only when it changes: every object includes it, so a new copy would rebuild them all.
sed 's/^\( *# *if\) ITK_COMPILER_IS_GNU$/\1 ITK_COMPILER_IS_GNU || ITK_COMPILER_IS_Clang/' \
  "$itk_include/itk_compiler_detection.h" >"$detection.new"
if cmp -s "$detection.new" "$detection"; then rm "$detection.new"; else mv "$detection.new" "$detection"; fi
cxx_flags="$flags -fgnuc-version=5.0.0 -I$itk_include -include $detection"
echo "fuzz: configuring and building $target in $build"
# No build type: the flags above are the only optimisation flags. No VTK: the targets do not use it.
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE= -DBUILD_TESTING=OFF \
  -DSmallIsoComponent_USE_VTK=OFF -DSmallIsoComponent_BUILD_FUZZERS=ON \
  -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$cxx_flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  >"$build.configure.log" 2>&1 || { cat "$build.configure.log" >&2; exit 1; }
cmake --build "$build" -j "$(nproc)" --target "$target"

corpus=$build/corpus-$name
artifacts=$build/artifacts-$name
mkdir -p "$corpus" "$artifacts"
cp -n "$root/test/fuzz/corpus-$name"/* "$corpus"/
export ASAN_OPTIONS="detect_leaks=1"
# ITK's own leaks on its error paths are suppressed as in the sanitizer runs (scripts/sanitizers/lsan.supp).
export LSAN_OPTIONS="suppressions=$root/scripts/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1"
echo "fuzz: running $target for $seconds s (log: $build/fuzz-$name.log)"
set +e
"$build/apps/fuzz/$target" "$corpus" -max_total_time="$seconds" -max_len="$max_len" -timeout=60 -rss_limit_mb=4096 \
  -print_final_stats=1 -artifact_prefix="$artifacts/" >"$build/fuzz-$name.log" 2>&1
status=$?
set -e
grep -E '^#[0-9]+[[:space:]]+(INITED|DONE)|^==[0-9]+==ERROR|SUMMARY|stat::' "$build/fuzz-$name.log" || true
ls "$artifacts" | sed "s|^|fuzz: finding: $artifacts/|"
exit "$status"
