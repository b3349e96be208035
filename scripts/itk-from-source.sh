#!/usr/bin/env bash
# Builds a minimal ITK 5.2.1 with Python wrapping from Debian's source package and checks
# this module against it, the way ITK's own CI and ITK's Python wheels build remote modules.
#
#   scripts/itk-from-source.sh build   fetch, configure and build ITK in the cache
#   scripts/itk-from-source.sh test    build (if needed), then
#                                      check 1: the module as an external module against
#                                               that ITK build tree, C++ tests under CTest;
#                                      check 2: the same with ITK's Python wrapping on,
#                                               Python tests under CTest.
#
# The cache ($SMALLISO_ITK_CACHE, default ~/.cache/smalliso-itk) holds the source package,
# the ITK build tree and a record of how long each step took. Every step leaves a stamp
# there when it finishes, so rerunning the script continues where it stopped. The module's
# own builds go to build-itk-source/ in the repository.
#
# Environment: SMALLISO_ITK_CACHE (cache directory), SMALLISO_ITK_JOBS (parallel build jobs,
# default: number of cores). Needs a Debian 12 (bookworm) system, root or sudo for apt-get.
set -euo pipefail

readonly repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
readonly cache_dir=${SMALLISO_ITK_CACHE:-${HOME}/.cache/smalliso-itk}
readonly jobs=${SMALLISO_ITK_JOBS:-$(nproc)}
readonly itk_version=5.2.1
readonly source_parent=${cache_dir}/source
readonly itk_source=${source_parent}/insighttoolkit5-${itk_version}
readonly itk_build=${cache_dir}/itk-build
readonly stamps=${cache_dir}/stamps
readonly times_file=${cache_dir}/step-times.txt
readonly module_builds=${repo_dir}/build-itk-source
readonly python=/usr/bin/python3

# Debian packages the build needs: CastXML and SWIG for the wrapping, Python with its
# headers and NumPy for the itk package, dpkg-dev for `apt-get source`.
readonly debian_packages=(dpkg-dev build-essential cmake ninja-build castxml swig python3-dev python3-numpy)

# The ITK modules: the module's dependencies and test dependencies (itk-module.cmake), what
# its command-line tools and benchmark need (SmallIsoComponent_APP_ITK_MODULES in
# CMakeLists.txt), and NumPy interop for the Python package. ITK enables the modules these
# depend on by itself. Changing the list reconfigures and incrementally rebuilds ITK.
readonly itk_modules=(
  ITKCommon ITKTestKernel ITKGoogleTest
  ITKIOImageBase ITKIOMeta ITKIONRRD ITKIONIFTI ITKIOPNG ITKIOTIFF ITKIOVTK ITKIOGIPL ITKIOBMP
  ITKThresholding ITKConnectedComponents
  ITKBridgeNumPy
)

log() { printf '[itk-from-source] %s\n' "$*"; }
die() { printf '[itk-from-source] error: %s\n' "$*" >&2; exit 1; }

as_root() {
  if [[ $(id -u) -eq 0 ]]; then "$@"; else sudo "$@"; fi
}

# run_step NAME FUNCTION: runs FUNCTION unless NAME's stamp exists, then records the time.
run_step() {
  local name=$1 fn=$2
  if [[ -f ${stamps}/${name} ]]; then
    log "step ${name}: done before ($(cat "${stamps}/${name}") s), skipped"
    return
  fi
  log "step ${name}: starting"
  local start=${SECONDS}
  "${fn}"
  local took=$((SECONDS - start))
  mkdir -p "${stamps}"
  echo "${took}" >"${stamps}/${name}"
  printf '%s %s %d\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "${name}" "${took}" >>"${times_file}"
  log "step ${name}: finished in $(format_seconds "${took}")"
}

format_seconds() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }

