"""Which packages setuptools installs; everything else is in pyproject.toml.

The folders stay at the top level of the repository (``core/``, ``explorer/``, ...) but install under the one
namespace ``wheelrail`` (so that an install never claims generic top-level names such as ``core``). pyproject.toml
can map folders to packages but cannot find the packages inside a mapped folder, so they are found here: a new
sub-package is in every wheel without a list to update (tests/unit/test_packaging.py builds one and checks).
"""

from pathlib import Path

from setuptools import find_packages, setup

HERE = Path(__file__).resolve().parent
# installed package -> its folder in this repository
PACKAGE_DIRS = {
    "wheelrail": "package",
    "wheelrail.cli": "cli",
    "wheelrail.core": "core",
    "wheelrail.explorer": "explorer",
    "wheelrail.sample_data": "sample_data",
}


def _packages() -> list[str]:
    found = []
    for name, folder in PACKAGE_DIRS.items():
        found += [name, *(f"{name}.{sub}" for sub in find_packages(str(HERE / folder)))]
    return found


setup(package_dir=PACKAGE_DIRS, packages=_packages())
