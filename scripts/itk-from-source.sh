#!/usr/bin/env bash
# Builds a minimal ITK of a given version from source and checks this module against it
# through the paths ITK offers remote modules.
#
#   scripts/itk-from-source.sh build VERSION          build ITK VERSION into its cache
#   scripts/itk-from-source.sh test VERSION [CHECK..] build (if needed), then run the checks:
#       external  the module against the ITK build tree (ITKModuleExternal), all C++ tests
#       in-tree   the module inside ITK's source tree as a remote module
#                 (Modules/Remote/SmallIsoComponent.remote.cmake, Module_SmallIsoComponent=ON)
#       python    the module with ITK's Python wrapping, C++ and Python tests
#     (default: every check the version's build supports)
#   scripts/itk-from-source.sh matrix                 the release matrix: 5.4.7 (external,
#                                                     in-tree, python) and 6.0b02 (external,
#                                                     in-tree)
#
# VERSION is 5.2.1, 5.4.7 or 6.0b02. The source comes from, in this order:
#   ITK_SOURCE_DIR  an unpacked ITK source tree of that version (not fetched: patched and
#                   used in place, and the in-tree check writes into its Modules/Remote)
#   Debian's source package (5.2.1 from bookworm; 5.4.7 from sid, through a temporary
#                   deb-src entry that is removed again)
#   ITK_GIT_DIR     a git repository (bare or not) holding the tag vVERSION (6.0b02)
#   ITK_GIT_URL     a repository to clone the tag from (default: ITK's on GitHub) (6.0b02)
#
# The cache ($SMALLISO_ITK_CACHE, default ~/.cache/smalliso-itk) holds, per version, the
# source, the ITK build trees and a record of how long each step took (step-times.txt).
# Every step leaves a stamp there when it finishes, so rerunning the script continues where
# it stopped. Compilers run through ccache (in the cache), so the in-tree build, which is a
# second ITK build, reuses the first one's objects. The module's own builds for the external
# and python checks go to build-itk-source/VERSION-CHECK in the repository.
# docs/python-and-itk-from-source.md describes the steps, the checks and the patches.
#
# Environment: SMALLISO_ITK_CACHE, SMALLISO_ITK_JOBS (parallel jobs, default: cores),
# SMALLISO_ITK_WRAP (ON/OFF: build ITK's Python wrapping; default ON for 5.2.1 and 5.4.7,
# OFF for 6.0b02), ITK_SOURCE_DIR, ITK_GIT_DIR, ITK_GIT_URL. Builds run under nice.
# Needs Debian 12 (bookworm) with root or sudo for apt-get.
set -euo pipefail

readonly repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
readonly cache_root=${SMALLISO_ITK_CACHE:-${HOME}/.cache/smalliso-itk}
readonly jobs=${SMALLISO_ITK_JOBS:-$(nproc)}
readonly python=/usr/bin/python3
readonly module_builds=${repo_dir}/build-itk-source

# Debian packages the builds need: CastXML and SWIG for the wrapping, Python with its
# headers and NumPy for the itk package, dpkg-dev for `apt-get source`, git for the
# in-tree check (ITK fetches remote modules with git), ccache.
readonly debian_packages=(dpkg-dev build-essential cmake ninja-build git ccache castxml swig python3-dev
  python3-numpy)

# The ITK modules: the module's dependencies and test dependencies (itk-module.cmake), what
# its command-line tools and benchmark need (SmallIsoComponent_APP_ITK_MODULES in
# CMakeLists.txt), NumPy interop for the Python package, and ITKIOXML (with ITKExpat), which
# SlicerExecutionModel's parser needs for the Slicer parser test. ITK enables the modules
# these depend on by itself. Changing the list reconfigures and incrementally rebuilds ITK.
readonly itk_modules=(
  ITKCommon ITKTestKernel ITKGoogleTest
  ITKIOImageBase ITKIOMeta ITKIONRRD ITKIONIFTI ITKIOPNG ITKIOTIFF ITKIOVTK ITKIOGIPL ITKIOBMP
  ITKThresholding ITKConnectedComponents
  ITKBridgeNumPy ITKIOXML
)

