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
    # second call: loaded from cache
    assert main(["track", "--json", "--speed-kmh", "140"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["cache"]["was_cached"] is True
    assert again["cache"]["speed_time_s"] < 1.0


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
