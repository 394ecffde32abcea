"""The Noise tab's contact position (``core.inputs.contact_position``, declared once): two fields in mm, the run's
noise recomputed with the contact off the rail's centreline (the ``rail_lateral`` component in the table, the
curves and the download), a value outside its range said in the page's words, centred the run's own noise."""

import functools
import json

import numpy as np
import pytest

from wheelrail.core.inputs.contact_position import ContactPosition
from wheelrail.core.noise import run_noise as run_noise_module
from wheelrail.core.noise.run_noise import AXLE_DB, run_noise
from wheelrail.core.noise.twins import NoiseNumerics
from wheelrail.explorer.tabs import NoiseTab

pytestmark = pytest.mark.slow  # a server, a 1 m run and its rolling noise: ~30-60 s

SMALL = NoiseNumerics(track_bays=40, elements_per_bay=4, points_per_band=1)  # the recomputed noise's, for speed


def _row(tab) -> str:
    return next(line for line in tab.totals_md.content.splitlines() if line.startswith("| **hertz**"))


def test_the_noise_tab_takes_the_contact_position(app, finish_run, monkeypatch):
    monkeypatch.setattr(run_noise_module, "run_noise", functools.partial(run_noise, numerics=SMALL))
    app.form.set_dropdown.value = "corrugated-rail"
    app.form.model_dropdown.value = "hertz"
    app.form.length_text.value = "1"
    result = finish_run(app)
    tab = app.tab(NoiseTab)
    assert [field.value for field in tab.position_texts] == ["0", "0"]
    heads = tab.totals_md.content.splitlines()[0]
    assert "| rail | rail, lateral | sleeper |" in heads
    assert _row(tab).split(" | ")[2] == "-"  # centred: the rail does not move sideways

    tab.position_texts[0].value = "10"  # mm off the rail's centreline: the run's noise recomputed
    expected = run_noise(result, numerics=SMALL, contact_position=ContactPosition(rail_offset=0.01))
    assert _row(tab).split(" | ")[2] == f"{expected.sound_power_dba['rail_lateral'] + AXLE_DB:.1f}"
    curves = dict(zip([label for label, _, _ in tab.power.series], tab.power.data[1:], strict=True))
    assert np.any(np.isfinite(np.asarray(curves["hertz: rail_lateral"], dtype=float)))
    summary = json.loads(tab.download_json()[1])  # the download is what the tab shows
    assert summary["configuration"]["contact_position"] == {"rail_offset_m": 0.01, "wheel_offset_m": 0.0}

    tab.position_texts[0].value = "40"  # beyond the railhead's accepted range: said in the page's words
    content = tab.totals_md.content
    assert "Contact offset on the railhead 40 mm" in content and "-30 to 30 mm" in content
    assert "\n" not in content and "Traceback" not in content and tab.json_button.disabled

    tab.position_texts[0].value = "0"  # centred again: the run's own noise
    assert _row(tab).split(" | ")[2] == "-"
