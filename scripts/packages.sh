# The Debian packages the project needs, and the function that installs the missing ones.
# Sourced by setup.sh and coverage.sh.

smalliso_packages=(
  build-essential cmake ninja-build pkg-config
  libinsighttoolkit5-dev  # ITK 5.2.1
  libgtest-dev            # GoogleTest
  zlib1g-dev              # the tools' streamed image files
  nlohmann-json3-dev      # the tools' JSON (statistics, report), header only
  python3                 # test helpers (XML and JSON checks)
  clang-format            # the format check of scripts/test.sh
  gnuplot-nox             # SmallIsoComponentReport --plot
  libvtk9-dev libx11-dev  # isosurfaces, piece counts and --render (optional for the module)
  xvfb libgl1-mesa-dri    # off-screen rendering on a machine without a display
  # The smalliso Python package (NumPy and Dask), its tests and its benchmarks (with their peers
  # and the NIfTI reader of the label maps); its sdist and wheel (python3 -m build) and the
  # virtual environment the tests install the wheel into
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3-dask python3-distributed python3-zarr python3-skimage python3-scipy python3-nibabel
  python3-setuptools python3-build python3-venv
)

# Installs those of the packages named that are not installed yet (as root, or with sudo).
smalliso_install_missing() {
  local missing=() p sudo=""
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -gt 0 ] || return 0
  echo "${0##*/}: installing missing Debian packages: ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "${0##*/}: need root (or sudo) to install: ${missing[*]}" >&2; return 1; }
    sudo=sudo
  fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}
