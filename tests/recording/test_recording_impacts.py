"""A recording of a run over a discrete irregularity states it and its impacts (core/recording/sink.py)."""

from __future__ import annotations

import json

import pytest
from rerun.chunk import RrdReader

from wheelrail.core.engine import simulate
from wheelrail.core.engine.impacts import impact_summary
from wheelrail.core.files.jsonready import strict_json
from wheelrail.core.irregularities import WheelFlat
from wheelrail.core.parameters import ModelParameters, RunParameters
from wheelrail.core.recording import read_recording, record_result
from wheelrail.core.recording.schema import PARAMETERS, parameters_from_text


def _last_parameters(path) -> dict:
    """The last parameters document of a file (a finished recording's), straight from rerun's reader."""
    texts = [
        row[0]
        for c in RrdReader(path).stream()
        if c.entity_path == "/" + PARAMETERS and "TextDocument:text" in c.to_record_batch().schema.names
        for row in c.to_record_batch().column("TextDocument:text").to_pylist()
        if row
    ]
    return parameters_from_text(texts[-1])


@pytest.mark.slow
def test_a_flat_runs_recording_holds_the_flat_and_its_impacts(tmp_path):
    flat = WheelFlat(length=0.05, position=0.3)
    params = ModelParameters(run=RunParameters(irregularities=(flat,)))
    result = simulate("corrugated-rail", model="hertz", params=params, length=0.6)
    path = record_result(result, tmp_path / "flat.rrd")
    document = _last_parameters(path)
    assert document["impacts"] == json.loads(strict_json(impact_summary(result).to_dict()))  # exact, as JSON
    assert document["impacts"]["impacts"][0]["position_m"] == pytest.approx(0.3, abs=0.05)
    assert read_recording(path).header.params.run.irregularities == (flat,)  # the digest still holds


def test_a_smooth_runs_recording_has_no_impacts(tmp_path):
    result = simulate("corrugated-rail", model="hertz", length=0.05)
    document = _last_parameters(record_result(result, tmp_path / "smooth.rrd"))
    assert "impacts" not in document and document["recorded_steps"] == result.n_steps
