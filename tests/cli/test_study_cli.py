"""`wheelrail study` and the study runner: files written, resume from cached runs, Dask = process pool, errors."""

import json
import warnings

import numpy as np
import pytest

from wheelrail.cli.dispatch import main
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.roughness import load_roughness, write_csv
from wheelrail.core.study import (
    STUDIES,
    RunSpec,
    execute,
    plan_study,
    roughness_digest,
    run_study,
    study_roughness,
    study_wheel_roughness,
)
from wheelrail.core.study import execution as study_execution
from wheelrail.core.study.store import cache_path


def _run_json(argv, capsys):
    code = main(argv)
    captured = capsys.readouterr()
    assert code == 0, captured.err
    return json.loads(captured.out)


@pytest.mark.slow
def test_filters_writes_tables_figure_and_summary_then_resumes(tmp_path, capsys):
    out = tmp_path / "filters"
    argv = ["study", "filters", "--set", "sinter-wheel-1", "--out", str(out), "--length-m", "0.8", "--json"]
    summary = _run_json(argv, capsys)
    assert summary["study"] == "filters" and summary["sets"] == ["sinter-wheel-1"]
    assert summary["runs"] == 29 and summary["runs_computed"] == 29 and summary["runs_cached"] == 0
    assert summary["speed_m_per_s"] == pytest.approx(100 / 3.6)
    # one CSV per figure table: band centres in Hz, one column per model in dB
    levels = out / "fig10_sinter-wheel-1_force_levels.csv"
    filters = out / "fig10_sinter-wheel-1_contact_filters.csv"
    header = levels.read_text().splitlines()[0].split(",")
    assert header == ["band", "centre_hz", "3d_db", "2d_db", "hertz_db", "hertz_winkler_db", "hertz_average_db"]
    assert filters.read_text().splitlines()[0].split(",") == [
        "band",
        "centre_hz",
        "3d_db",
        "2d_db",
        "hertz_winkler_db",
        "hertz_average_db",
        "ref_cnossos_db",
        "ref_averaging_db",
        "ref_patch_correlated_db",
        "ref_patch_incoherent_db",
    ]
    data = np.genfromtxt(filters, delimiter=",", names=True)
    # nominal names in "band", exact centres (6 significant digits) in "centre_hz"
    assert filters.read_text().splitlines()[1].startswith("50,50.1187,")
    assert data["centre_hz"][0] == pytest.approx(50.1187, abs=1e-4) and data["centre_hz"][-1] == pytest.approx(
        7943.28, abs=0.01
    )
    # the 2D filter is L_2D - L_hertz: small (|.| < 1 dB) where the wavelength is long (< 700 Hz: > 4 cm)
    # and strongly negative at 8 kHz (3.5 mm waves fill the contact: measured about -20 dB); 0.8 m leave 8.8 ms
    # after the 20 ms start-up, which resolve the bands at least 1 / 8.8 ms = 114 Hz wide: from 500 Hz up
    low = np.isfinite(data["2d_db"]) & (data["centre_hz"] < 700)
    assert low.sum() == 2 and np.all(np.abs(data["2d_db"][low]) < 1.0)
    assert data["2d_db"][-1] < -10.0
    png = out / "fig10_filters.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    saved = json.loads((out / "filters_summary.json").read_text())
    assert (
        saved["tables"]["fig10_sinter-wheel-1_contact_filters"]["2d_db"]
        == summary["tables"]["fig10_sinter-wheel-1_contact_filters"]["2d_db"]
    )
    assert len(list((out / "runs").glob("run-*.npz"))) == 29
    # the same study again: every run comes from the cache, the tables are identical
    again = _run_json(argv, capsys)
    assert again["runs_computed"] == 0 and again["runs_cached"] == 29
    assert again["tables"] == summary["tables"]


@pytest.mark.slow
def test_interrupted_study_recomputes_only_missing_runs(tmp_path):
    # an interrupted study = some runs cached, some not (each finished run is written at once); also a
    # half-written temporary file and a truncated entry, as a kill during a write could leave them
    plan = plan_study("filters", ["cast-iron-wheel"], length=0.8)
    cache = tmp_path / "runs"
    first = execute(plan.specs[:11], cache=cache, workers=2, progress=False)
    assert first.computed == 11 and first.cached == 0
    (cache / "run-0123456789abcdef.npz.x1.tmp").write_bytes(b"partial")
    victim = sorted(cache.glob("run-*.npz"))[0]
    victim.write_bytes(victim.read_bytes()[:100])
    with pytest.warns(UserWarning, match="unusable study run file .*BadZipFile"):
        result = run_study("filters", ["cast-iron-wheel"], tmp_path, length=0.8, progress=False, figures=False)
    assert result.report.cached == 10  # the truncated one is not trusted
    assert result.report.computed == 29 - 10


