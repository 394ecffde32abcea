"""Recordings written by an earlier version still read, and today's writer writes the same content.

``tests/data/recording/main-*.rrd.gz`` were written (then gzipped) by ``record_result`` of commit 0b015c5,
before ``core/recording.py`` became a package, from ``synthetic_result(n=40, model=...)`` with the
description ``"written by main 0b015c5"`` (its ``roughness/lines`` are lines -3..3 of the bundled
``corrugated-rail`` set). If the file format changes on purpose, the reader must still
read these files; only the content comparison may then be updated (with new fixtures and a note why).
"""

from __future__ import annotations

import gzip
import json
from dataclasses import asdict
from pathlib import Path

import numpy as np
import pytest
from rerun.chunk import RrdReader
from test_recording import synthetic_result

from wheelrail.core.lateral_parameters import LateralParameters
from wheelrail.core.recording import read_recording, record_result
from wheelrail.core.roughness import load_roughness

DATA = Path(__file__).resolve().parents[1] / "data" / "recording"
DESCRIPTION = "written by main 0b015c5"
N_STEPS = 40
# columns that differ from one writing to the next: when a row was logged, and rerun's row ids
VOLATILE = ("log_time", "log_tick", "RowId")


def old_file(model: str, folder: Path) -> Path:
    path = folder / f"main-{model}.rrd"
    path.write_bytes(gzip.decompress((DATA / f"main-{model}.rrd.gz").read_bytes()))
    return path


def content(path: Path) -> dict:
    """Decoded content by (entity, static): temporal rows sorted by step; static values by component."""
    rows: dict = {}
    for chunk in RrdReader(path).stream():
        if chunk.entity_path.startswith("/__"):  # recording properties: id and start time
            continue
        batch = chunk.to_record_batch()
        columns = {
            name: batch.column(name).to_pylist()
            for name in batch.schema.names
            if not any(word in name for word in VOLATILE)
        }
        key = (chunk.entity_path, chunk.is_static)
        if chunk.is_static:  # a static component's rows in logging order (the last one counts)
            for name, values in columns.items():
                rows.setdefault(key, {}).setdefault(name, []).extend(v for v in values if v is not None)
        else:
            names = sorted(columns)
            rows.setdefault(key, []).extend(
                tuple((name, repr(columns[name][i])) for name in names) for i in range(len(columns["step"]))
            )
    for key, value in rows.items():
        if not key[1]:
            value.sort(key=lambda row: dict(row)["step"])
    return rows


@pytest.mark.parametrize("model", ["3d", "hertz-average"])
def test_old_recording_reads_back_exactly(tmp_path, model):
    result = synthetic_result(n=N_STEPS, model=model)
    back = read_recording(old_file(model, tmp_path))
    assert back.header == result.header
    for name in (
        "x",
        "force",
        "xi_wheel",
        "xi_rail",
        "roughness",
        "contact_length",
        "contact_area",
        "equivalent_roughness",
        "window_x",
        "window_y",
        "pressure",
    ):
        np.testing.assert_array_equal(getattr(back, name), getattr(result, name), err_msg=name)  # exact
    np.testing.assert_allclose(back.time, result.time, rtol=0, atol=0.5e-9)  # timeline in whole ns


@pytest.mark.parametrize("model", ["3d", "hertz-average"])
def test_writer_writes_what_the_old_writer_wrote(tmp_path, model):
    """Same entities, components and values as the file of the earlier version (volatile columns aside)."""
    old = content(old_file(model, tmp_path))
    # the earlier writer loaded the roughness set from the run's roughness name; today it is given
    new = content(
        record_result(
            synthetic_result(n=N_STEPS, model=model),
            tmp_path / "new.rrd",
            roughness=load_roughness("corrugated-rail"),
            description=DESCRIPTION,
        )
    )
    _as_the_old_layout(new)
    assert sorted(new) == sorted(old)
    for key in old:
        if key == ("/parameters", True):  # the contact geometry (wheel, crown, tread radii) added three
            new[key] = _without_new_parameters(new[key])  # parameters, the time-based run-in its duration
        if key == ("/spectra/force", True):  # the old centres in Hz, today's band numbers 10 lg f
            from wheelrail.core.recording.schema import band_numbers

            numbers, old_centres = new[key].pop("BarChart:abscissa"), old[key].pop("BarChart:abscissa")
            assert len(numbers) == len(old_centres) == 1
            for number, centres in zip(numbers, old_centres, strict=True):
                centres = np.array(centres["buffer"], dtype=np.uint8).view(np.float64)
                np.testing.assert_array_equal(number, band_numbers(centres))
        assert new[key] == old[key], key