log() { printf '[itk-from-source] %s\n' "$*"; }
die() {
  printf '[itk-from-source] error: %s\n' "$*" >&2
  exit 1
}
format_seconds() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }
as_root() { if [[ $(id -u) -eq 0 ]]; then "$@"; else sudo "$@"; fi; }

# Per-version settings, set by select_version.
select_version() {
  version=$1
  case ${version} in
    5.2.1) debian_suite=bookworm default_wrap=ON ;;
    5.4.7) debian_suite=sid default_wrap=ON ;;
    6.0b02) debian_suite="" default_wrap=OFF ;;
    *) die "unknown ITK version '${version}': expected 5.2.1, 5.4.7 or 6.0b02" ;;
  esac
  wrap=${SMALLISO_ITK_WRAP:-${default_wrap}}
  [[ ${wrap} == ON || ${wrap} == OFF ]] || die "SMALLISO_ITK_WRAP is '${wrap}': expected ON or OFF"
  cache_dir=${cache_root}/${version}
  stamps=${cache_dir}/stamps
  times_file=${cache_dir}/step-times.txt
  itk_build=${cache_dir}/build
  intree_build=${cache_dir}/build-in-tree
  if [[ -n ${ITK_SOURCE_DIR:-} ]]; then
    itk_source=$(cd "${ITK_SOURCE_DIR}" && pwd)
  else
    itk_source=${cache_dir}/source/ITK
  fi
  export CCACHE_DIR=${cache_root}/ccache CCACHE_BASEDIR=${cache_dir} CCACHE_NOHASHDIR=1
}

# run_step NAME FUNCTION: runs FUNCTION unless NAME's stamp exists, then records the time.
run_step() {
  local name=$1 fn=$2
  if [[ -f ${stamps}/${name} ]]; then
    log "${version} step ${name}: done before ($(cat "${stamps}/${name}") s), skipped"
    return
  fi
  log "${version} step ${name}: starting"
  local start=${SECONDS}
  "${fn}"
  local took=$((SECONDS - start))
  mkdir -p "${stamps}"
  echo "${took}" >"${stamps}/${name}"
  printf '%s %s %d\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "${name}" "${took}" >>"${times_file}"
  log "${version} step ${name}: finished in $(format_seconds "${took}")"
}

