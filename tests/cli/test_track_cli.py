"""`wheelrail track`: resonances, cache, --json, --csv, bad input (one line on stderr, non-zero exit)."""

import csv
import json

import numpy as np
import pytest

from wheelrail.cli import main


def test_help_lists_commands(capsys):
    with pytest.raises(SystemExit) as info:
        main(["--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    assert "track" in out and "explore" in out


@pytest.mark.slow
def test_track_json_csv(tmp_path, capsys):
    # The full default track: one-off precompute (about 10-20 s here), then cached.
    out_csv = tmp_path / "receptance.csv"
    assert main(["track", "--json", "--csv", str(out_csv), "--df-hz", "20"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["resonances_hz"]["pinned_pinned_hz"] == pytest.approx(943, rel=0.03)
    assert summary["sleeper_passing_frequency_hz"] == pytest.approx(100 / 3.6 / 0.65)
    assert summary["cache"]["size_bytes"] > 0
    with open(out_csv) as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == [
        "frequency_hz",
        "above_sleeper_abs_m_per_n",
        "above_sleeper_phase_rad",
        "midspan_abs_m_per_n",
        "midspan_phase_rad",
    ]
    data = np.array(rows[1:], dtype=float)
    assert data[0, 0] == 20 and data[-1, 0] == 5000
    # around the pinned-pinned frequency the midspan receptance is the larger one
    near = np.argmin(np.abs(data[:, 0] - 940))
    assert data[near, 3] > 3 * data[near, 1]
    # the decay rate per band beside EN ISO 3095:2013's lower limit (JSON and the _decay CSV)
    decay = summary["decay_rate"]
    f = np.array(decay["frequency_hz"])
    assert len(f) == len(decay["decay_rate_dB_per_m"]) == len(decay["limit_dB_per_m"]) == 24
    limits = {round(fc, -1): v for fc, v in zip(f, decay["limit_dB_per_m"], strict=True) if v is not None}
    assert limits == {250: 2.0, 320: 2.0, 400: 6.0, 500: 6.0, 630: 6.0, 790: 2.19, 1000: 0.8, 1260: 0.8,
                      1580: 0.8, 2000: 0.8, 2510: 0.8, 3160: 0.8, 3980: 0.8, 5010: 0.8}  # fmt: skip
    rates = np.array(decay["decay_rate_dB_per_m"])
    below = [fc for fc, rate, v in zip(f, rates, decay["limit_dB_per_m"], strict=True) if v is not None and rate < v]
    assert decay["below_limit_hz"] == pytest.approx(below) and decay["meets_limit"] is (not below)
    assert summary["track_parameters"]["rail"]["loss_factor"] == 0.0 and summary["track"]["pad_width"] == 0.0
    receptance = summary["point_receptance"]
    assert len(receptance["frequency_hz"]) == len(receptance["midspan_m_per_n"]) == len(data)
    with open(tmp_path / "receptance_decay.csv") as handle:
        decay_rows = list(csv.reader(handle))
    assert decay_rows[0][:2] == ["frequency_hz", "decay_rate_dB_per_m"] and len(decay_rows) == 25
    np.testing.assert_allclose([float(r[1]) for r in decay_rows[1:]], rates, rtol=1e-5)
    # the lateral decay rate beside EN ISO 3095:2013's lateral limit (Figure 3, curve B): JSON and the _decay CSV
    lateral = summary["lateral_decay_rate"]
    assert len(lateral["frequency_hz"]) == len(lateral["decay_rate_dB_per_m"]) == len(lateral["limit_dB_per_m"]) == 24
    lateral_limits = {round(fc, -1): v for fc, v in zip(f, lateral["limit_dB_per_m"], strict=True) if v is not None}
    assert lateral_limits == {250: 2.04, 320: 1.38, 400: 0.94, 500: 0.64, 630: 0.43, 790: 0.29, 1000: 0.2,
                              1260: 0.2, 1580: 0.32, 2000: 0.5, 2510: 0.5, 3160: 0.5, 3980: 0.5, 5010: 0.5}  # fmt: skip
    assert "curve B (lateral)" in lateral["limit_source"] and lateral["band_labels"][7] == "250"
    assert decay_rows[0][4:] == ["lateral_decay_rate_dB_per_m", "iso3095_lateral_limit_dB_per_m", "lateral_below_limit"]
    np.testing.assert_allclose([float(r[4]) for r in decay_rows[1:]], lateral["decay_rate_dB_per_m"], rtol=1e-5)
    assert len(summary["lateral_receptance"]["lateral_point_m_per_n"]) == 24
    # second call: loaded from cache
    assert main(["track", "--json", "--speed-kmh", "140"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["cache"]["was_cached"] is True
    # its timings are reported (no bound on them: a wall time depends on the machine's load; benchmarks/ time it)
    assert again["cache"]["speed_time_s"] > 0.0 and again["cache"]["stationary_time_s"] > 0.0


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["track", "--speed-kmh", "0"], "--speed-kmh 0 is outside the accepted 5 to 400 km/h"),
        (["track", "--speed-kmh", "nan"], "--speed-kmh nan: not a number"),
        (["track", "--csv", "/no/such/folder/r.csv"], "does not exist"),
        (["track", "--df-hz", "-1"], "--df-hz"),
    ],
)
def test_bad_input_is_one_line(argv, fragment, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert fragment in err and err.count("\n") == 1


def test_bands_are_named_by_their_nominal_centres(capsys):
    # `wheelrail track` once named its bands 79, 126, 158, 251, 398, 1259, 2512 Hz (the exact centres
    # rounded) where every other output says 80, 125, 160, 250, 400, 1250, 2500 (``spectra.bands.band_labels``).
    from wheelrail.cli.commands.track import _print_bands
    from wheelrail.core.spectra.bands import noise_bands

    f = noise_bands()
    f = f[f < 5100]
    ones = np.ones(len(f))
    bands = {"frequency_hz": f, "above_sleeper_m_per_n": 1e-9 * ones, "midspan_m_per_n": 2e-9 * ones}
    below = [float(x) for x in f if 1200 < x < 2600]
    decay = {
        "frequency_hz": f,
        "decay_rate_dB_per_m": [0.5] * len(f),
        "limit_dB_per_m": [None if x < 240 else 0.8 for x in f],
        "below_limit_hz": below,
        "meets_limit": False,
        "limit_source": "EN ISO 3095:2013",
    }
    _print_bands(bands, decay)
    out = capsys.readouterr().out
    names = [line.split()[0] for line in out.splitlines()[2:-1]]
    assert names == ["50", "63", "80", "100", "125", "160", "200", "250", "315", "400", "500", "630", "800", "1000",
                     "1250", "1600", "2000", "2500", "3150", "4000", "5000"]  # fmt: skip
    assert "below EN ISO 3095:2013's lower limit at 1250, 1600, 2000 and 2500 Hz" in out


def test_the_lateral_decay_rate_is_tabled_beside_its_limit(capsys):
    from wheelrail.cli.commands.track import _print_bands
    from wheelrail.core.noise.decay import decay_against_limit
    from wheelrail.core.spectra.bands import noise_bands

    f = noise_bands()
    ones = np.ones(len(f))
    bands = {
        "frequency_hz": f[f < 5100],
        "above_sleeper_m_per_n": 1e-9 * ones[:21],
        "midspan_m_per_n": 2e-9 * ones[:21],
    }
    vertical = decay_against_limit(f, 9 * ones)
    lateral = decay_against_limit(f, np.where(f < 1100, 3.0, 0.3), "lateral")
    _print_bands(bands, vertical, {"decay": lateral, "receptance": {"lateral_point_m_per_n": 1e-8 * ones}})
    out = capsys.readouterr().out.splitlines()
    assert out[1].split()[-3:] == ["lateral", "decay", "limit"]
    row = {line.split()[0]: line.split() for line in out[2:-2]}
    assert row["2000"][-4:] == ["1.000e-08", "0.30", "0.50", "below"] and row["1000"][-3:] == [
        "1.000e-08",
        "3.00",
        "0.20",
    ]
    assert row["50"][-2:] == ["1.000e-08", "3.00"]  # no limit below 250 Hz
    assert out[-2] == "  the decay rate meets EN ISO 3095:2013's lower limit in every band 250 Hz-5 kHz (" + (
        "EN ISO 3095:2013, 6.2.6, Figure 3 curve A (vertical), 250 Hz-5 kHz)"
    )
    assert out[-1].startswith(
        "  the lateral decay rate is below EN ISO 3095:2013's lower limit at 1600, 2000, 2500, 3150, 4000 and 5000 "
        "Hz (EN ISO 3095:2013, 6.2.6, Figure 3 curve B (lateral)"
    )


@pytest.mark.slow
@pytest.mark.parametrize("pads_mn_m", ["10", "3000"])
def test_track_answers_at_the_ends_of_the_pad_range(pads_mn_m, cli):
    # Pads of 10, 30, 60, 90, 100, 1000 and 3000 MN/m (all accepted) ended in "could not find two
    # support resonances below 700 Hz" before anything was printed. Each resonance is reported as found or not.
    code, out, err = cli("track", "--pad-stiffness-mn-m", pads_mn_m, "--json")
    assert code == 0, err
    summary = json.loads(out)
    resonances = summary["resonances"]
    assert list(resonances) == ["sleeper_on_ballast", "rail_on_pad", "pinned_pinned"]
    for kind, entry in resonances.items():
        assert set(entry) == {"label", "frequency_hz", "band_edge_hz", "receptance", "reason"}
        assert (entry["frequency_hz"] is None) == (entry["reason"] is not None)
        assert summary["resonances_hz"][f"{kind}_hz"] == entry["frequency_hz"]
    assert resonances["pinned_pinned"]["frequency_hz"] == pytest.approx(943, rel=0.01)
    if pads_mn_m == "10":  # the soft pads' lower resonance is the rail's; the sleeper's is damped out
        assert resonances["rail_on_pad"]["frequency_hz"] == pytest.approx(65, rel=0.05)
        assert resonances["sleeper_on_ballast"]["frequency_hz"] is None
    assert summary["bands"]["band_labels"][:4] == ["50", "63", "80", "100"]
    code, text, err = cli("track", "--pad-stiffness-mn-m", pads_mn_m)  # the text, from the cache
    assert code == 0 and err == ""
    for name in ("sleeper-on-ballast", "rail-on-pad", "pinned-pinned"):
        assert f"  {name} resonance" in text
    assert " 1250   " in text and " 1259 " not in text
