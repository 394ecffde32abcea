"""Reliability through the command line: outputs never overwrite inputs, sizes bounded before any work,
clean Ctrl-C, explorer address checks, track/roughness/spectra file handling, lazy start-up."""

import json
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wheelrail.cli import EXPLORER_COMMANDS  # the `wheelrail` command: core's commands and `explore`
from wheelrail.cli.dispatch import COMMANDS

SAMPLE = Path(__file__).resolve().parents[2] / "sample_data" / "corrugated-rail.npz"


def _one_error_line(code, err, command, text):
    assert code == 2, err
    assert err.startswith(f"wheelrail {command}: error:") and len(err.strip().splitlines()) == 1
    assert text in err, err


# item 2: an output that is one of the inputs -----------------------------------------------------------------
def test_output_that_is_the_input_is_refused_in_any_spelling(tmp_path, cli, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copy(SAMPLE, "in.npz")
    os.symlink(tmp_path / "in.npz", "link.npz")
    before = Path("in.npz").read_bytes()
    for argv in (
        ["run", "--set", "in.npz", "--length-m", "0.05", "--out", "in.npz"],
        ["run", "--set", "in.npz", "--length-m", "0.05", "--out", f"{tmp_path}/./in.npz"],
        ["run", "--set", "link.npz", "--length-m", "0.05", "--out", "in.npz"],
        ["run", "--set", "in.npz", "--length-m", "0.05", "--rrd", "in.npz"],
    ):
        code, out, err = cli(*argv)
        _one_error_line(code, err, "run", "is the input file")
    Path("plot.png").symlink_to(tmp_path / "in.npz")
    code, out, err = cli("roughness", "--set", "in.npz", "--plot", "plot.png")
    _one_error_line(code, err, "roughness", "is the input file")
    assert Path("in.npz").read_bytes() == before


def test_unwritable_output_is_refused_before_the_run(tmp_path, cli):
    code, out, err = cli("run", "--set", "corrugated-rail", "--out", "/proc/x.npz")
    _one_error_line(code, err, "run", "cannot write in folder /proc")
    code, out, err = cli("run", "--set", "corrugated-rail", "--out", str(tmp_path))
    _one_error_line(code, err, "run", "must end in .npz")


# item 5: sizes ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("argv", "text"),
    [
        (["run", "--set", "cast-iron-wheel", "--length-m", "1e9"], "GiB of memory"),
        (["run", "--set", "cast-iron-wheel", "--model", "3d", "--length-m", "1e5"], "GiB of memory"),
        (
            ["run", "--set", "cast-iron-wheel", "--model", "3d", "--length-m", "1e5", "--out", "x.npz"],
            "are the pressure maps kept",
        ),
        (["run", "--set", "corrugated-rail", "--speed-kmh", "1e308"], "outside the accepted"),
        (["track", "--speed-kmh", "1e308"], "km/h"),
        (
            ["run", "--set", "corrugated-rail", "--length-m", "0.01", "--rrd", "x.rrd", "--record-every", str(10**20)],
            "exceeds the run's 10 steps",
        ),
        (["track", "--df-hz", "1e-9"], "--df-hz must be in [0.05, 100] Hz"),
    ],
)
@pytest.mark.slow
def test_sizes_are_refused_with_a_figure(argv, text, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = cli(*argv)
    _one_error_line(code, err, argv[0], text)
    assert not Path("x.npz").exists() and not Path("x.rrd").exists()


@pytest.mark.slow
def test_3d_keeps_pressure_maps_only_for_out(tmp_path, cli, monkeypatch):
    # 0.3 m of 3d after the default 0.014 m run-in (from the steady state): 0.20 MiB estimated without maps,
    # 0.92 MiB with the 300 maps kept (engine.memory.check_run_memory); a limit between the two
    monkeypatch.setenv("WHEELRAIL_MEMORY_LIMIT_GB", str(0.5 / 1024))
    argv = ["run", "--set", "corrugated-rail", "--model", "3d", "--length-m", "0.3", "--json"]
    code, out, err = cli(*argv)
    assert code == 0, err
    code, out, err = cli(*argv, "--out", str(tmp_path / "run.npz"))
    _one_error_line(code, err, "run", "are the pressure maps kept for the result")


# item 7: Ctrl-C ---------------------------------------------------------------------------------------------
_CTRL_C_CHILD = """
import signal, sys
from wheelrail.cli.dispatch import main
from wheelrail.core.engine.run import InteractionRun

advance = InteractionRun._advance_to  # the steps up to a chunk's end (3d: in compiled code)
said = []

def advance_and_say(self, *args, **kwargs):
    if not said:
        said.append(1)
        print("stepping", flush=True)
    return advance(self, *args, **kwargs)

InteractionRun._advance_to = advance_and_say
signal.signal(signal.SIGINT, signal.default_int_handler)
sys.exit(main(["run", "--set", "cast-iron-wheel", "--model", "3d", "--length-m", "50", "--json"]))
"""


@pytest.mark.slow
def test_ctrl_c_during_a_3d_run_is_interrupted_130():
    child = subprocess.Popen(
        [sys.executable, "-c", _CTRL_C_CHILD], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert child.stdout.readline().strip() == "stepping"  # the run is inside its step loop
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=120)
    assert child.returncode == 130, err
    assert err.strip() == "wheelrail run: interrupted"


def test_interrupt_turned_into_systemerror_by_compiled_code_is_reported_as_interrupted(cli, monkeypatch):
    # what numba does when Ctrl-C arrives while it calls back into Python
    from wheelrail.cli.commands import datasets

    def interrupted(args):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as error:
            raise SystemError(
                "CPUDispatcher(<function _active_set_solve>) returned a result with an exception set"
            ) from error

    monkeypatch.setattr(datasets, "run", interrupted)
    code, out, err = cli("datasets")
    assert code == 130 and err == "wheelrail datasets: interrupted\n"


# item 8: explorer address -----------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("argv", "text"),
    [
        (["--port", "-1"], "--port must be in 1..65535"),
        (["--port", "70000"], "--port must be in 1..65535"),
        (["--host", "999.1.1.1"], "is not an address"),
        (["--host", "192.0.2.1"], "cannot listen on 192.0.2.1"),
    ],
)
def test_explore_refuses_bad_addresses_before_starting(argv, text, cli):
    code, out, err = cli("explore", *argv)
    _one_error_line(code, err, "explore", text)