@pytest.fixture(scope="module")
def stored_run(tmp_path_factory):
    """One short run (1 m at 100 km/h: its 50 Hz band is legitimately NaN) and the bytes of its run file."""
    wheel = load_roughness("sinter-wheel-1")
    spec = RunSpec(
        source="sinter-wheel-1", set_label="w", set_digest=roughness_digest(wheel), model="hertz", length=1.0
    )
    cache = tmp_path_factory.mktemp("runs")
    report = execute([spec], cache=cache, workers=1, progress=False)
    summary = report.summaries[spec.key]
    assert np.isnan(summary.levels[0]) and np.isfinite(summary.levels[-1])
    return spec, summary, cache_path(cache, spec.key).read_bytes()


def _damage_zip_byte(raw: bytes, offset: int, value: int) -> bytes:
    """Set one byte of the first entry of the ZIP's central directory (offset from its signature)."""
    at = raw.index(b"PK\x01\x02") + offset
    return raw[:at] + bytes([value]) + raw[at + 1 :]


def _change_arrays(raw: bytes, change) -> bytes:
    import io

    with np.load(io.BytesIO(raw)) as data:
        arrays = {name: data[name] for name in data.files}
    change(arrays)
    out = io.BytesIO()
    np.savez(out, **arrays)
    return out.getvalue()


def _set(name, value):
    def change(arrays):
        arrays[name] = value(arrays[name])

    return change


def test_an_intact_run_file_is_used(stored_run, tmp_path):
    spec, summary, raw = stored_run
    cache_path(tmp_path, spec.key).write_bytes(raw)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        report = execute([spec], cache=tmp_path, workers=1, progress=False)
    assert report.cached == 1 and report.computed == 0
    np.testing.assert_array_equal(report.summaries[spec.key].levels, summary.levels)


@pytest.mark.parametrize(
    "damage",
    [
        # one byte of the ZIP: zipfile raised RuntimeError (encrypted) / NotImplementedError on every later run
        lambda raw: _damage_zip_byte(raw, 8, 0x01),  # general-purpose flag: "encrypted"
        lambda raw: _damage_zip_byte(raw, 10, 99),  # compression method
        lambda raw: _damage_zip_byte(raw, 6, 99),  # version needed to extract
        # readable, but not this run's summary
        lambda raw: _change_arrays(raw, _set("levels_db", lambda v: v[:-1])),
        lambda raw: _change_arrays(raw, _set("band_centres_hz", lambda v: np.stack([v, v]))),
        lambda raw: _change_arrays(raw, _set("levels_db", lambda v: np.append(v[:-1], np.nan))),
        lambda raw: _change_arrays(raw, _set("levels_db", lambda v: np.nan_to_num(v, nan=60.0))),
        lambda raw: _change_arrays(raw, _set("force_mean", lambda v: np.array(np.nan))),
        lambda raw: _change_arrays(raw, _set("n_steps", lambda v: np.array([v, v]))),
        lambda raw: _change_arrays(raw, lambda arrays: arrays.pop("force_std")),
    ],
    ids=[
        "zip-flag",
        "zip-method",
        "zip-version",
        "short-levels",
        "2d-centres",
        "nan-level",
        "level-in-nan-band",
        "nan-force",
        "array-step-count",
        "missing-array",
    ],
)
def test_a_damaged_run_file_is_recomputed_with_a_warning(stored_run, tmp_path, damage):
    spec, summary, raw = stored_run
    path = cache_path(tmp_path, spec.key)
    path.write_bytes(damage(raw))
    with pytest.warns(UserWarning, match="unusable study run file"):
        report = execute([spec], cache=tmp_path, workers=1, progress=False)
    assert report.cached == 0 and report.computed == 1
    # the same run again, deterministic: equal to the bit, and its file replaced by a good one
    np.testing.assert_array_equal(report.summaries[spec.key].levels, summary.levels)
    assert execute([spec], cache=tmp_path, workers=1, progress=False).cached == 1


