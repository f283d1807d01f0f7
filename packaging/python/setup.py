"""Wheel and sdist of the CMake-built package clearshape (pyproject.toml has the metadata).

The extension clearshape._core is not compiled here: CMake built it for this Python
(docs/python.md). In <build>/python-dist this copies the package from <build>/python/clearshape
(CLEARSHAPE_PYTHON_PACKAGE overrides the place); an unpacked sdist already holds it. The wheel is
marked as platform-specific (cpXY-cpXY-linux_<arch>), since it carries a compiled extension.
"""
import os
import shutil
from pathlib import Path

from setuptools import setup
from setuptools.dist import Distribution

HERE = Path(__file__).resolve().parent
PATTERNS = ("*.py", "*.pyi", "py.typed", "_core*.so")


def copy_built_package() -> None:
    built = Path(os.environ.get("CLEARSHAPE_PYTHON_PACKAGE", HERE.parent / "python" / "clearshape"))
    if not built.is_dir():
        if not (HERE / "clearshape" / "__init__.py").is_file():
            raise SystemExit(f"setup.py: no package clearshape here and none built at {built} "
                             "(build the CMake target clearshape_python first, or set CLEARSHAPE_PYTHON_PACKAGE)")
        return
    target = HERE / "clearshape"
    shutil.rmtree(target, ignore_errors=True)
    target.mkdir()
    for pattern in PATTERNS:
        for f in built.glob(pattern):
            shutil.copy2(f, target / f.name)
    if not list(target.glob("_core*.so")):
        raise SystemExit(f"setup.py: {built} has no extension _core*.so (build the CMake target clearshape_python)")


class BinaryDistribution(Distribution):
    """A distribution with a compiled extension: the wheel gets the platform's tag."""

    def has_ext_modules(self) -> bool:
        return True


copy_built_package()
setup(distclass=BinaryDistribution, packages=["clearshape"], include_package_data=False,
      package_data={"clearshape": ["_core*.so", "*.pyi", "py.typed"]})