def _as_the_old_layout(new: dict) -> None:
    """Today's file in the old files' layout, where it changed on purpose for the viewer (the blueprint test,
    ``test_blueprint.py``): the Hertz circle in pixels has its own entity (one entity held LineStrips2D and
    LineStrips3D, an error badge in both spatial views), and the force spectrum's bars stand over band numbers
    10 lg f with widths (over centres in Hz, 1 Hz wide by default, they were invisible)."""
    from wheelrail.core.recording.schema import BAR_WIDTH

    pixels = new.pop(("/contact/nominal_circle_image", True), None)
    if pixels is not None:
        new[("/contact/nominal_circle", True)].update(pixels)
    bars = new.get(("/spectra/force", True))
    if bars is not None:
        widths = bars.pop("BarChart:widths")
        assert all(w == [BAR_WIDTH] * len(w) for w in widths)
        numbers = [np.array(a["buffer"], dtype=np.uint8).view(np.float64) for a in bars["BarChart:abscissa"]]
        bars["BarChart:abscissa"] = numbers  # compared with the old centres below


_NEW_CONTACT_PARAMETERS = ("wheel_radius", "rail_crown_radius", "wheel_transverse_radius")


_LATERAL_DEFAULTS = json.loads(json.dumps(asdict(LateralParameters())))


def _without_new_parameters(component: dict) -> dict:
    """The parameters document without the geometry fields added since the old files (their defaults, None and
    an infinite tread, keep the old files' circle), the rail's loss factor and the pads' width (0) and the lateral
    track's inputs (``track.lateral``, their defaults: no vertical result reads them), without
    the run-in's duration (``run_in_time_s``, the run-in length over the speed), without ``recorded_steps``
    (the mark of a finished recording), ``wheel_model`` (the paper's 2-DOF) and the final document's ``digest_sha256``,
    re-rendered as the writer renders it."""
    import json

    from wheelrail.core.recording.schema import parameters_from_text

    rows = []
    for (text,) in component["TextDocument:text"]:  # the document at the start and at the end of the run
        document = parameters_from_text(text)
        contact = document["parameters"]["contact"]
        for name in _NEW_CONTACT_PARAMETERS:
            assert contact.pop(name) is None, name  # defaults: None (the radius), an infinite tread (JSON null)
        track = document["parameters"]["track"]  # the rail's loss factor and the pads' width: 0, the paper's
        assert track["rail"].pop("loss_factor") == 0.0 and track["support"].pop("pad_width") == 0.0
        assert track.pop("lateral") == _LATERAL_DEFAULTS  # the lateral track's inputs, added since: the defaults
        # the mark of a finished recording, added since: null at the start, the steps at the end
        assert document.pop("recorded_steps") in (None, N_STEPS)
        assert document.pop("wheel_model") == "2dof"  # the interaction's wheel, recorded since: the paper's
        if "digest_sha256" in document:
            assert len(document.pop("digest_sha256")) == 64  # the final document's SHA-256, added since
        run_in_time = document.pop("run_in_time_s")
        assert run_in_time == document["run_in_length_m"] / document["speed_m_per_s"]
        head = text.split("```json", 1)[0]
        rows.append([f"{head}```json\n{json.dumps(document, indent=2)}\n```\n"])
    return {**component, "TextDocument:text": rows}
