"""``wheelrail study noise`` on a short wheel set at two speeds (the full study runs 50-300 km/h)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wheelrail.core.noise.run_noise import DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH, pass_by_level
from wheelrail.core.study import noise_plan, run_study


@pytest.mark.slow
def test_noise_study_tables_physics_and_resume(tmp_path, monkeypatch):
    monkeypatch.setattr(noise_plan, "NOISE_SPEEDS_KMH", (100.0, 200.0))
    result = run_study("noise", ["sinter-wheel-1"], tmp_path, length=2.0, workers=1, progress=False)
    tables = {table.name: table for table in result.tables}
    lwa = tables["noise_sinter-wheel-1_lwa_vs_speed"]
    assert lwa.axis_name == "speed_kmh" and list(lwa.band_centres) == [100.0, 200.0]
    header = (tmp_path / "noise_sinter-wheel-1_lwa_vs_speed.csv").read_text().splitlines()[0]
    assert header.startswith("speed_kmh,hertz_LWA_dBA")
    for model in ("hertz", "hertz_winkler", "hertz_average", "2d", "3d"):
        assert np.all(np.isfinite(lwa.columns[f"{model}_LWA_dBA"]))
    # the sinter wheel's low lateral coherence: the 3D patch filters more than the 2D line (paper section 3.4),
    # so 3d is quieter than 2d, and both quieter than the unfiltered hertz
    assert np.all(lwa.columns["3d_LWA_dBA"] < lwa.columns["2d_LWA_dBA"] - 1.0)
    assert np.all(lwa.columns["2d_LWA_dBA"] < lwa.columns["hertz_LWA_dBA"])
    # the reference model's force radiated by the modal wheel instead of the directive's L_H,veh: a number per speed
    assert np.all(np.isfinite(lwa.columns["hertz_modal_wheel_LWA_dBA"]))
    # rolling noise grows with speed (about 30 lg v for CNOSSOS-like roughness spectra)
    assert lwa.columns["cnossos_a3_LWA_dBA"][1] > lwa.columns["cnossos_a3_LWA_dBA"][0] + 3
    lpaeq = tables["noise_sinter-wheel-1_lpaeq_vs_speed"]
    np.testing.assert_allclose(
        lpaeq.columns["3d_LpAeq_dBA"],
        [pass_by_level(x, DEFAULT_TRAIN_AXLES, DEFAULT_TRAIN_LENGTH) for x in lwa.columns["3d_LWA_dBA"]],
        atol=1e-9,
    )
    filters = tables["noise_sinter-wheel-1_filters_100kmh"]
    assert len(filters.band_centres) == 24 and math.isnan(filters.columns["3d_filter_db"][-1])  # 10 kHz left out
    assert np.nanmean(filters.columns["3d_filter_db"][14:22]) < -5  # 1.25-6.3 kHz: the 3D filter acts
    assert (tmp_path / "noise_noise.png").is_file() and (tmp_path / "noise_summary.json").is_file()
    again = run_study("noise", ["sinter-wheel-1"], tmp_path, length=2.0, workers=1, progress=False, figures=False)
    assert again.report.computed == 0 and again.report.cached == 10
    np.testing.assert_allclose(again.tables[0].columns["3d_LWA_dBA"], lwa.columns["3d_LWA_dBA"])


def test_noise_is_a_study(tmp_path):
    from wheelrail.core.errors import WheelrailError
    from wheelrail.core.study import STUDIES

    assert "noise" in STUDIES
    with pytest.raises(WheelrailError, match="unknown study"):
        run_study("nois", ["sinter-wheel-1"], tmp_path, progress=False)