def test_run_keys_hash_the_full_spec():
    rail = load_roughness("corrugated-rail")
    digest = roughness_digest(rail)
    base = RunSpec(source="corrugated-rail", set_label="a", set_digest=digest, model="2d", line=1, length=1.0)
    same = RunSpec(source=rail, set_label="b", set_digest=digest, model="2d", line=1, length=1.0)
    assert base.key == same.key  # where the set came from and its label do not change the result
    changed = rail.with_heights(rail.heights * 1.001)
    others = [
        RunSpec(source=changed, set_label="a", set_digest=roughness_digest(changed), model="2d", line=1, length=1.0),
        RunSpec(source=rail, set_label="a", set_digest=digest, model="2d", line=2, length=1.0),
        RunSpec(source=rail, set_label="a", set_digest=digest, model="2d", line=1, length=1.1),
        RunSpec(source=rail, set_label="a", set_digest=digest, model="hertz", line=1, length=1.0),
        RunSpec(
            source=rail,
            set_label="a",
            set_digest=digest,
            model="2d",
            line=1,
            length=1.0,
            averaged_lines=(-3, -2, -1, 0, 1, 2, 3),
        ),
        RunSpec(
            source=rail,
            set_label="a",
            set_digest=digest,
            model="2d",
            line=1,
            length=1.0,
            params=plan_study("speeds", [rail]).specs[0].params,
        ),
    ]
    keys = {base.key} | {spec.key for spec in others}
    assert len(keys) == 1 + len(others)


def test_study_inputs_averaged_and_reduced_lateral_resolution():
    wheel = load_roughness("cast-iron-wheel")
    digest = roughness_digest(wheel)
    averaged, line = study_roughness(
        RunSpec(source=wheel, set_label="w", set_digest=digest, model="2d", averaged_lines=range(-3, 4))
    )
    assert line == 0 and averaged.n_lines == 1
    np.testing.assert_allclose(
        averaged.line(0), wheel.heights[wheel.centre_row - 3 : wheel.centre_row + 4].mean(axis=0)
    )
    # Fig. 17, 4 mm: the paper's lines -4, -2, 0, 2, 4 of 2 mm spacing are this set's own lines (exact copies)
    low, _ = study_roughness(
        RunSpec(source=wheel, set_label="w", set_digest=digest, model="3d", lateral_lines_mm=(-8, -4, 0, 4, 8))
    )
    np.testing.assert_allclose(low.y, np.array([-8, -4, 0, 4, 8]) * 1e-3)
    np.testing.assert_array_equal(low.heights, wheel.heights[[wheel.row_of_line(n) for n in (-4, -2, 0, 2, 4)]])
    # lines between measured ones are interpolated linearly across the track
    odd, _ = study_roughness(
        RunSpec(source=wheel, set_label="w", set_digest=digest, model="3d", lateral_lines_mm=(-1, 1))
    )
    np.testing.assert_allclose(odd.heights[1], 0.5 * (wheel.line(0) + wheel.line(1)), atol=1e-15)


