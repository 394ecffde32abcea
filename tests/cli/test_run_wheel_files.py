"""`wheelrail run --wheel-model modal` writes the interaction's wheel into every file it writes: --out (.npz: the
header's ``wheel_model`` and ``wheel_profile``, read back by ``spectra``, ``noise --run`` and ``RunResult``),
--csv (the header comment) and --rrd (the parameters document, read back by ``read_recording``); a file written
before the wheel was recorded reads as the paper's 2-DOF wheel."""

import json

import pytest

from wheelrail.cli import main
from wheelrail.core.engine.results import RunHeader, RunResult
from wheelrail.core.errors import WheelrailError
from wheelrail.core.modal_wheel import profile_from_description, wheel_profile_for

# 1.5 m at 100 km/h: 54 ms, enough for a force spectrum (the summary's) after the start-up skip
MODAL_RUN = ["run", "--set", "corrugated-rail", "--length-m", "1.5", "--wheel-model", "modal"]


@pytest.fixture(scope="module")
def modal_files(tmp_path_factory):
    """One modal-wheel run written as .npz, .csv and .rrd (its modes cached: tests/conftest.py's cache)."""
    folder = tmp_path_factory.mktemp("modal")
    files = {suffix: folder / f"run.{suffix}" for suffix in ("npz", "csv", "rrd")}
    argv = [*MODAL_RUN, "--out", str(files["npz"]), "--csv", str(files["csv"]), "--rrd", str(files["rrd"])]
    assert main(argv) == 0
    return files


def test_the_npz_records_the_modal_wheel_and_its_profile(modal_files):
    header = RunResult.load_npz(modal_files["npz"]).header
    expected = wheel_profile_for(0.39)  # the paper's R: the nearest named wheel (840 mm) at R = 390 mm
    assert header.wheel_model == "modal"
    assert profile_from_description(header.wheel_profile) == expected  # the same cross-section, rebuilt
    assert "modal wheel 780 mm" in header.description()


def test_the_csv_header_names_the_modal_wheel(modal_files):
    head = modal_files["csv"].read_text().splitlines()[:2]
    assert "modal wheel 780 mm" in head[0]
    configuration = json.loads(head[1].split("configuration (SI): ", 1)[1])
    assert configuration["wheel_model"] == "modal" and configuration["wheel_profile"]["wheel_radius"] == 0.39


def test_the_recording_names_the_modal_wheel(modal_files):
    from wheelrail.core.recording import read_recording

    header = read_recording(modal_files["rrd"]).header
    assert header.wheel_model == "modal" and header.wheel_profile["kind"] == "parametric"