step_packages() {
  local missing=() pkg
  for pkg in "${debian_packages[@]}"; do
    dpkg-query -W -f='${Status}' "${pkg}" 2>/dev/null | grep -q 'install ok installed' || missing+=("${pkg}")
  done
  if ((${#missing[@]})); then
    log "installing ${missing[*]}"
    as_root apt-get update -qq
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
  ccache --max-size=20G >/dev/null
}

# Writes a deb-src entry for suite $1 to stdout, copying the archive address and key of the
# bookworm binary entry already configured (so no host is named here).
deb_src_entry() {
  "${python}" - "$1" <<'EOF'
import glob, re, sys

suite = sys.argv[1]

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
                yield {'Types': 'deb', 'URIs': m.group(2), 'Suites': m.group(3), 'Components': m.group(4)}

for s in stanzas():
    if 'deb' in s.get('Types', '').split() and 'bookworm' in s.get('Suites', '').split() \
            and s.get('Enabled', 'yes') != 'no':
        print('Types: deb-src')
        print('URIs: ' + s['URIs'])
        print('Suites: ' + suite)
        print('Components: main')
        if 'Signed-By' in s:
            print('Signed-By: ' + s['Signed-By'])
        break
else:
    raise SystemExit('no apt entry for bookworm found to derive a deb-src entry from')
EOF
}

# Fetches Debian's source package of ITK ${version} from ${debian_suite}. The deb-src entry
# is added for the download only and removed afterwards (also when the download fails).
fetch_debian_source() {
  local list=/etc/apt/sources.list.d/smalliso-itk-deb-src-${debian_suite}.sources
  local entry=${cache_dir}/deb-src-${debian_suite}.sources
  deb_src_entry "${debian_suite}" >"${entry}"
  log "adding a temporary deb-src entry for ${debian_suite} (${list})"
  as_root cp "${entry}" "${list}"
  local status=0
  (
    set -e
    as_root apt-get update -qq
    local available
    available=$(apt-cache showsrc insighttoolkit5 | sed -n 's/^Version: //p' | grep "^${version}-" | sort -V | tail -1)
    [[ -n ${available} ]] || {
      echo "Debian ${debian_suite} has no source package of ITK ${version} (it has: $(apt-cache showsrc insighttoolkit5 | sed -n 's/^Version: //p' | tr '\n' ' '))" >&2
      exit 1
    }
    cd "${cache_dir}/source"
    apt-get source -qq "insighttoolkit5=${available}"
  ) || status=$?
  log "removing the temporary deb-src entry"
  as_root rm -f "${list}"
  as_root apt-get update -qq || true
  ((status == 0)) || die "could not fetch Debian's source package of ITK ${version}"
  local unpacked
  unpacked=$(find "${cache_dir}/source" -mindepth 1 -maxdepth 1 -type d -name "insighttoolkit5-*" | head -1)
  [[ -n ${unpacked} && -f ${unpacked}/CMakeLists.txt ]] || die "the source package did not unpack"
  mv "${unpacked}" "${itk_source}"
}

step_fetch() {
  if [[ -n ${ITK_SOURCE_DIR:-} ]]; then
    [[ -f ${itk_source}/CMakeLists.txt ]] || die "ITK_SOURCE_DIR=${ITK_SOURCE_DIR} is not an ITK source tree"
    log "using the ITK source tree ${itk_source}"
    return
  fi
  rm -rf "${cache_dir}/source"
  mkdir -p "${cache_dir}/source"
  if [[ -n ${debian_suite} ]]; then
    fetch_debian_source
  elif [[ -n ${ITK_GIT_DIR:-} ]]; then
    log "exporting tag v${version} from the git repository ${ITK_GIT_DIR}"
    mkdir -p "${itk_source}"
    git --git-dir="$(git -C "${ITK_GIT_DIR}" rev-parse --absolute-git-dir 2>/dev/null || echo "${ITK_GIT_DIR}")" \
      archive "v${version}" | tar -x -C "${itk_source}"
  else
    local url=${ITK_GIT_URL:-https://github.com/InsightSoftwareConsortium/ITK.git}
    log "cloning tag v${version} of ${url}"
    git clone --depth 1 --branch "v${version}" "${url}" "${itk_source}" ||
      die "could not clone ITK ${version}; set ITK_GIT_DIR to a repository holding tag v${version} or ITK_SOURCE_DIR to its source"
  fi
  [[ -f ${itk_source}/CMakeLists.txt ]] || die "no ITK source tree at ${itk_source}"
}

# Fixes for tools newer than ITK 5.2.1, and for Debian 12's SWIG under ITK 5.4 (explained in
# docs/python-and-itk-from-source.md, "Patches"). Each is applied once; a rerun finds it applied.
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
  if [[ ${version} == 5.4.7 ]]; then
    # ITK 5.4's Python wrapping calls SWIG_Py_INCREF, SWIG_Py_DECREF and their X forms, macros
    # that SWIG 4.3 added (Py_INCREF and Py_DECREF outside Python's limited API); Debian 12
    # has SWIG 4.1. Files already patched hold none of them and are left alone.
    local file files
    files=$(grep -rlE --include='*.i' --include='*.hxx' --include='CMakeLists.txt' 'SWIG_Py_X?(IN|DE)CREF' \
      "${itk_source}/Wrapping" "${itk_source}/Modules/Bridge/NumPy" 2>/dev/null || true)
    for file in ${files}; do
      sed -i -E 's/SWIG_Py_(X?)(IN|DE)CREF/Py_\1\2CREF/g' "${file}"
      log "patch swig-4.1: ${file#"${itk_source}"/}"
    done
    [[ -n ${files} ]] || log "patch swig-4.1: already applied"
    return 0
  fi
  [[ ${version} == 5.2.1 ]] || return 0
  # CastXML 0.5.1 is clang 14, which (unlike GCC) leaves C++14 sized deallocation off;
  # parsing GCC 12's <bits/new_allocator.h> then fails. The flag has to reach clang itself,
  # so it goes into the options file CastXML reads.
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
  # NumPy 1.24 removed the alias np.bool; np.bool_ is the type it named.
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

# Options shared by every ITK build of this script.
common_itk_options() {
  echo -G Ninja
  echo -DCMAKE_BUILD_TYPE=Release
  echo -DCMAKE_C_COMPILER_LAUNCHER=ccache
  echo -DCMAKE_CXX_COMPILER_LAUNCHER=ccache
  echo -DBUILD_SHARED_LIBS=ON
  echo -DBUILD_EXAMPLES=OFF
  echo -DITK_BUILD_DEFAULT_MODULES=OFF
  echo -DITK_FORBID_DOWNLOADS=ON
  echo -DITK_USE_KWSTYLE=OFF
  echo -DPython3_EXECUTABLE=${python}
}

itk_cmake_options() {
  local module
  common_itk_options
  echo -DBUILD_TESTING=OFF
  for module in "${itk_modules[@]}"; do
    echo "-DModule_${module}=ON"
  done
  echo "-DITK_WRAP_PYTHON=${wrap}"
  if [[ ${wrap} == ON ]]; then
    echo -DITK_WRAP_unsigned_char=ON
    echo -DITK_WRAP_signed_short=ON
    echo -DITK_WRAP_unsigned_short=ON
    echo -DITK_WRAP_float=ON
    echo "-DITK_WRAP_IMAGE_DIMS=2;3"
    echo -DITK_USE_SYSTEM_CASTXML=ON
    echo -DCASTXML_EXECUTABLE=/usr/bin/castxml
    echo -DITK_USE_SYSTEM_SWIG=ON
    echo -DSWIG_EXECUTABLE=/usr/bin/swig
    # ITK 5.4 and 6 build against Python's stable ABI by default, which needs libpython3.so;
    # Debian's python3-dev has only the versioned library.
    echo -DITK_USE_PYTHON_LIMITED_API=OFF
  fi
}

step_configure() {
  mkdir -p "${itk_build}"
  local options
  mapfile -t options < <(itk_cmake_options)
  nice cmake -S "${itk_source}" -B "${itk_build}" "${options[@]}"
  # ITK 5.2's second configure changes the compiler flags of most targets once (seen
  # here); doing it now keeps any later configure from recompiling all of ITK.
  nice cmake "${itk_build}"
  itk_cmake_options >"${cache_dir}/itk-options.txt"
}

# A build configured with other options (an older version of this script, another
# SMALLISO_ITK_WRAP) is configured again and rebuilt incrementally.
forget_build_if_options_changed() {
  if [[ -f ${stamps}/configure ]] && ! itk_cmake_options | cmp -s - "${cache_dir}/itk-options.txt"; then
    log "the ITK options differ from those of the existing build: configuring and building again"
    rm -f "${stamps}/configure" "${stamps}/compile"
  fi
}

step_compile() {
  # Ninja prints [done/total] for every step; that is the progress.
  nice cmake --build "${itk_build}" -j "${jobs}"
  # ITK builds its GoogleTest only for its own tests (EXCLUDE_FROM_ALL), but exports it
  # for modules' tests.
  nice cmake --build "${itk_build}" -j "${jobs}" --target gtest gtest_main
  log "ITK build tree: $(du -sh "${itk_build}" | cut -f1)"
}

cmd_build() {
  local start=${SECONDS}
  mkdir -p "${cache_dir}"
  run_step packages step_packages
  run_step fetch step_fetch
  run_step patch step_patch
  forget_build_if_options_changed
  run_step configure step_configure
  run_step compile step_compile
  log "ITK ${version} (Python wrapping ${wrap}) is ready in ${itk_build} ($(format_seconds $((SECONDS - start))) this run)"
}

record_check() {
  local name=$1 status=$2 took=$3
  printf '%s check-%s %s %d\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "${name}" \
    "$( ((status == 0)) && echo passed || echo FAILED)" "${took}" >>"${times_file}"
  log "${version} check ${name}: $( ((status == 0)) && echo passed || echo FAILED) in $(format_seconds "${took}")"
}

# check_external NAME WRAP: configures, builds and tests the module against the ITK build
# tree in build-itk-source/VERSION-NAME. ITK's wrapping, read again for the module, does
# not inherit ITK's choice of system CastXML and SWIG and would download its own: the
# module is told the same. SlicerExecutionModel, for the Slicer parser test, is found as
# scripts/setup.sh finds it ($SMALLISO_SLICER_EXECUTION_MODEL, else the archive in the
# folder of third-party sources beside the repository) and is built against this ITK.
check_external() {
  local name=$1 module_wrap=$2 dir=${module_builds}/${version}-$1 start=${SECONDS} status=0 sem
  log "${version} check ${name}: the module against the ITK build tree (Python wrapping ${module_wrap})"
  sem=${SMALLISO_SLICER_EXECUTION_MODEL:-$(ls "${repo_dir}"/../shared/vendor/SlicerExecutionModel-*.tar.gz 2>/dev/null | head -n 1 || true)}
  if [[ -n ${sem} ]]; then
    log "the Slicer parser test uses SlicerExecutionModel from ${sem}"
  else
    log "no SlicerExecutionModel found (set SMALLISO_SLICER_EXECUTION_MODEL): the Slicer parser test will be skipped"
  fi
  rm -rf "${dir}"
  {
    nice cmake -S "${repo_dir}" -B "${dir}" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DITK_DIR="${itk_build}" -DSmallIsoComponent_WRAP_PYTHON="${module_wrap}" -DBUILD_TESTING=ON \
      -DSmallIsoComponent_SLICER_EXECUTION_MODEL="${sem}" \
      -DPython3_EXECUTABLE=${python} -DITK_FORBID_DOWNLOADS=ON -DITK_USE_KWSTYLE=OFF \
      -DITK_USE_SYSTEM_CASTXML=ON -DCASTXML_EXECUTABLE=/usr/bin/castxml \
      -DITK_USE_SYSTEM_SWIG=ON -DSWIG_EXECUTABLE=/usr/bin/swig -DITK_USE_PYTHON_LIMITED_API=OFF &&
      nice cmake --build "${dir}" -j "${jobs}" &&
      (cd "${dir}" && nice ctest --output-on-failure -j "${jobs}" --timeout 900)
  } || status=$?
  record_check "${name}" "${status}" $((SECONDS - start))
  return "${status}"
}

# The in-tree check: ITK's own source tree with this module as a remote module. The
# module's SmallIsoComponent.remote.cmake is copied into Modules/Remote/, which declares the
# module to ITK's configure (Module_SmallIsoComponent), and the commit checked out now (it
# must be committed) is cloned from this repository into Modules/Remote/SmallIsoComponent,
# where ITK's own clone would put it: ITK_FORBID_DOWNLOADS=ON, which keeps every build of
# this script off the network, also makes itk_fetch_module skip its clone, so ITK finds the
# module the way it finds one fetched before. ITK is configured with
# Module_SmallIsoComponent=ON and BUILD_TESTING=ON in a second build tree, builds the module
# with the modules it needs (from ccache) and its tests, and CTest runs the module's tests:
# those named after it, since ITK labels the regression tests (SmallIsoComponent) but not
# the GoogleTest cases.
readonly intree_tests='^(itk)?SmallIsoComponent'
check_in_tree() {
  local start=${SECONDS} status=0 head remote_dir=${itk_source}/Modules/Remote
  local remote=${remote_dir}/SmallIsoComponent.remote.cmake clone=${remote_dir}/SmallIsoComponent
  log "${version} check in-tree: the module inside ITK's source tree (Modules/Remote)"
  head=$(git -C "${repo_dir}" rev-parse HEAD)
  if [[ -n $(git -C "${repo_dir}" status --porcelain --untracked-files=no) ]]; then
    log "note: the working tree has uncommitted changes; the in-tree check builds the commit ${head}"
  fi
  sed -e "s|GIT_REPOSITORY .*|GIT_REPOSITORY ${repo_dir}|" -e "s|GIT_TAG .*|GIT_TAG ${head}|" \
    "${repo_dir}/SmallIsoComponent.remote.cmake" >"${remote}"
  # A fresh clone keeps the check independent of earlier ones.
  rm -rf "${clone}"
  {
    git clone --quiet --no-checkout "${repo_dir}" "${clone}" &&
      git -C "${clone}" checkout --quiet "${head}" &&
      log "cloned the module at ${head} into Modules/Remote/SmallIsoComponent" &&
      {
        local options
        mapfile -t options < <(common_itk_options)
        nice cmake -S "${itk_source}" -B "${intree_build}" "${options[@]}" -DBUILD_TESTING=ON \
          -DITK_WRAP_PYTHON=OFF -DModule_SmallIsoComponent=ON -DModule_ITKGoogleTest=ON
      } &&
      grep -q '^Module_SmallIsoComponent:BOOL=ON' "${intree_build}/CMakeCache.txt" &&
      nice cmake --build "${intree_build}" -j "${jobs}" &&
      (cd "${intree_build}" &&
        nice ctest --output-on-failure --no-tests=error -j "${jobs}" --timeout 900 -R "${intree_tests}")
  } || status=$?
  rm -rf "${remote}" "${clone}"
  record_check in-tree "${status}" $((SECONDS - start))
  return "${status}"
}

cmd_test() {
  local start=${SECONDS} failed=0 checks=("$@") check
  if ((${#checks[@]} == 0)); then
    checks=(external in-tree)
    [[ ${wrap} == ON ]] && checks+=(python)
  fi
  for check in "${checks[@]}"; do
    case ${check} in
      external | in-tree) ;;
      python) [[ ${wrap} == ON ]] || die "the python check needs ITK built with SMALLISO_ITK_WRAP=ON" ;;
      *) die "unknown check '${check}': expected external, in-tree or python" ;;
    esac
  done
  cmd_build
  for check in "${checks[@]}"; do
    case ${check} in
      external) check_external external OFF || failed=1 ;;
      in-tree) check_in_tree || failed=1 ;;
      python) check_external python ON || failed=1 ;;
    esac
  done
  log "ITK ${version}: checks ${checks[*]}: total $(format_seconds $((SECONDS - start)))"
  if ((failed)); then
    log "FAILED"
    return 1
  fi
  log "all checks passed"
}

cmd_matrix() {
  local failed=0
  # Each version in a process of its own: a step that fails stops that version's run
  # (set -e does not apply to commands whose failure a "||" handles).
  "${BASH_SOURCE[0]}" test 5.4.7 external in-tree python || failed=1
  "${BASH_SOURCE[0]}" test 6.0b02 external in-tree || failed=1
  ((failed == 0)) || die "the matrix failed (see above)"
  log "matrix passed"
}

# The whole script is read before it runs (a change to the file during a long build cannot
# reach the running copy).
main() {
  case ${1:-} in
    build)
      [[ $# -eq 2 ]] || die "usage: $0 build VERSION"
      select_version "$2"
      cmd_build
      ;;
    test)
      [[ $# -ge 2 ]] || die "usage: $0 test VERSION [external] [in-tree] [python]"
      select_version "$2"
      shift 2
      cmd_test "$@"
      ;;
    matrix) cmd_matrix ;;
    *)
      sed -n '2,/^[^#]/{/^#/{s/^# \{0,1\}//;p}}' "$0"
      exit 2
      ;;
  esac
}

main "$@"
exit $?
