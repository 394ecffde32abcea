"""Outputs never destroy inputs and never each other: one check for every command (the dispatcher's
``check_files`` of each command's ``FILES``), however a path is spelled, derived names included."""

import errno
import importlib
import os
import shutil
from pathlib import Path

import pytest

from wheelrail.cli.dispatch import COMMANDS, build_parser

SAMPLE = Path(__file__).resolve().parents[2] / "sample_data" / "corrugated-rail.npz"
OUTLINE = (
    "r_mm,z_mm\n80,-40\n110,-40\n110,-10\n280,-10\n280,-60\n320,-60\n320,60\n280,60\n280,10\n110,10\n110,40\n80,40\n"
)


def _refused(cli, argv, text):
    code, out, err = cli(*argv)
    assert code == 2, err
    assert err.startswith(f"wheelrail {argv[0]}: error:") and len(err.strip().splitlines()) == 1, err
    assert text in err, err
    return err


@pytest.fixture
def folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    Path("o1.csv").write_text(OUTLINE, encoding="utf-8")
    Path("o2_modes.csv").write_text(OUTLINE, encoding="utf-8")
    os.link("o1.csv", "hard.csv")
    Path("soft.csv").symlink_to(tmp_path / "o1.csv")
    shutil.copy(SAMPLE, "in.npz")
    os.link("in.npz", "in_hard.npz")
    return tmp_path


@pytest.mark.parametrize(
    ("outline", "csv"),
    [
        ("o1.csv", "o1.csv"),  # the same name
        ("o1.csv", "./sub/../o1.csv"),
        ("hard.csv", "o1.csv"),  # a hard link: another name, the same inode
        ("o1.csv", "soft.csv"),  # a symbolic link to the outline
        ("soft.csv", "hard.csv"),
    ],
)
def test_wheel_csv_never_replaces_its_outline(folder, cli, outline, csv):
    _refused(cli, ["wheel", "--outline", outline, "--csv", csv], "is the input file")
    assert Path("o1.csv").read_text(encoding="utf-8") == OUTLINE


def test_a_name_derived_from_an_output_never_replaces_an_input(folder, cli):
    # --csv o2.csv also writes o2_modes.csv: the outline here
    err = _refused(cli, ["wheel", "--outline", "o2_modes.csv", "--csv", "o2.csv"], "is the input file o2_modes.csv")
    assert "written beside --csv o2.csv" in err
    assert Path("o2_modes.csv").read_text(encoding="utf-8") == OUTLINE
    _refused(cli, ["wheel", "--outline", "o2_modes.csv", "--csv", f"{folder}/sub/../o2.csv"], "is the input file")


@pytest.mark.parametrize(
    "argv",
    [
        ["wheel", "--csv", "w.png", "--plot", "w_modes.png"],  # a derived name against another output
        ["wheel", "--csv", "w.png", "--plot", "./w.png"],
        ["track", "--csv", "t.png", "--plot", "t_decay.png"],
        ["filters", "--csv", "f.csv", "--plot", "sub/../f.csv"],  # refused by its suffix first
        ["run", "--set", "corrugated-rail", "--out", "r.npz", "--csv", "sub/../r.npz"],
    ],
)
def test_two_outputs_of_one_command_are_never_the_same_file(folder, cli, argv):
    code, out, err = cli(*argv)
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "name the same file" in err or "must end in" in err, err
    assert sorted(p.name for p in folder.iterdir()) == sorted(
        ["sub", "o1.csv", "o2_modes.csv", "hard.csv", "soft.csv", "in.npz", "in_hard.npz"]
    )


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "--set", "in.npz", "--rrd", "in_hard.npz"],
        ["run", "--set", "in.npz", "--out", "in_hard.npz"],
        ["run", "--set", "corrugated-rail", "--wheel-set", "in_hard.npz", "--out", "sub/../in.npz"],
        ["noise", "--run", "in.npz", "--csv", "in_hard.npz"],
        ["noise", "--run", "in.npz", "--wav", "in_hard.npz"],
        ["roughness", "--set", "in.npz", "--plot", "in_hard.npz"],
    ],
)
def test_every_command_refuses_an_output_that_is_an_input(folder, cli, argv):
    before = Path("in.npz").read_bytes()
    code, out, err = cli(*argv)
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "is the input file" in err or "must end in" in err, err
    assert Path("in.npz").read_bytes() == before


_FILE_METAVARS = ("FILE", "SET", "RESULT", ".npz", ".csv", ".png", ".wav", ".rrd")


