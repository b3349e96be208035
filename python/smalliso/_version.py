# The one version of the project: the C++ module and tools (CMakeLists.txt reads this line), the
# ITK wrapping's wheel (pyproject.toml) and this package.
__version__ = "0.1.0"