def test_study_wheel_set_is_taken_at_the_rail_sets_lateral_positions():
    # corrugated-rail lines are 1 mm apart, sinter-wheel-1's 2 mm: the wheel under rail line n (y = n mm) is
    # the wheel between its lines, not its own line n (at 2n mm). Linear interpolation across, as the runs do.
    rail, wheel = load_roughness("corrugated-rail"), load_roughness("sinter-wheel-1")
    own_wheel = ContactParameters(wheel_radius=0.4615)  # the bundled wheel sets are 2.900 m round
    plan = plan_study(
        "averaged-input",
        ["corrugated-rail"],
        length=0.6,
        wheel_set="sinter-wheel-1",
        params=ModelParameters(contact=own_wheel),
    )
    averaged = next(spec for spec in plan.specs if spec.averaged_lines)
    assert averaged.averaged_lines == tuple(range(-3, 4))
    mean = study_wheel_roughness(averaged)
    at_rail = [
        0.5 * (wheel.line(n // 2) + wheel.line(n // 2 + 1)) if n % 2 else wheel.line(n // 2) for n in range(-3, 4)
    ]
    np.testing.assert_allclose(mean.line(0), np.mean(at_rail, axis=0), rtol=0, atol=1e-15)
    # Fig. 17's lines at -8, -4, 0, 4, 8 mm of the rail: the wheel's lines -4, -2, 0, 2, 4 (2 mm apart)
    fig17 = plan_study(
        "lateral-resolution",
        ["corrugated-rail"],
        length=0.6,
        wheel_set="sinter-wheel-1",
        params=ModelParameters(contact=own_wheel),
    )
    low = next(spec for spec in fig17.specs if spec.lateral_lines_mm == (-8, -4, 0, 4, 8))
    taken = study_wheel_roughness(low)
    np.testing.assert_allclose(taken.y, study_roughness(low)[0].y)
    np.testing.assert_array_equal(taken.heights, wheel.heights[[wheel.row_of_line(n) for n in (-4, -2, 0, 2, 4)]])
    assert rail.y[rail.centre_row] == 0.0 and wheel.y[wheel.centre_row] == 0.0
    # a wheel set with no data under the paper's lines -3..3 (its lines 8..10: 16 .. 20 mm) blames the wheel set
    from wheelrail.cli.commands._common import CLI_NAMES
    from wheelrail.core.errors import WheelrailError

    rows = [wheel.row_of_line(n) for n in (8, 9, 10)]
    aside = wheel.with_heights(wheel.heights[rows], y=wheel.y[rows])
    with pytest.raises(WheelrailError) as info:
        plan_study(
            "speeds", ["corrugated-rail"], length=0.6, wheel_set=aside, params=ModelParameters(contact=own_wheel)
        )
    assert info.value.parameter == "wheel_set"
    assert info.value.render(CLI_NAMES).startswith(
        "--wheel-set SYNTHETIC-wheel-roughness-sinter-wheel: no data at the lateral positions of corrugated-rail's "
        "lines -3 to 3; its data span 16 .. 20 mm (the wheel set is paired with the rail set by lateral position)"
    )


@pytest.mark.slow
def test_dask_cluster_gives_the_same_tables_as_the_process_pool_and_threads(tmp_path):
    distributed = pytest.importorskip("distributed")
    common = {"length": 0.6, "progress": False, "figures": False}
    plan = plan_study("averaged-input", ["sinter-wheel-1"], length=0.6)
    on_processes = execute(plan.specs, cache=tmp_path / "pool", workers=2, progress=False, backend="processes")
    threads = run_study("averaged-input", ["sinter-wheel-1"], tmp_path / "threads", **common)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        dask = run_study(
            "averaged-input",
            ["sinter-wheel-1"],
            tmp_path / "dask",
            length=0.6,
            progress=False,
            figures=False,
            dask_address=cluster.scheduler_address,
        )
    assert dask.report.backend.startswith("dask") and dask.report.computed == 2
    assert on_processes.backend.startswith("process pool") and on_processes.computed == 2
    assert threads.report.backend.startswith(("threads", "forked")) and threads.report.computed == 2
    pool_tables = plan.tabulate(on_processes.summaries)
    for a, b in zip(pool_tables, threads.tables, strict=True):
        for column in a.columns:
            # the same code in processes and threads, equal to rounding (1e-9 dB): on a fresh machine a process that
            # compiled the kernels itself and one that loaded them from numba's cache differ ~1e-12 relative
            np.testing.assert_allclose(a.columns[column], b.columns[column], atol=1e-9, equal_nan=True)
    for a, b in zip(pool_tables, dask.tables, strict=True):
        assert a.name == b.name and list(a.columns) == list(b.columns)
        for column in a.columns:
            # the runs are deterministic (same code, inputs and machine): equal to rounding, 1e-9 dB
            np.testing.assert_allclose(a.columns[column], b.columns[column], atol=1e-9, equal_nan=True)


@pytest.mark.slow
def test_user_csv_set_and_human_output(tmp_path, capsys):
    wheel = load_roughness("sinter-wheel-2")
    path = tmp_path / "my wheel.csv"
    write_csv(wheel, path)
    code = main(
        [
            "study",
            "averaged-input",
            "--set",
            str(path),
            "--set",
            "cast-iron-wheel",
            "--out",
            str(tmp_path / "o"),
            "--length-m",
            "0.6",
            "--workers",
            "1",
        ]
    )
    text = capsys.readouterr().out
    assert code == 0
    assert "4 runs (4 computed, 0 from" in text and "in-process" in text
    # what the force spectra analysed: 0.6 m at 100 km/h leaves 1.6 ms after the 20 ms start-up, 1 / T = 620 Hz
    assert "force spectrum of 1.584 ms (44 steps) after the first 20.02 ms (start-up, left out): bands 3150-8000" in (
        text
    )
    # the contact geometry as run and filters state it: the radii in use (unset: the paper's R) and the patch
    assert "contact geometry: wheel radius 390 mm (the paper's R), rail crown radius 390 mm (the paper's R)" in text
    assert "Hertz patch at 65 kN a = 5.48 mm along, b = 5.48 mm across" in text
    header = (tmp_path / "o" / "fig16_3d_minus_2d_averaged_input.csv").read_text().splitlines()[0]
    assert header == "band,centre_hz,my-wheel_db,cast-iron-wheel_db"
    assert (tmp_path / "o" / "fig16_averaged-input.png").exists()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["study", "bogus", "--set", "corrugated-rail"], "unknown study 'bogus'"),
        (["study", "filters", "--set", "no-such-set"], "unknown roughness set 'no-such-set'"),
        (["study", "filters", "--set", "corrugated-rail", "--dask", "not an address"], "not a scheduler address"),
        (["study", "filters", "--set", "corrugated-rail", "--dask", "tcp://127.0.0.1:99999"], "not a scheduler"),
        (["study", "filters", "--set", "corrugated-rail", "--workers", "0"], "--workers must be at least 1"),
        (["study", "filters", "--set", "corrugated-rail", "--speed-kmh", "-5"], "--speed-kmh -5 is outside"),
        (["study", "filters", "--set", "corrugated-rail", "--length-m", "99"], "--length-m 99: longer than the rail"),
        (
            ["study", "speeds", "--set", "corrugated-rail", "--length-m", "0.5"],
            "--length-m 0.5: too short for a force spectrum at 100 km/h",
        ),
    ],
)
def test_bad_input_is_one_line_on_stderr(argv, message, tmp_path, capsys):
    code = main([*argv, "--out", str(tmp_path / "o")])
    captured = capsys.readouterr()
    assert code != 0 and captured.out == ""
    assert captured.err.count("\n") == 1 and message in captured.err, captured.err