step_packages() {
  local missing=() pkg
  for pkg in "${debian_packages[@]}"; do
    dpkg-query -W -f='${Status}' "${pkg}" 2>/dev/null | grep -q 'install ok installed' || missing+=("${pkg}")
  done
  if ((${#missing[@]})); then
    log "installing ${missing[*]}"
    as_root apt-get install -y --no-install-recommends "${missing[@]}"
  fi
}

# apt needs a deb-src entry to fetch source packages. The new entry copies the archive
# address of the bookworm binary entry already configured, so no host is named here.
step_sources() {
  if apt-cache showsrc insighttoolkit5 2>/dev/null | grep -q "^Version: ${itk_version}"; then
    return
  fi
  local list=/etc/apt/sources.list.d/smalliso-itk-deb-src.sources
  log "adding a deb-src entry for bookworm (${list})"
  "${python}" - >"${cache_dir}/deb-src.sources" <<'EOF'
import glob, re

# Debian's own one-line and deb822 source lists: take the bookworm main archive entry.
def stanzas():
    for path in sorted(glob.glob('/etc/apt/sources.list.d/*.sources')):
        for block in open(path).read().split('\n\n'):
            fields = {}
            for line in block.splitlines():
                if line.startswith('#') or ':' not in line or line.startswith(' '):
                    continue
                key, value = line.split(':', 1)
                fields[key.strip()] = value.strip()
            if fields:
                yield fields
    for path in ['/etc/apt/sources.list'] + sorted(glob.glob('/etc/apt/sources.list.d/*.list')):
        try:
            lines = open(path).read().splitlines()
        except OSError:
            continue
        for line in lines:
            m = re.match(r'^deb\s+(\[[^]]*\]\s+)?(\S+)\s+(\S+)\s+(.+)$', line.strip())
            if m:
                yield {'Types': 'deb', 'URIs': m.group(2), 'Suites': m.group(3),
                       'Components': m.group(4)}

for s in stanzas():
    if 'deb' in s.get('Types', '').split() and 'bookworm' in s.get('Suites', '').split() \
            and s.get('Enabled', 'yes') != 'no':
        print('Types: deb-src')
        print('URIs: ' + s['URIs'])
        print('Suites: bookworm')
        print('Components: main')
        if 'Signed-By' in s:
            print('Signed-By: ' + s['Signed-By'])
        break
else:
    raise SystemExit('no apt entry for bookworm found to derive a deb-src entry from')
EOF
  as_root cp "${cache_dir}/deb-src.sources" "${list}"
  as_root apt-get update
}

step_fetch() {
  rm -rf "${source_parent}"
  mkdir -p "${source_parent}"
  # Downloads the .dsc and tarballs and unpacks them with Debian's patches applied.
  (cd "${source_parent}" && apt-get source insighttoolkit5)
  [[ -f ${itk_source}/CMakeLists.txt ]] || die "the source package did not unpack to ${itk_source}"
}

# Fixes for tools newer than ITK 5.2.1, as patches to the unpacked source (explained in
# docs/python-and-itk-from-source.md). Each is applied once; a rerun finds it applied.
apply_patch() {
  local name=$1 patch_text
  patch_text=$(cat)
  if patch -d "${itk_source}" -p1 -R --dry-run --silent <<<"${patch_text}" >/dev/null 2>&1; then
    log "patch ${name}: already applied"
  else
    patch -d "${itk_source}" -p1 --forward <<<"${patch_text}"
    log "patch ${name}: applied"
  fi
}

step_patch() {
  # CastXML 0.5.1 is clang 14, which (unlike GCC) leaves C++14 sized deallocation off;
  # parsing GCC 12's <bits/new_allocator.h> then fails ("call to
  # '__builtin_operator_delete' selects non-usual deallocation function"). The flag has to
  # reach clang itself, so it goes into the options file CastXML reads, not CMAKE_CXX_FLAGS.
  apply_patch castxml-sized-deallocation <<'EOF'
--- a/Wrapping/Generators/CastXML/CMakeLists.txt
+++ b/Wrapping/Generators/CastXML/CMakeLists.txt
@@ -325,6 +325,8 @@
   set(c "${c}-Qunused-arguments\n")
   set(c "${c}-DITK_WRAPPING_PARSER\n")
   set(c "${c}-DITK_MANUAL_INSTANTIATION\n")
+  # Clang enables sized deallocation only when asked; GCC 12's <new> needs it.
+  set(c "${c}-fsized-deallocation\n")
   foreach(def ${compile_definition_list})
     set(c "${c}\"-D${def}\"\n")
   endforeach()
EOF
  # NumPy 1.24 removed the alias np.bool (deprecated since 1.20); np.bool_ is the type it
  # named. Without this, `import itk` fails.
  apply_patch numpy-bool <<'EOF'
--- a/Wrapping/Generators/Python/itk/support/types.py
+++ b/Wrapping/Generators/Python/itk/support/types.py
@@ -137,7 +137,7 @@
         _SS: "itkCType" = itkCType("signed short", "SS", np.int16)
         _SI: "itkCType" = itkCType("signed int", "SI", np.int32)
         _SLL: "itkCType" = itkCType("signed long long", "SLL", np.int64)
-        _B: "itkCType" = itkCType("bool", "B", np.bool)
+        _B: "itkCType" = itkCType("bool", "B", np.bool_)
         return _F, _D, _UC, _US, _UI, _UL, _SL, _LD, _ULL, _SC, _SS, _SI, _SLL, _B
 
 
EOF
}

itk_cmake_options() {
  local module
  echo -G Ninja
  echo -DCMAKE_BUILD_TYPE=Release
  echo -DBUILD_SHARED_LIBS=ON
  echo -DBUILD_TESTING=OFF
  echo -DBUILD_EXAMPLES=OFF
  echo -DITK_BUILD_DEFAULT_MODULES=OFF
  for module in "${itk_modules[@]}"; do
    echo "-DModule_${module}=ON"
  done
  echo -DITK_WRAP_PYTHON=ON
  echo -DITK_WRAP_unsigned_char=ON
  echo -DITK_WRAP_signed_short=ON
  echo -DITK_WRAP_unsigned_short=ON
  echo -DITK_WRAP_float=ON
  echo "-DITK_WRAP_IMAGE_DIMS=2;3"
  echo -DITK_USE_SYSTEM_CASTXML=ON
  echo -DCASTXML_EXECUTABLE=/usr/bin/castxml
  echo -DITK_USE_SYSTEM_SWIG=ON
  echo -DSWIG_EXECUTABLE=/usr/bin/swig
  echo -DPython3_EXECUTABLE=${python}
}

step_configure() {
  mkdir -p "${itk_build}"
  local options
  mapfile -t options < <(itk_cmake_options)
  cmake -S "${itk_source}" -B "${itk_build}" "${options[@]}"
  # ITK 5.2's second configure changes the compiler flags of most targets once (seen
  # here); doing it now keeps any later configure from recompiling all of ITK.
  cmake "${itk_build}"
  itk_cmake_options >"${cache_dir}/itk-options.txt"
}

# A build configured with other options (an older version of this script) is configured
# again and rebuilt incrementally.
forget_build_if_options_changed() {
  if [[ -f ${stamps}/configure ]] && ! itk_cmake_options | cmp -s - "${cache_dir}/itk-options.txt"; then
    log "the ITK options differ from those of the existing build: configuring and building again"
    rm -f "${stamps}/configure" "${stamps}/compile"
  fi
}

step_compile() {
  # Ninja prints [done/total] for every step; that is the progress.
  cmake --build "${itk_build}" -j "${jobs}"
  # ITK builds its GoogleTest only for its own tests (EXCLUDE_FROM_ALL), but exports it
  # for modules' tests.
  cmake --build "${itk_build}" -j "${jobs}" --target gtest gtest_main
  log "ITK build tree: $(du -sh "${itk_build}" | cut -f1)"
}

cmd_build() {
  local start=${SECONDS}
  mkdir -p "${cache_dir}"
  run_step packages step_packages
  run_step sources step_sources
  run_step fetch step_fetch
  run_step patch step_patch
  forget_build_if_options_changed
  run_step configure step_configure
  run_step compile step_compile
  log "ITK ${itk_version} with Python wrapping is ready in ${itk_build} ($(format_seconds $((SECONDS - start))) this run)"
}

# check_module NAME WRAP: configures, builds and tests the module against the ITK build
# tree in build-itk-source/NAME, with ITK's Python wrapping on or off. With BUILD_TESTING
# on, ITK's module macros would download clang-format and KWStyle (style checks, not
# tests): ITK_FORBID_DOWNLOADS and ITK_USE_KWSTYLE turn that off. ITK's wrapping, read again
# for the module, does not inherit ITK's choice of system CastXML and SWIG and would
# download and build its own: the module is told the same.
check_module() {
  local name=$1 wrap=$2 dir=${module_builds}/$1 start=${SECONDS}
  log "check ${name}: configure, build and test the module (Python wrapping ${wrap})"
  cmake -S "${repo_dir}" -B "${dir}" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DITK_DIR="${itk_build}" -DSmallIsoComponent_WRAP_PYTHON="${wrap}" -DBUILD_TESTING=ON \
    -DPython3_EXECUTABLE=${python} -DITK_FORBID_DOWNLOADS=ON -DITK_USE_KWSTYLE=OFF \
    -DITK_USE_SYSTEM_CASTXML=ON -DCASTXML_EXECUTABLE=/usr/bin/castxml \
    -DITK_USE_SYSTEM_SWIG=ON -DSWIG_EXECUTABLE=/usr/bin/swig &&
    cmake --build "${dir}" -j "${jobs}" &&
    (cd "${dir}" && ctest --output-on-failure -j "${jobs}")
  local status=$?
  printf '%s check-%s %d\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "${name}" $((SECONDS - start)) >>"${times_file}"
  log "check ${name}: $( ((status == 0)) && echo passed || echo FAILED) in $(format_seconds $((SECONDS - start)))"
  return "${status}"
}

cmd_test() {
  local start=${SECONDS} failed=0
  cmd_build
  check_module cxx OFF || failed=1
  check_module python ON || failed=1
  log "total $(format_seconds $((SECONDS - start)))"
  if ((failed)); then
    log "FAILED"
    return 1
  fi
  log "all checks passed"
}

case ${1:-} in
  build) cmd_build ;;
  test) cmd_test ;;
  *)
    sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
