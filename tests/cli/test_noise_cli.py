"""``wheelrail noise --run``: what it refuses, before any computation, in its own words."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.parameters import ModelParameters

DT = 1e-3 / (100 / 3.6)  # s: 1 mm at 100 km/h


def _run_file(folder, n_steps: int):
    zeros = np.zeros(n_steps)
    t = np.arange(n_steps) * DT
    result = RunResult(
        header=RunHeader(model="hertz", line=0, roughness_name="corrugated-rail", params=ModelParameters()),
        time=t,
        x=np.arange(n_steps) * 1e-3,
        force=65e3 + 1e3 * np.sin(2 * np.pi * 1000 * t),
        xi_wheel=zeros,
        xi_rail=zeros,
        roughness=zeros,
        contact_length=np.full(n_steps, 0.011),
        contact_area=np.full(n_steps, 9.4e-5),
        equivalent_roughness=zeros,
    )
    return result.save_npz(folder / "run.npz")


def _noise(capsys, *argv):
    code = main(["noise", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_a_run_too_short_for_a_spectrum_is_refused_first_in_the_commands_words(tmp_path, capsys, monkeypatch):
    """A 0.5 m run once computed the track's transfer functions for 11 minutes, then named --skip-ms."""
    import wheelrail.core.noise.twins as twins

    def not_reached(*args, **kwargs):
        raise AssertionError("the track's transfer functions were computed for a run too short to use")

    monkeypatch.setattr(twins, "track_noise_model", not_reached)
    path = _run_file(tmp_path, 500)
    code, out, err = _noise(capsys, "--run", str(path))
    assert code != 0 and out == ""
    assert err.count("\n") == 1 and "--skip" not in err and "0.5 m" in err and "0.572 m" in err, err


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["--train-length-m", "1e300"], "--train-length-m 1e+300"),
        (["--train-length-m", "1e-300"], "--train-length-m 1e-300"),
        (["--train-axles", "40", "--train-length-m", "2.5"], "--train-axles 40"),
    ],
)
def test_impossible_trains_are_refused(tmp_path, capsys, argv, expected):
    path = _run_file(tmp_path, 2000)
    code, out, err = _noise(capsys, "--run", str(path), *argv)
    assert code != 0 and out == "" and err.count("\n") == 1 and expected in err, err


def test_csv_needs_a_run(tmp_path, capsys):
    code, out, err = _noise(capsys, "--method", "cnossos", "--csv", str(tmp_path / "x.csv"))
    assert code != 0 and err.count("\n") == 1 and "--csv: not used by --method cnossos" in err, err


def test_a_wav_longer_than_the_limit_is_refused_before_any_computation(tmp_path, capsys, monkeypatch):
    """5 km at 100 km/h: a 182 s pass-by, over a limit of 120 s (the default, 600 s, refuses 5 km at 27 km/h)."""
    import wheelrail.core.noise.twins as twins

    def not_reached(*args, **kwargs):
        raise AssertionError("the noise was computed for a WAV that is refused")

    monkeypatch.setattr(twins, "track_noise_model", not_reached)
    path = _run_file(tmp_path, 2000)
    monkeypatch.setattr("wheelrail.core.noise.wav.MAX_WAV_S", 120.0)
    code, out, err = _noise(capsys, "--run", str(path), "--train-length-m", "5000", "--wav", str(tmp_path / "p.wav"))
    assert (
        code == 2
        and out == ""
        and err
        == (
            "wheelrail noise: error: --train-length-m 5000: a WAV of this pass-by would last 182 s (5000 m at 100 km/h "
            "and 1 s before and after; 17 MB): at most 120 s are written; give a train of at most 3277 m at this speed "
            "for the WAV (the pass-by level itself needs no WAV)\n"
        )
    )
    assert not (tmp_path / "p.wav").exists()


def test_a_wav_of_too_many_wheels_is_refused_before_any_computation(tmp_path, capsys, monkeypatch):
    import wheelrail.core.noise.twins as twins

    def not_reached(*args, **kwargs):
        raise AssertionError("the noise was computed for a WAV that is refused")

    monkeypatch.setattr(twins, "track_noise_model", not_reached)
    path = _run_file(tmp_path, 2000)
    argv = ["--run", str(path), "--train-length-m", "5000", "--train-axles", "2000", "--wav", str(tmp_path / "p.wav")]
    code, out, err = _noise(capsys, *argv)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("wheelrail noise: error: --train-axles 2000: a WAV of this pass-by sums 4000 wheels'")
    assert "give at most 197 axles or a shorter train for the WAV" in err
    assert not (tmp_path / "p.wav").exists()
