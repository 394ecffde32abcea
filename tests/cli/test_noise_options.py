"""``wheelrail noise`` refuses every option its mode does not use, even an invalid one (they were ignored: exit 0)."""

from __future__ import annotations

import pytest

from wheelrail.cli.dispatch import main


@pytest.mark.parametrize(
    ("argv", "wording"),
    [
        (["--method", "twins", "--preload-kn", "nan"], "--preload-kn: not used by --method twins"),
        (
            ["--method", "twins", "--speed-kmh", "80", "--axles", "2"],
            "--speed-kmh, --axles: not used by --method twins",
        ),
        (["--method", "cnossos", "--train-axles", "5"], "--train-axles: not used by --method cnossos"),
        (["--method", "cnossos", "--pad-stiffness-mn-m", "60"], "--pad-stiffness-mn-m: not used by --method cnossos"),
        (["--method", "cnossos", "--wav", "x.wav"], "--wav: not used by --method cnossos"),
        (["--run", "r.npz", "--track-type", "wooden"], "--track-type: not used by --run"),
        (["--run", "r.npz", "--speed-kmh", "100"], "--speed-kmh: not used by --run"),
        (["--run", "r.npz", "--rail-loss-factor", "0.02"], "--rail-loss-factor: not used by --run"),
    ],
)
def test_an_option_the_mode_does_not_use_is_refused_naming_the_mode(argv, wording, capsys):
    assert main(["noise", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith(f"wheelrail noise: error: {wording}"), err


def test_the_options_a_mode_uses_are_checked_before_use(capsys):
    assert main(["noise", "--method", "cnossos", "--preload-kn", "nan"]) == 2
    assert "--preload-kn" in capsys.readouterr().err
    assert main(["noise", "--method", "twins", "--pad-stiffness-mn-m", "0"]) == 2
    assert "--pad-stiffness-mn-m 0 is outside the accepted 10 to 3000 MN/m" in capsys.readouterr().err
