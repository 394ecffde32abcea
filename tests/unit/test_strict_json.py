"""Every metadata string the package writes is strict JSON (no ``Infinity``/``NaN``) and reads back."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.parameters import ModelParameters

ROOT = Path(__file__).resolve().parents[2]


def _reject_constant(name):
    raise ValueError(f"not strict JSON: {name}")


def _strict_loads(text: str):
    return json.loads(text, parse_constant=_reject_constant)


def _result(n: int = 50) -> RunResult:
    zeros = np.zeros(n)
    return RunResult(
        header=RunHeader(model="hertz", line=0, roughness_name="corrugated-rail", params=ModelParameters()),
        time=np.arange(n) * 3.6e-5,
        x=np.arange(n) * 1e-3,
        force=np.full(n, 65e3),
        xi_wheel=zeros,
        xi_rail=zeros,
        roughness=zeros,
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5),
        equivalent_roughness=zeros,
    )


def test_run_file_metadata_is_strict_json_and_reads_back(tmp_path):
    result = _result()
    assert result.header.params.contact.wheel_transverse_radius == np.inf  # the default: a cylindrical tread
    path = result.save_npz(tmp_path / "run.npz")
    with np.load(path, allow_pickle=False) as data:
        meta = _strict_loads(str(data["metadata"]))
    assert meta["parameters"]["contact"]["wheel_transverse_radius"] is None  # inf written as null
    back = RunResult.load_npz(path)
    assert back.header.params == result.header.params


def test_strict_json_writes_null_for_non_finite():
    text = strict_json({"a": np.inf, "b": [np.nan, 1.0], "c": np.float64(-np.inf)})
    assert _strict_loads(text) == {"a": None, "b": [None, 1.0], "c": None}


def test_metadata_is_written_only_through_strict_json():
    """The class, not the instance: a ``json.dump(s)`` elsewhere could write ``Infinity`` again.

    Allowed: jsonready.py itself, and the two cache-key hashes (cache.py, study/specs.py), whose text is
    hashed, never written or read as JSON (changing it would invalidate every stored entry).
    """
    allowed = {"core/files/jsonready.py", "core/files/cache.py", "core/study/specs.py"}
    offenders = []
    for path in [*ROOT.glob("core/**/*.py"), *ROOT.glob("explorer/**/*.py")]:
        relative = path.relative_to(ROOT).as_posix()
        if relative in allowed:
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if re.search(r"\bjson\.dumps?\(", line):
                offenders.append(f"{relative}:{number}")
    assert offenders == []
