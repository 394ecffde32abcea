"""The command line's figures and noise text name what they show: ``track --plot`` its track and the bands below
the limit, ``wheel --plot`` its wheel, ``noise --run`` the run's track (core's ``describe_track``,
``describe_wheel``, ``decay_verdict``)."""

from __future__ import annotations

import pytest

from wheelrail.cli import main
from wheelrail.cli.commands import track as track_command
from wheelrail.cli.commands import wheel as wheel_command


def _spy(monkeypatch, module, name: str) -> list:
    """Keep each figure that ``module.name`` makes (the command still writes it)."""
    made, original = [], getattr(module, name)

    def keep(*args, **kwargs):
        made.append(original(*args, **kwargs))
        return made[-1]

    monkeypatch.setattr(module, name, keep)
    return made


@pytest.mark.slow  # the track's Green's functions and decay rate (cached) and its receptances: 10-60 s
def test_the_track_plot_names_the_track_and_the_bands_below_the_limit(tmp_path, monkeypatch, capsys):
    made = _spy(monkeypatch, track_command, "track_figure")
    assert main(["track", "--plot", str(tmp_path / "t.png"), "--df-hz", "50"]) == 0
    out = capsys.readouterr().out
    # the paper's track is below the limit at 400-800 Hz and 2.5 kHz (tests/gui/test_explorer_server.py)
    verdict = "is below EN ISO 3095:2013's lower limit at 400, 500, 630, 800 and 2500 Hz"
    assert f"  the decay rate {verdict} (EN ISO 3095:2013" in out
    (figure,) = made
    assert figure._suptitle.get_text() == "wheelrail track: the paper's track"
    assert figure.axes[3].get_title().replace("\n", " ") == f"Vertical track decay rate: it {verdict}"
    assert (tmp_path / "t.png").stat().st_size > 10_000


def test_the_wheel_plot_names_the_wheel(tmp_path, monkeypatch, capsys):
    made = _spy(monkeypatch, wheel_command, "wheel_figure")
    argv = ["wheel", "--wheel", "wheel_640", "--web-thickness-mm", "30", "--max-frequency-hz", "1500"]
    assert main([*argv, "--max-harmonic", "2", "--plot", str(tmp_path / "w.png")]) == 0
    (figure,) = made
    assert figure._suptitle.get_text().startswith(
        "wheelrail wheel: wheel wheel_640, diameter 640 mm, web thickness 30 mm; bore clamped; "
    )


@pytest.fixture
def coarse_noise_track(monkeypatch):
    """The noise chain's track coarse where none is given (as tests/cli/test_run_wheel_files.py): this test reads
    what the command states, not its levels."""
    from wheelrail.core.noise import twins

    coarse = twins.NoiseNumerics(track_bays=60, elements_per_bay=8, points_per_band=2)
    full = twins.track_noise_model

    def track_noise_model(params=None, numerics=None, *args, **kwargs):
        return full(params, coarse if numerics is None else numerics, *args, **kwargs)

    monkeypatch.setattr(twins, "track_noise_model", track_noise_model)


@pytest.mark.slow  # a 1.5 m run and its noise on a coarse track: 10-30 s
def test_the_noise_of_a_run_names_its_track(tmp_path, coarse_noise_track, capsys):
    run = tmp_path / "r.npz"
    assert main(["run", "--set", "corrugated-rail", "--model", "hertz", "--length-m", "1.5", "--out", str(run)]) == 0
    capsys.readouterr()
    assert main(["noise", "--run", str(run)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "  track (its force and the rail's and sleepers' sound): the paper's track" in lines


def test_the_track_studys_text_states_what_the_tracks_share(monkeypatch, capsys, tmp_path):
    """``study track`` with a swept input: each track by its swept values, then what every track shares (not the
    first track's values for all of them)."""
    from types import SimpleNamespace

    from wheelrail.core import study

    summary = {"wheel_set": None, "sets": ["corrugated-rail"], "runs": 10, "runs_computed": 10, "runs_cached": 0,
               "wall_time_s": 1.0, "backend": "test", "loss_of_contact_steps": 0, "spectrum_records": [],
               "files": []}  # fmt: skip
    monkeypatch.setattr(study, "run_study", lambda *args, **kwargs: SimpleNamespace(summary=summary, tables=[]))
    argv = ["study", "track", "--set", "corrugated-rail", "--out", str(tmp_path), "--sleeper-mass-kg", "150"]
    assert main([*argv, "--pad-stiffness-mn-m", "60", "120"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[1:4] == [
        "  track 1: pad stiffness 60 MN/m",
        "  track 2: pad stiffness 120 MN/m",
        "  every track with sleeper mass 150 kg, else the paper's but for its pad stiffness",
    ]
