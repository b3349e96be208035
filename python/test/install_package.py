"""Installs the smalliso package as a user does, for the tests: builds the sdist and, from it, the
wheel (python3 -m build, without build isolation), installs the wheel into a fresh virtual
environment that sees the system's NumPy, Dask and Zarr, and checks that the package imports there,
from a folder where the source tree is not importable, with the project's version.

Usage: install_package.py SOURCE_DIR PACKAGE_DIR
  SOURCE_DIR   the package's folder (python/ in the repository)
  PACKAGE_DIR  where to put dist/ (the sdist and the wheel) and venv/ (made anew)
"""

import ast
import pathlib
import shutil
import subprocess
import sys


def main(source, package):
    shutil.rmtree(package, ignore_errors=True)
    package.mkdir(parents=True)
    subprocess.run([sys.executable, "-m", "build", "--no-isolation", "--skip-dependency-check",
                    "--outdir", str(package / "dist"), str(source)], check=True)
    sdists, wheels = sorted((package / "dist").glob("*.tar.gz")), sorted((package / "dist").glob("*.whl"))
    if len(sdists) != 1 or len(wheels) != 1:
        sys.exit(f"expected one sdist and one wheel in {package / 'dist'}, found {sdists + wheels}")
    venv = package / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-index", "--quiet", str(wheels[0])],
                   check=True)
    probe = ("import smalliso, smalliso.dask; print(smalliso.__version__); print(smalliso.__file__); "
             "print(smalliso._core.__file__)")
    lines = subprocess.run([str(venv / "bin" / "python"), "-c", probe], cwd=package, check=True,
                           capture_output=True, text=True).stdout.split()
    expected = version_of(source)
    if lines[0] != expected:
        sys.exit(f"the installed package says version {lines[0]}, the source {expected}")
    for path in lines[1:]:
        if not pathlib.Path(path).resolve().is_relative_to(venv.resolve()):
            sys.exit(f"smalliso was imported from {path}, not from the virtual environment {venv}")
    print(f"smalliso {expected} installed from {wheels[0].name} into {venv}")


def version_of(source):
    """The version in smalliso/_version.py, read without importing the package."""
    tree = ast.parse((source / "smalliso" / "_version.py").read_text())
    return next(node.value.value for node in tree.body if isinstance(node, ast.Assign)
                and node.targets[0].id == "__version__")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(pathlib.Path(sys.argv[1]).resolve(), pathlib.Path(sys.argv[2]).resolve())