@pytest.mark.parametrize("workers", ["2", "1"])
def test_dask_and_workers_exclude_each_other(workers, tmp_path, capsys):
    # `--workers 2` (the default value) used to slip through argparse's exclusive group
    with pytest.raises(SystemExit) as stopped:
        main(
            [
                "study",
                "filters",
                "--set",
                "corrugated-rail",
                "--out",
                str(tmp_path),
                "--dask",
                "tcp://127.0.0.1:8786",
                "--workers",
                workers,
            ]
        )
    err = capsys.readouterr().err
    assert stopped.value.code == 2 and err.count("\n") == 1
    assert "argument --workers: not allowed with argument --dask" in err, err


def test_unwritable_output_folder(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    for out in (blocker, blocker / "sub"):
        code = main(["study", "filters", "--set", "corrugated-rail", "--out", str(out)])
        err = capsys.readouterr().err
        assert code != 0 and err.count("\n") == 1 and str(out) in err, err


@pytest.mark.slow
def test_unreachable_dask_scheduler(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(study_execution, "DASK_CONNECT_TIMEOUT", "1s")
    code = main(
        [
            "study",
            "speeds",
            "--set",
            "corrugated-rail",
            "--out",
            str(tmp_path),
            "--length-m",
            "1.5",
            "--dask",
            "tcp://127.0.0.1:9",
        ]
    )
    err = capsys.readouterr().err
    assert code != 0 and err.count("\n") == 1 and "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in err, err


def test_every_named_study_is_known_to_the_cli(capsys):
    with pytest.raises(SystemExit):
        main(["study", "--help"])
    text = capsys.readouterr().out
    for name in STUDIES:
        assert name in text


@pytest.mark.slow
def test_explorer_does_not_load_the_study_package(python_probe):
    # the explorer's contact filters come from core.spectra; importing the study package would load the
    # process-pool and Dask machinery into the GUI for nothing
    code = (
        "import sys, wheelrail.explorer.app; "
        "print(sorted(m for m in sys.modules if m.startswith('wheelrail.core.study')))"
    )
    out = python_probe(code)
    assert out.strip() == "[]", out


@pytest.mark.slow
def test_study_on_an_elliptic_patch(tmp_path, capsys):
    """The study's runs take the contact geometry; its summary carries it; the reference filters
    follow Hertz's semi-axis a along the rail (6.20 mm for a 0.46 m wheel on a 0.30 m crown)."""
    argv = [
        "study",
        "filters",
        "--set",
        "sinter-wheel-1",
        "--out",
        str(tmp_path),
        "--length-m",
        "0.6",
        "--json",
        "--workers",
        "1",
        "--wheel-radius-mm",
        "460",
        "--rail-crown-radius-mm",
        "300",
    ]
    summary = _run_json(argv, capsys)
    contact = summary["contact"]
    assert contact["wheel_radius"] == pytest.approx(0.46) and contact["rail_crown_radius"] == pytest.approx(0.30)
    from wheelrail.core.parameters import ContactParameters
    from wheelrail.core.reference_filters import reference_filters

    ellipse = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30)
    refs = reference_filters(65e3, 0.46, 100 / 3.6, contact=ellipse)
    table = summary["tables"]["fig10_sinter-wheel-1_contact_filters"]
    expected = [
        None if not np.isfinite(v) else pytest.approx(round(float(v), 3), abs=1e-3)
        for v in refs.by_frequency["averaging"]
    ]
    assert table["ref_averaging_db"] == expected


@pytest.mark.slow
def test_study_with_a_wheel_set_runs_the_combined_roughness_and_names_it(tmp_path, capsys):
    """`wheelrail study --wheel-set`: every run adds the wheel set (its label and digest in the run key,
    so cached runs of the rail alone are never reused), the summary names it, a run's spectrum is that of
    simulate(..., wheel_roughness=...)."""
    from wheelrail.core.engine import simulate
    from wheelrail.core.parameters import ContactParameters, ModelParameters
    from wheelrail.core.spectra.force import force_spectrum

    out = tmp_path / "speeds"
    base = [
        "study",
        "speeds",
        "--set",
        "corrugated-rail",
        "--out",
        str(out),
        "--length-m",
        "1.2",
        "--workers",
        "1",
        "--json",
    ]
    rail_only = _run_json(base, capsys)
    assert rail_only["wheel_set"] is None and rail_only["runs_computed"] == 5
    # the bundled wheel sets are 2.900 m round: a wheel of 461.5 mm (ranges.check_wheel_circumference)
    combined = _run_json([*base, "--wheel-set", "sinter-wheel-1", "--wheel-radius-mm", "461.5"], capsys)
    assert combined["wheel_set"] == "sinter-wheel-1" and combined["sets"] == ["corrugated-rail"]
    assert combined["runs_computed"] == 5 and combined["runs_cached"] == 0  # other keys than the rail alone
    assert len(list((out / "runs").glob("run-*.npz"))) == 10
    plain = plan_study("speeds", ["corrugated-rail"], length=1.2)
    plan = plan_study(
        "speeds",
        ["corrugated-rail"],
        length=1.2,
        wheel_set="sinter-wheel-1",
        params=ModelParameters(contact=ContactParameters(wheel_radius=0.4615)),
    )
    assert "wheel_set" not in plain.specs[0].description()  # runs without a wheel set keep their keys
    assert plan.specs[0].description()["wheel_set"] == {
        "label": "sinter-wheel-1",
        "digest": roughness_digest(load_roughness("sinter-wheel-1")),
    }
    assert plan.specs[0].label().startswith("2d on corrugated-rail + sinter-wheel-1 line 0, 75 km/h")
    # a run's spectrum is that of the combined run itself (the same code path: equal to round-off)
    spec = plan.specs[1]
    result = simulate(
        "corrugated-rail",
        wheel_roughness="sinter-wheel-1",
        model=spec.model,
        line=0,
        params=spec.params,
        length=1.2,
        keep_pressure=False,
    )
    assert result.wheel_roughness_name == "sinter-wheel-1"
    centres, levels = force_spectrum(result)
    table = combined["tables"]["fig11_corrugated-rail_speeds"]
    column = "100_kmh_db"
    finite = np.isfinite(levels)
    assert np.allclose(np.asarray(table[column], dtype=float)[finite], levels[finite], atol=0.0011)  # 3 decimals
    alone = np.asarray(rail_only["tables"]["fig11_corrugated-rail_speeds"][column], dtype=float)
    assert np.nanmax(np.abs(alone - levels)) > 1.0  # the wheel's roughness changes the force (measured: dB)
    # the wrong kinds are one clear error
    for argv, message in [
        ([*base, "--wheel-set", "corrugated-rail"], "the wheel set corrugated-rail is a rail set"),
        (
            [*base, "--wheel-set", "sinter-wheel-1"],
            "--wheel-radius-mm 390: the wheel set sinter-wheel-1 is 2.9 m round",
        ),
        (
            ["study", "speeds", "--set", "cast-iron-wheel", "--wheel-set", "sinter-wheel-1", "--out", str(out)],
            "every set must be a rail set; cast-iron-wheel is a wheel set",
        ),
    ]:
        assert main(argv) == 2
        captured = capsys.readouterr()
        assert message in captured.err and "Traceback" not in captured.err