def test_spectra_states_the_run_s_wheel(modal_files, capsys):
    for suffix in ("npz", "rrd"):
        assert main(["spectra", str(modal_files[suffix]), "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["wheel_model"] == "modal"
    assert main(["spectra", str(modal_files["npz"])]) == 0
    assert "wheel: modal wheel 780 mm" in capsys.readouterr().out


@pytest.fixture
def coarse_noise_track(monkeypatch):
    """The noise chain's track coarse where none is given (60 bays, 8 elements per bay, 2 frequencies per band:
    tests/physics/test_noise_run.py's SMALL), for tests of what a command states rather than of its levels (the
    default track's 480 frequencies take 4-6 s)."""
    from wheelrail.core.noise import twins

    coarse = twins.NoiseNumerics(track_bays=60, elements_per_bay=8, points_per_band=2)
    full = twins.track_noise_model

    def track_noise_model(params=None, numerics=None, *args, **kwargs):
        return full(params, coarse if numerics is None else numerics, *args, **kwargs)

    monkeypatch.setattr(twins, "track_noise_model", track_noise_model)


def test_noise_of_a_modal_run_states_its_wheel(modal_files, coarse_noise_track, capsys):
    assert main(["noise", "--run", str(modal_files["npz"]), "--json"]) == 0
    run = json.loads(capsys.readouterr().out)["configuration"]["run"]
    assert run["wheel_model"] == "modal" and run["wheel_profile"]["wheel_radius"] == 0.39


def test_a_2dof_run_says_so_and_older_headers_read_as_the_2dof():
    header = RunHeader(model="hertz", line=0, roughness_name="corrugated-rail")
    values = header.to_dict()
    assert values["wheel_model"] == "2dof" and "wheel_profile" not in values
    del values["wheel_model"]  # a file written before the wheel was recorded
    assert RunHeader.from_dict(values).wheel_model == "2dof"
    assert "the paper's 2-DOF wheel" in header.description()
    with pytest.raises(WheelrailError, match="damaged"):
        RunHeader.from_dict({**values, "wheel_model": "3dof"})


def test_noise_wheel_model_needs_sound_power(capsys):
    assert main(["run", "--set", "corrugated-rail", "--noise-wheel-model", "modal"]) != 0
    err = capsys.readouterr().err
    assert "--noise-wheel-model needs --sound-power" in err and err.count("\n") == 1


@pytest.fixture
def coarse_noise_wheel(monkeypatch):
    """The noise chain's modal wheel up to 3 kHz and n = 0..4 (as tests/gui/test_explorer_wheel_tab.py): its
    radiation table, memory-cached by profile alone, emptied before and after."""
    from wheelrail.core.noise import wheel_power

    monkeypatch.setattr(wheel_power, "MAX_FREQUENCY", 3000.0)
    monkeypatch.setattr(wheel_power, "MAX_HARMONIC", 4)
    wheel_power.radiation_table.cache_clear()
    yield
    wheel_power.radiation_table.cache_clear()


def _sound_power_summary(path) -> dict:
    from rerun.chunk import RrdReader

    (chunk,) = [c for c in RrdReader(path).stream() if c.entity_path == "/spectra/sound_power/summary"]
    return json.loads(chunk.to_record_batch().column("TextDocument:text")[0].as_py()[0])


@pytest.mark.slow  # 5-10 s each: a run, its recording and its sound power (the modal wheel's chain coarse)
@pytest.mark.parametrize("noise_wheel", ["directive", "modal"])
def test_the_recorded_sound_power_states_its_wheel(noise_wheel, coarse_noise_wheel, tmp_path, capsys):
    # run --rrd F --sound-power [--noise-wheel-model modal]: the summary names whose wheel power it took
    # (wheel_transfer_source), the modal one the run's own wheel (780 mm), its wheel power differing from the
    # directive's L_H,veh (the wheel_power tests bound by how much)
    path = tmp_path / f"{noise_wheel}.rrd"
    argv = [*MODAL_RUN, "--rrd", str(path), "--sound-power", "--noise-wheel-model", noise_wheel]
    assert main(argv) == 0
    summary = _sound_power_summary(path)
    assert summary["wheel_model"] == noise_wheel
    words = "modal wheel" if noise_wheel == "modal" else "L_H,veh"
    assert words in summary["wheel_transfer_source"], summary["wheel_transfer_source"]


def test_the_sink_takes_the_declared_wheel_choice(tmp_path):
    from wheelrail.core.recording import RecordingOptions, RecordingSink

    sink = RecordingSink(rrd=tmp_path / "a.rrd", options=RecordingOptions(sound_power="modal"))
    assert sink.options.sound_power and sink.options.sound_power_wheel == "modal"
    sink.abort()
    sink = RecordingSink(rrd=tmp_path / "b.rrd", options=RecordingOptions(sound_power=True))
    assert sink.options.sound_power_wheel == "directive"  # True: the directive's L_H,veh, as before the choice
    sink.abort()
    with pytest.raises(WheelrailError, match="must be one of directive, modal"):
        RecordingSink(rrd=tmp_path / "c.rrd", options=RecordingOptions(sound_power="tabled"))
