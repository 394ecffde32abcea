"""The Noise tab's choice of the wheel's sound power (``noise_wheel_model`` of ``core.inputs.declared.CHOICES``): the
directive's L_H,veh or the modal wheel's, used in the tab's curves, table, download and stated in its text."""

import json

import numpy as np
import pytest

from wheelrail.core.noise import wheel_power
from wheelrail.core.noise.run_noise import run_noise
from wheelrail.explorer.tabs import NoiseTab

pytestmark = pytest.mark.slow  # a server, a 1 m run and its rolling noise with both wheels: ~15-30 s


@pytest.fixture(scope="module", autouse=True)
def coarse_wheel():
    """The noise chain's modal wheel up to 3 kHz and n = 0..4 (as test_explorer_wheel_tab.py), its memory-cached
    radiation table emptied before and after."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(wheel_power, "MAX_FREQUENCY", 3000.0)
        patch.setattr(wheel_power, "MAX_HARMONIC", 4)
        wheel_power.radiation_table.cache_clear()
        yield
    wheel_power.radiation_table.cache_clear()


def test_the_noise_tab_offers_the_declared_wheels_and_shows_the_chosen_one(app, finish_run):
    app.form.set_dropdown.value = "corrugated-rail"
    app.form.model_dropdown.value = "hertz"
    app.form.length_text.value = "1"
    result = finish_run(app)
    tab = app.tab(NoiseTab)
    assert tuple(tab.wheel_dropdown.options) == ("directive", "modal") and tab.wheel_dropdown.value == "directive"
    assert "| wheel (directive) |" in tab.totals_md.content and "L_H,veh" in tab.totals_md.content
    directive = dict(zip([label for label, _, _ in tab.power.series], tab.power.data[1:], strict=True))

    tab.wheel_dropdown.value = "modal"  # the tab recomputes the run's noise with the modal wheel's power
    expected = run_noise(result, wheel_model="modal")
    assert "| wheel (modal) |" in tab.totals_md.content and expected.configuration["wheel"] in tab.totals_md.content
    row = next(line for line in tab.totals_md.content.splitlines() if line.startswith("| **hertz**"))
    assert f"| {expected.sound_power_dba['wheel'] + 10 * np.log10(2):.1f} |" in row  # per axle: +3 dB
    modal = dict(zip([label for label, _, _ in tab.power.series], tab.power.data[1:], strict=True))
    # the rail's curve is the same chain (the run's force, the track), the wheel's is the modal one's
    np.testing.assert_allclose(modal["hertz: rail"], directive["hertz: rail"], atol=1e-9)
    assert np.nanmax(np.abs(np.asarray(modal["hertz: wheel"]) - np.asarray(directive["hertz: wheel"]))) > 0.5
    assert "(wheel: modal)" in tab.power.handle.title  # the plot shown (its PNG the same)
    summary = json.loads(tab.download_json()[1])  # the download is what the tab shows
    assert summary["configuration"]["wheel_model"] == "modal"
    tab.wheel_dropdown.value = "directive"
    assert "| wheel (directive) |" in tab.totals_md.content
