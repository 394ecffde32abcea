"""Run files (.npz) and recordings (.rrd) read back with checks: a flipped byte, an edited array or header, a run
no interaction could make (negative force, NaN speed, zero time step, unknown model, ...) is refused in one line
naming the file, in words (no Python exception names); a constant force says there is no fluctuating force."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ModelParameters
from wheelrail.core.recording import read_recording, record_result

DT = 1e-3 / (100 / 3.6)  # s, 1 mm at 100 km/h
N = 1200
PYTHON_NAMES = re.compile(r"KeyError|JSONDecodeError|BadZipFile|ValueError|TypeError|Traceback|Exception|Error\(")


def _result(n: int = N, force=None, model: str = "hertz") -> RunResult:
    t = np.arange(n) * DT
    if force is None:
        force = 65e3 + 2e3 * np.sin(2 * np.pi * 501.187 * t) + np.random.default_rng(3).normal(0, 30, n)
    roughness = 1e-6 * np.sin(2 * np.pi * t / 2e-3)
    return RunResult(
        header=RunHeader(model=model, line=0, roughness_name="corrugated-rail", params=ModelParameters()),
        time=t,
        x=0.02 + np.arange(n) * 1e-3,
        force=np.asarray(force, dtype=float),
        xi_wheel=np.full(n, 8e-5),
        xi_rail=np.full(n, 3e-5),
        roughness=roughness,
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5),
        equivalent_roughness=roughness,
        loss_of_contact_steps=int(np.count_nonzero(np.asarray(force) == 0)) if force is not None else 0,
    )


def _refused(read, path, *fragments):
    with pytest.raises(WheelrailError) as error:
        read(path)
    text = str(error.value)
    assert "\n" not in text and str(path) in text and not PYTHON_NAMES.search(text), text
    for fragment in fragments:
        assert fragment in text, text
    return text


def _edited_npz(tmp_path, name, *, meta=None, arrays=None, keep_digest=False):
    """A run file edited as a user might with numpy: metadata or arrays changed, the digest dropped (a file
    written before digests) unless ``keep_digest``."""
    path = _result().save_npz(tmp_path / "run.npz")
    with np.load(path) as data:
        stored = {key: data[key] for key in data.files}
    header = json.loads(str(stored["metadata"]))
    if meta is not None:
        meta(header)
    stored["metadata"] = np.array(json.dumps(header))
    if arrays is not None:
        arrays(stored)
    if not keep_digest:
        stored.pop("digest", None)
    target = tmp_path / f"{name}.npz"
    np.savez(target, **stored)
    return target


def _set_run(key, value):
    return lambda header: header["parameters"]["run"].__setitem__(key, value)


@pytest.mark.parametrize(
    ("name", "meta", "arrays", "fragment"),
    [
        ("nan-speed", _set_run("speed", float("nan")), None, "RunParameters.speed nan m/s: not a number"),
        ("negative-speed", _set_run("speed", -27.0), None, "RunParameters.speed -27 m/s is outside"),
        ("zero-element", _set_run("element_size", 0.0), None, "RunParameters.element_size"),
        ("derived-speed", lambda h: h.__setitem__("speed_m_per_s", float("nan")), None, "speed_m_per_s"),
        ("zero-time-step", lambda h: h.__setitem__("time_step_s", 0.0), None, "time_step_s 0.0 disagrees"),
        ("unknown-model", lambda h: h.__setitem__("model", "banana"), None, "'banana' is not a known contact model"),
        ("no-model", lambda h: h.pop("model"), None, "run header is incomplete: no model"),
        ("line", lambda h: h.__setitem__("line", 1.5), None, "line 1.5 is not a whole number"),
        ("run-in", lambda h: h.__setitem__("run_in_length_m", -1.0), None, "run_in_length_m -1.0"),
        ("header-list", lambda h: h.clear(), None, "run header is incomplete"),
        ("negated-force", None, lambda a: a.__setitem__("force", -a["force"]), "contact is compressive (F >= 0"),
        ("nan-force", None, lambda a: a["force"].__setitem__(5, np.nan), "the contact force holds NaN"),
        ("text-force", None, lambda a: a.__setitem__("force", a["force"].astype(str)), "not numbers"),
        ("short-force", None, lambda a: a.__setitem__("force", a["force"][:-1]), "different lengths"),
        ("empty", None, lambda a: [a.__setitem__(k, v[:0]) for k, v in list(a.items()) if v.ndim], "no steps"),
        ("no-x", None, lambda a: a.pop("x"), "no 'x' array"),
        ("extra", None, lambda a: a.__setitem__("notes", np.zeros(3)), "'notes', which no run file has"),
        ("time", None, lambda a: a.__setitem__("time", a["time"] * 2), "times are not 3.6e-05 s"),
        ("x", None, lambda a: a.__setitem__("x", a["x"] * 2), "positions are not 0.001 m"),
        ("loss", lambda h: h.__setitem__("loss_of_contact_steps", 7), None, "7 loss-of-contact steps"),
    ],
    ids=lambda v: v if isinstance(v, str) else "",
)
def test_an_impossible_or_edited_run_file_is_refused_in_one_line(tmp_path, name, meta, arrays, fragment):
    path = _edited_npz(tmp_path, name, meta=meta, arrays=arrays)
    _refused(RunResult.load_npz, path, fragment)
    # with the digest it was written with, the same edit is refused for not matching it
    path = _edited_npz(tmp_path, f"{name}-digest", meta=meta, arrays=arrays, keep_digest=True)
    _refused(RunResult.load_npz, path)


def test_damaged_npz_files_are_refused_in_words(tmp_path):
    good = _result().save_npz(tmp_path / "good.npz")
    raw = good.read_bytes()
    (tmp_path / "truncated.npz").write_bytes(raw[: len(raw) // 2])
    _refused(RunResult.load_npz, tmp_path / "truncated.npz", "not a readable wheelrail run file")
    (tmp_path / "text.npz").write_text("hello")
    _refused(RunResult.load_npz, tmp_path / "text.npz", "not a readable wheelrail run file")
    np.savez(tmp_path / "no-meta.npz", force=np.ones(3))
    _refused(RunResult.load_npz, tmp_path / "no-meta.npz", "no run metadata")
    _refused(RunResult.load_npz, tmp_path / "missing.npz", "does not exist")
    _edited = _edited_npz(tmp_path, "json", meta=None)
    with np.load(_edited) as data:
        stored = {key: data[key] for key in data.files}
    stored["metadata"] = np.array("{not json")
    np.savez(tmp_path / "json.npz", **stored)
    _refused(RunResult.load_npz, tmp_path / "json.npz", "its metadata is not JSON")


@pytest.mark.parametrize("content", [b"hello", b"", b"PK\x03\x04 cut short"], ids=["text", "empty", "zip-head"])
def test_a_file_that_is_no_npz_archive_is_named_so_without_numpys_advice(tmp_path, content):
    # numpy's reason for a text file ("This file contains pickled (object) data. If you trust the file you can
    # load it unsafely using the `allow_pickle=` keyword argument or `pickle.load()`") and zipfile's ("File is not
    # a zip file") reached `noise --run` and the explorer's upload, while `spectra` said it in words
    path = tmp_path / "not-a-run.npz"
    path.write_bytes(content)
    text = _refused(RunResult.load_npz, path, "not a NumPy .npz archive")
    assert "pickle" not in text and "zip file" not in text, text


def _flipped_copies(good, folder):
    """(offset, path) of 48 copies of the file ``good``, each with one byte flipped (XOR 0x5A), spread evenly over
    it: ``folder/flip-OFFSET.SUFFIX``."""
    raw = good.read_bytes()
    copies = []
    for offset in np.linspace(0, len(raw) - 1, 48).astype(int):
        flipped = bytearray(raw)
        flipped[offset] ^= 0x5A
        path = folder / f"flip-{offset}{good.suffix}"
        path.write_bytes(bytes(flipped))
        copies.append((int(offset), path))
    return copies


def test_every_single_byte_flip_of_a_run_file_is_refused_or_harmless(tmp_path):
    good = _result().save_npz(tmp_path / "good.npz")
    original = RunResult.load_npz(good)
    silent = []
    for offset, path in _flipped_copies(good, tmp_path):
        try:
            back = RunResult.load_npz(path)
        except WheelrailError as error:
            assert "\n" not in str(error) and not PYTHON_NAMES.search(str(error)), str(error)
            continue
        if not all(np.array_equal(getattr(back, k), getattr(original, k)) for k in ("time", "force", "x", "xi_rail")):
            silent.append(int(offset))
    assert silent == []


def _recording(tmp_path, result=None):
    return record_result(result if result is not None else _result(), tmp_path / "run.rrd", chunk_steps=400)


# Reads each flipped recording in turn and prints one line per file: "refused", "same", "silent" or "named" (a
# refusal whose words carry a Python name); the parent restarts it after a file whose decoding aborted the process.
_FLIP_READER = """
import sys, warnings
import numpy as np
from wheelrail.core.errors import WheelrailError
from wheelrail.core.recording import read_recording
sys.path.insert(0, sys.argv[1])
from test_damaged_runs import PYTHON_NAMES
original = read_recording(sys.argv[2])
fields = ("time", "force", "x", "xi_wheel", "xi_rail", "roughness", "contact_length", "contact_area")
for path in sys.argv[3:]:
    print(path, flush=True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an incomplete-recording warning is not a refusal
            back = read_recording(path)
    except WheelrailError as error:
        text = str(error)
        print("named" if "\\n" in text or PYTHON_NAMES.search(text) else "refused", flush=True)
        continue
    same = back.header == original.header and all(
        np.array_equal(getattr(back, k), getattr(original, k), equal_nan=True) for k in fields
    )
    print("same" if same else "silent", flush=True)
"""


def test_every_single_byte_flip_of_a_recording_is_refused_or_reads_back_the_same(tmp_path):
    """48 single-byte flips across a recording: each is refused in words or reads back exactly the recording;
    none reads back different data without a word (the digest). A flip that makes rerun's own decoder abort the
    process (its Arrow conversion, upstream of wheelrail; docs/limitations.md) is counted, not read: each file is
    read in a child process that is restarted after one."""
    import subprocess
    import sys
    from pathlib import Path

    good = _recording(tmp_path)
    paths = [str(path) for _, path in _flipped_copies(good, tmp_path)]
    outcome, aborted, todo = {}, [], list(paths)
    while todo:
        child = subprocess.run(
            [sys.executable, "-c", _FLIP_READER, str(Path(__file__).parent), str(good), *todo],
            capture_output=True,
            text=True,
        )
        lines = child.stdout.splitlines()
        for path, verdict in zip(lines[0::2], lines[1::2], strict=False):
            outcome[path] = verdict
        if child.returncode == 0:
            break
        assert len(lines) % 2 == 1, child.stderr[-2000:]  # the child stopped while it read a file
        aborted.append(lines[-1])
        todo = todo[todo.index(lines[-1]) + 1 :]
    silent = [p for p, v in outcome.items() if v in ("silent", "named")]
    assert silent == [], silent
    assert len(outcome) + len(aborted) == len(paths)
    assert len(aborted) <= 2, aborted  # rare: 1 run of 10 had one such flip among 48


def test_recordings_are_checked_like_run_files(tmp_path):
    force = 65e3 + 2e3 * np.sin(np.arange(N) * 0.3)
    negated = _recording(tmp_path, _result(force=-force))
    _refused(read_recording, negated, "contact is compressive (F >= 0")


def test_a_constant_force_says_there_is_no_fluctuating_force(tmp_path, capsys):
    from wheelrail.cli import main

    path = _result(force=np.full(N, 65e3)).save_npz(tmp_path / "constant.npz")
    for argv in (["spectra", str(path)], ["noise", "--run", str(path)]):
        assert main(argv) != 0
        out, err = capsys.readouterr()
        assert out == "" and len(err.strip().splitlines()) == 1, err
        assert "the contact force is constant (65000 N) after the start-up: there is no fluctuating force" in err
        assert "-inf" not in err
