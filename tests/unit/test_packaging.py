"""Packaging: the version, a wheel built from the repository holds every sub-package and data file, Dask is an
optional extra, the lint tool is pinned once."""

import email
import importlib.metadata
import re
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

import wheelrail
from wheelrail.cli import main
from wheelrail.core.errors import WheelrailError
from wheelrail.core.study.execution import parse_dask_address

ROOT = Path(__file__).resolve().parents[2]
# the repository's folders and the packages they install as (setup.py's PACKAGE_DIRS, restated on purpose: the
# test checks the build, not the build script against itself)
FOLDERS = {
    "package": "wheelrail",
    "cli": "wheelrail.cli",
    "core": "wheelrail.core",
    "explorer": "wheelrail.explorer",
    "sample_data": "wheelrail.sample_data",
}


def test_version_is_the_package_metadata_and_the_command_prints_it(capsys):
    assert re.fullmatch(r"\d+\.\d+\.\d+", wheelrail.__version__)
    assert importlib.metadata.version("wheelrail") == wheelrail.__version__
    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out == f"wheelrail {wheelrail.__version__}\n"


def _packages_on_disk() -> set[str]:
    """Every folder with an __init__.py under the mapped folders, as the package it installs as."""
    found = set()
    for folder, package in FOLDERS.items():
        for init in (ROOT / folder).rglob("__init__.py"):
            relative = init.parent.relative_to(ROOT / folder).parts
            found.add(".".join((package, *relative)))
    return found


@pytest.mark.slow
def test_a_wheel_built_from_the_repository_holds_every_sub_package(tmp_path):
    # build from a copy (setuptools writes build/ and *.egg-info into the tree it builds), offline
    source = shutil.copytree(
        ROOT,
        tmp_path / "source",
        ignore=shutil.ignore_patterns(
            ".venv", ".git", "__pycache__", "*.egg-info", "build", "dist", "test-artifacts", ".*_cache"
        ),
    )
    build = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "--no-index",
            "--quiet",
            "--wheel-dir",
            str(tmp_path / "dist"),
            str(source),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert build.returncode == 0, build.stderr
    (wheel,) = (tmp_path / "dist").glob("wheelrail-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    packages = {name.removesuffix("/__init__.py").replace("/", ".") for name in names if name.endswith("/__init__.py")}
    expected = _packages_on_disk()
    assert {
        "wheelrail",
        "wheelrail.core.contact",
        "wheelrail.core.track",
        "wheelrail.core.study",
        "wheelrail.core.noise",
    } <= expected
    assert packages == expected
    # every module of every package, the bundled sets and the command
    modules = {
        f"{package.replace('.', '/')}/{path.relative_to(ROOT / folder).as_posix()}"
        for folder, package in FOLDERS.items()
        for path in (ROOT / folder).rglob("*.py")
        if "__pycache__" not in path.parts
    }
    assert modules <= names, sorted(modules - names)
    sets = {f"wheelrail/sample_data/{path.name}" for path in (ROOT / "sample_data").glob("*.npz")}
    assert len(sets) == 4 and sets <= names
    # the data files read at run time: the CNOSSOS-EU tables of the noise source (wheelrail.core.noise.tables)
    # and EN ISO 3095's vertical and lateral track decay limits (wheelrail.core.noise.decay)
    tables = {
        f"wheelrail/core/noise/data/{path.name}"
        for path in (ROOT / "core" / "noise" / "data").iterdir()
        if path.is_file()
    }
    assert len(tables) == 7 and tables <= names, sorted(tables - names)
    info = next(name.split("/")[0] for name in names if name.endswith(".dist-info/METADATA"))
    metadata = email.message_from_bytes(zipfile.ZipFile(wheel).read(f"{info}/METADATA"))
    assert metadata["Version"] == wheelrail.__version__
    requires = metadata.get_all("Requires-Dist")
    dask = [line for line in requires if line.startswith("dask")]
    assert dask and all('extra == "cluster"' in line for line in dask)  # Dask only with the cluster extra
    assert any(re.match(r"viser[<>=,.\d ]*<", line) for line in requires)  # viser has an upper bound
    entry_points = zipfile.ZipFile(wheel).read(f"{info}/entry_points.txt").decode()
    assert "wheelrail = wheelrail.cli:main" in entry_points


def test_study_on_dask_without_dask_installed_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if the cluster extra were not installed
    code = main(
        ["study", "speeds", "--set", "sinter-wheel-1", "--dask", "tcp://127.0.0.1:8786", "--out", str(tmp_path / "o")]
    )
    err = capsys.readouterr().err
    assert code == 2
    assert err == (
        "wheelrail study: error: --dask: needs Dask, an optional part of wheelrail: pip install 'wheelrail[cluster]'\n"
    )
    assert not (tmp_path / "o").exists()  # refused before any work
    with pytest.raises(WheelrailError) as refused:  # the API names its own argument
        parse_dask_address("tcp://127.0.0.1:8786")
    assert str(refused.value) == (
        "dask_address: needs Dask, an optional part of wheelrail: pip install 'wheelrail[cluster]'"
    )


def test_ruff_is_pinned_once_for_the_tests_and_ci():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    (pin,) = [spec for spec in extras["test"] if spec.startswith("ruff")]
    assert re.fullmatch(r"ruff==\d+\.\d+\.\d+", pin)
    ci = (ROOT / ".ci" / "run").read_text()
    assert re.findall(r"ruff==[\d.]+", ci) == [pin]  # CI lints with the same ruff before it installs the rest