# item 9: track, roughness, spectra files --------------------------------------------------------------------
@pytest.mark.slow
def test_track_plot_must_be_png_and_files_are_written_atomically(tmp_path, cli):
    for name in ("r.txt", "rplot"):
        code, out, err = cli("track", "--plot", str(tmp_path / name))
        _one_error_line(code, err, "track", "must end in .png")
    csv_path, png = tmp_path / "r.csv", tmp_path / "r.png"
    code, out, err = cli("track", "--df-hz", "100", "--csv", str(csv_path), "--plot", str(png), "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["plot"] == str(png) and png.read_bytes()[:4] == b"\x89PNG"
    assert csv_path.read_text().startswith("frequency_hz,")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.png", "r_decay.csv"]  # no temporary left


@pytest.mark.parametrize("damage", ["metadata", "two_d_force", "nan_force", "short_time"])
def test_spectra_refuses_hand_made_run_files_in_one_line(damage, tmp_path, cli):
    from tests.cli.test_spectra_cli import _result

    path = _result(n=2000).save_npz(tmp_path / "run.npz")
    with np.load(path) as data:
        arrays = {name: data[name] for name in data.files}
    if damage == "metadata":
        arrays["metadata"] = np.array("[1, 2]")
    elif damage == "two_d_force":
        arrays["force"] = np.zeros((2, 1000))
    elif damage == "nan_force":
        arrays["force"] = arrays["force"].copy()
        arrays["force"][5] = np.nan
    else:
        arrays["time"] = arrays["time"][:10]
    np.savez(tmp_path / "hand.npz", **arrays)
    code, out, err = cli("spectra", str(tmp_path / "hand.npz"))
    _one_error_line(code, err, "spectra", "cannot read run file")


@pytest.mark.slow
def test_edge_of_window_advice_names_what_the_cli_can_change(cli, tmp_path):
    import dataclasses

    from wheelrail.core.roughness import load_roughness, write_csv

    rail = load_roughness("corrugated-rail")
    write_csv(dataclasses.replace(rail, heights=rail.heights * 200), tmp_path / "rough.csv")  # up to 8 mm
    code, out, err = cli("run", "--set", str(tmp_path / "rough.csv"), "--model", "hertz-winkler", "--length-m", "0.1")
    _one_error_line(code, err, "run", "--model hertz-winkler: the bedding contact reaches the end of its window")
    assert err.rstrip().endswith("use a smoother line or set, or the hertz model")
    assert "half_window" not in err  # a keyword argument the CLI does not have


# item 11: start-up ------------------------------------------------------------------------------------------
def test_help_imports_no_command_module_and_lists_each_modules_help(python_probe):
    probe = (
        "import sys, io, contextlib\nfrom wheelrail.cli.dispatch import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try:\n        main(['--help'])\n    except SystemExit:\n        pass\n"
        "print(sorted(m for m in sys.modules if m.startswith(('wheelrail.cli.commands.', 'numpy', 'scipy'))))"
    )
    loaded = python_probe(probe)
    assert loaded.strip() == "[]"
    import argparse
    import importlib

    modules = {name: (text, f"wheelrail.cli.commands.{name}") for name, text in COMMANDS.items()}
    for name, (help_text, module) in {**modules, **EXPLORER_COMMANDS}.items():
        sub = argparse.ArgumentParser().add_subparsers()
        importlib.import_module(module).add_parser(sub)
        assert sub._choices_actions[0].help == help_text, name