def test_every_option_naming_a_file_is_declared_for_the_common_check():
    """A command's option that names a file it reads or writes is in its module's FILES, so that the
    dispatcher's one check covers it (a new output option cannot bypass it)."""
    for name in COMMANDS:
        module = importlib.import_module(f"wheelrail.cli.commands.{name.replace('-', '_')}")
        files = getattr(module, "FILES", None)
        declared = set() if files is None else {*files.reads, *(output.dest for output in files.writes)}
        parser = build_parser(name)
        command = next(a for a in parser._actions if a.dest == "command").choices[name]
        for action in command._actions:
            metavar = action.metavar or ""
            if any(word in metavar for word in _FILE_METAVARS):
                assert action.dest in declared, f"wheelrail {name} {action.option_strings or action.dest}"


# all or none: a full disk while writing any output leaves none, and says which file and why ------------------
def _disk_full_for(suffix, monkeypatch):
    """The run's writer of ``suffix`` files meets a full disk half-way (the real atomic_write around it)."""
    from wheelrail.core.engine import results
    from wheelrail.core.files import atomic

    def write_then_full(path, write, *args, **kwargs):
        if not str(path).endswith(suffix):
            return atomic.atomic_write(path, write, *args, **kwargs)

        def full(handle):
            handle.write(b"half" if "b" in (args[0] if args else kwargs.get("mode", "wb")) else "half")
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

        return atomic.atomic_write(path, full, *args, **kwargs)

    monkeypatch.setattr(results, "atomic_write", write_then_full)


@pytest.mark.slow  # a run
@pytest.mark.parametrize("full", [".csv", ".npz"])
def test_run_outputs_are_all_or_none_on_a_full_disk(tmp_path, cli, monkeypatch, full):
    monkeypatch.chdir(tmp_path)
    _disk_full_for(full, monkeypatch)
    code, out, err = cli("run", "--set", "corrugated-rail", "--length-m", "0.05", "--out", "r.npz", "--csv", "r.csv")
    assert code == 2, err
    assert err == f"wheelrail run: error: no space left on device writing r{full}\n"
    assert list(tmp_path.iterdir()) == []  # neither file, no temporary


@pytest.mark.slow  # a run
def test_run_outputs_with_a_recording_are_all_or_none(tmp_path, cli, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("r.rrd").write_text("an earlier recording")
    _disk_full_for(".csv", monkeypatch)
    argv = ["run", "--set", "corrugated-rail", "--length-m", "0.05", "--out", "r.npz", "--csv", "r.csv"]
    code, out, err = cli(*argv, "--rrd", "r.rrd")
    assert err == "wheelrail run: error: no space left on device writing r.csv\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.rrd"]
    assert Path("r.rrd").read_text() == "an earlier recording"  # not replaced by this run's


@pytest.mark.slow  # a run
def test_a_recording_that_meets_a_full_disk_blames_the_disk_and_leaves_nothing(tmp_path, cli, monkeypatch):
    # rerun's file writer stops on a full disk and its flush says so; here the partial file is then the full
    # device (/dev/full), where the check of why it stopped meets ENOSPC as the writer did
    from wheelrail.core.recording.outputs import Outputs

    disconnect = Outputs.disconnect

    def writer_stopped(self):
        disconnect(self)
        self._temporary.unlink()
        self._temporary.symlink_to("/dev/full")
        return "File-writer thread shut down prematurely"

    monkeypatch.setattr(Outputs, "disconnect", writer_stopped)
    monkeypatch.chdir(tmp_path)
    code, out, err = cli("run", "--set", "corrugated-rail", "--length-m", "0.05", "--rrd", "r.rrd", "--out", "r.npz")
    assert code == 2
    assert err == "wheelrail run: error: no space left on device writing r.rrd\n"  # no viewer named
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_recording_whose_first_bytes_meet_a_full_disk_is_refused_before_the_run(tmp_path, cli, monkeypatch):
    from wheelrail.core.recording import outputs

    made = outputs.partial_beside

    def on_full_device(path):
        partial = made(path)
        partial.unlink()
        partial.symlink_to("/dev/full")
        return partial

    monkeypatch.setattr(outputs, "partial_beside", on_full_device)
    monkeypatch.chdir(tmp_path)
    code, out, err = cli("run", "--set", "corrugated-rail", "--length-m", "0.05", "--rrd", "r.rrd")
    assert code == 2
    assert err == "wheelrail run: error: no space left on device writing r.rrd\n"
    assert list(tmp_path.iterdir()) == []
