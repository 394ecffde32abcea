"""Roughness files by name or path: the bundled sets of ``wheelrail.sample_data`` and a user's ``.csv`` or
``.npz`` file, which works everywhere a bundled set does."""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path

from wheelrail.core.errors import WheelrailError
from wheelrail.core.roughness.csv_io import read_csv
from wheelrail.core.roughness.model import RoughnessSet
from wheelrail.core.roughness.npz_io import read_npz

SAMPLE_DATA_PACKAGE = "wheelrail.sample_data"


def read_roughness(path: str | os.PathLike, *, kind: str | None = None, label: str | None = None) -> RoughnessSet:
    """Read a ``.csv`` or ``.npz`` roughness file, chosen by its suffix. ``label``: what messages call the file
    (default its path; e.g. an upload's name, when the path is a temporary one the user never saw)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return read_csv(path, kind=kind, label=label)
    if suffix == ".npz":
        return read_npz(path, label=label)
    raise WheelrailError(f"{label or path}: unknown roughness file type {path.suffix!r}, allowed: .csv, .npz")


def bundled_names() -> list[str]:
    """Names of the bundled roughness sets (the ``.npz`` files of ``wheelrail.sample_data``)."""
    folder = resources.files(SAMPLE_DATA_PACKAGE)
    return sorted(entry.name[:-4] for entry in folder.iterdir() if entry.name.endswith(".npz"))


def load_roughness(name_or_path: str | os.PathLike) -> RoughnessSet:
    """Load a roughness set: a bundled one by name or a user's ``.csv``/``.npz`` file by path.

    A user file works everywhere a bundled set does.

    Parameters
    ----------
    name_or_path : str or os.PathLike
        A bundled set's name (:func:`bundled_names`: ``"corrugated-rail"``, ...) or a file's path.

    Returns
    -------
    RoughnessSet
        The heights (m) of the set's lines, their spacing and lateral positions (m), kind and description.

    Raises
    ------
    WheelrailError
        For an unknown name, a missing file or folder, or a file that is not a valid roughness file (each
        reader says what is wrong and where).

    See Also
    --------
    read_roughness : a file by path alone.
    wheelrail.core.roughness.write_csv : writes a set in the format read here.

    Examples
    --------
    >>> from wheelrail.core.roughness import load_roughness
    >>> rail = load_roughness("corrugated-rail")
    >>> rail.kind, rail.heights.shape[0], rail.dx     # kind, lines, spacing in m
    ('rail', 19, 0.001)
    """
    text = str(name_or_path)
    names = bundled_names()
    if text in names:
        resource = resources.files(SAMPLE_DATA_PACKAGE).joinpath(f"{text}.npz")
        with resources.as_file(resource) as path:
            return read_npz(path)
    path = Path(text)
    if path.suffix.lower() in (".csv", ".npz") or path.exists():
        if not path.is_file():
            problem = "is a folder, not a roughness file" if path.is_dir() else "roughness file not found"
            raise WheelrailError(f"{text}: {problem} (bundled sets: {', '.join(names)})")
        return read_roughness(path)
    raise WheelrailError(
        f"unknown roughness set {text!r}; bundled sets: {', '.join(names) or 'none'}; "
        "or give the path of a .csv or .npz file"
    )
