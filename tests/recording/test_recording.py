"""Rerun recordings: what is written is read back exactly by rerun's own reader (rerun.chunk.RrdReader)."""

from __future__ import annotations

import argparse
import os

import numpy as np
import pytest
from rerun.chunk import RrdReader

from wheelrail.core.engine.results import RunHeader, RunResult, StepState
from wheelrail.core.errors import WheelrailError
from wheelrail.core.parameters import ContactParameters, ModelParameters
from wheelrail.core.recording import (
    ENTITY_PATHS,
    RecordingOptions,
    RecordingSink,
    add_recording_arguments,
    check_recording_path,
    read_recording,
    record_result,
    sink_from_args,
)
from wheelrail.core.roughness import load_roughness
from wheelrail.core.spectra.force import force_spectrum

DT = 1e-3 / (100 / 3.6)  # s, 1 mm at 100 km/h
N_STEPS = 700  # 25 ms: enough for a force spectrum after the 20 ms start-up skip


def synthetic_result(n: int = N_STEPS, model: str = "3d", preload: float = 65e3) -> RunResult:
    """A 3D-like run: sine force on the preload, Hertz pressure (scaled with the force) on a 25 x 25 window."""
    t = np.arange(n) * DT
    force = preload + 3e3 * np.sin(2 * np.pi * 500 * t) + 50 * np.sin(2 * np.pi * 3100 * t)
    contact = ContactParameters(preload=preload)
    window = np.arange(-12, 13) * 1e-3
    r2 = window[None, :] ** 2 + window[:, None] ** 2
    pressure = None
    if model == "3d":
        radius = contact.hertz_radius(force)[:, None, None]
        peak = contact.hertz_peak_pressure(force)[:, None, None]
        pressure = (peak * np.sqrt(np.clip(1 - r2 / radius**2, 0, None))).astype(np.float32)
    roughness = 1e-5 * np.sin(2 * np.pi * t / 2e-3)
    return RunResult(
        header=RunHeader(
            model=model,
            line=0,
            roughness_name="corrugated-rail",
            params=ModelParameters(contact=contact),
            run_in_length=1.0,
        ),
        time=t,
        x=0.016 + np.arange(n) * 1e-3,
        force=force,
        xi_wheel=8e-5 + 1e-6 * np.cos(t * 3e3),
        xi_rail=3e-5 + 1e-6 * np.sin(t * 3e3),
        roughness=roughness,
        contact_length=np.full(n, 0.011),
        contact_area=np.full(n, 9.4e-5) if model != "2d" else np.full(n, np.nan),
        equivalent_roughness=roughness if model != "hertz-average" else 0.5 * roughness,
        pressure=pressure,
        window_x=window if model == "3d" else None,
        window_y=window if model == "3d" else None,
        loss_of_contact_steps=0,
    )


def chunks_of(path, entity: str, *, static: bool | None = None):
    """The chunks of one entity in a file, straight from rerun's reader."""
    return [
        c
        for c in RrdReader(path).stream()
        if c.entity_path == "/" + entity and (static is None or c.is_static == static)
    ]


def scalar_column(path, entity: str) -> tuple[np.ndarray, np.ndarray]:
    """(steps, values) of a Scalars entity, ordered by step, decoded from the Arrow record batches."""
    steps, values = [], []
    for chunk in chunks_of(path, entity, static=False):
        batch = chunk.to_record_batch()
        steps.append(batch.column("step").to_numpy())
        rows = batch.column("Scalars:scalars")
        values.append(rows.flatten().to_numpy().reshape(len(rows), -1))  # one row per step, 1+ series
    steps, values = np.concatenate(steps), np.concatenate(values)
    order = np.argsort(steps, kind="stable")
    return steps[order], values[order].squeeze(axis=1) if values.shape[1] == 1 else values[order]


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    result = synthetic_result()
    path = tmp_path_factory.mktemp("rec") / "run.rrd"
    assert record_result(result, path, roughness=load_roughness("corrugated-rail")) == path
    return result, path


def test_force_column_equals_the_run_force(recorded):
    result, path = recorded
    steps, force = scalar_column(path, "contact/force")
    np.testing.assert_array_equal(steps, np.arange(result.n_steps))
    # exact: rerun stores Scalars as float64, the dtype of the run's force
    np.testing.assert_array_equal(force, result.force)


def test_pressure_map_at_a_step_equals_the_original(recorded):
    result, path = recorded
    chosen = 123
    (static,) = chunks_of(path, "contact/pressure", static=True)
    image_format = static.to_record_batch().column("DepthImage:format")[0].as_py()[0]
    assert (image_format["width"], image_format["height"]) == (25, 25)
    for chunk in chunks_of(path, "contact/pressure", static=False):
        batch = chunk.to_record_batch()
        steps = batch.column("step").to_numpy()
        if chosen in steps:
            row = int(np.nonzero(steps == chosen)[0][0])
            raw = batch.column("DepthImage:buffer")[row].values[0].values.to_numpy(zero_copy_only=False)
            stored = np.asarray(raw, dtype=np.uint8).view(np.float32).reshape(25, 25)
            # exact: the map is stored as its float32 bytes
            np.testing.assert_array_equal(stored, result.pressure[chosen])
            assert stored.max() > 1e9  # a real Hertz map (p0 ~ 1.03 GPa at 65 kN), not zeros
            return
    pytest.fail(f"step {chosen} has no pressure map in the recording")


def test_blueprint_is_in_the_file(recorded):
    _, path = recorded
    reader = RrdReader(path)
    (blueprint,) = reader.blueprints()
    summary = reader.store(store=blueprint).summary()
    # the default blueprint: 5 time series, pressure map, pressure surface, bar chart, text = 9 views
    assert summary.count("ViewBlueprint:class_identifier") == 9
    assert "ViewportBlueprint:root_container" in summary


def test_entity_tree_and_timelines(recorded):
    _, path = recorded
    chunks = list(RrdReader(path).stream())
    paths = {c.entity_path.lstrip("/") for c in chunks}
    expected = set(ENTITY_PATHS) - {"roughness/equivalent"}  # r_eq = r here, so not repeated
    assert expected <= paths, expected - paths
    temporal = [c for c in chunks if not c.is_static and not c.entity_path.startswith("/__")]
    assert all(set(c.timeline_names) == {"step", "time", "position_um"} for c in temporal)


def test_nominal_circle_is_the_hertz_radius(tmp_path):
    for preload, radius in ((65e3, 5.482e-3), (130e3, 5.482e-3 * 2 ** (1 / 3))):  # a ∝ P^(1/3)
        path = record_result(synthetic_result(model="hertz", preload=preload), tmp_path / f"c{preload:.0f}.rrd")
        (chunk,) = [
            c
            for c in chunks_of(path, "contact/nominal_circle", static=True)
            if "LineStrips3D:strips" in c.to_record_batch().schema.names
        ]
        strip = np.array(chunk.to_record_batch().column("LineStrips3D:strips")[0].as_py()[0])
        # 1 µm: the paper's a = 5.48 mm is given to 10 µm; the circle is stored in float32 (~1e-9 m)
        assert np.hypot(strip[:, 0], strip[:, 1]) == pytest.approx(radius, abs=1e-6)


def test_elliptic_patch_and_wheel_set_are_recorded(tmp_path):
    """A 0.46 m wheel on a 0.30 m crown draws Hertz's ellipse (a = 6.20 mm along the rail, b = 4.67 mm
    across), and a run on rail and wheel roughness together names both sets, read back in the header."""
    from wheelrail.core.engine import simulate

    contact = ContactParameters(wheel_radius=0.46, rail_crown_radius=0.30)
    result = simulate(
        "corrugated-rail",
        wheel_roughness="sinter-wheel-1",
        model="hertz",
        length=0.05,
        params=ModelParameters(contact=contact),
    )
    path = record_result(result, tmp_path / "ellipse.rrd", roughness=load_roughness("corrugated-rail"))
    (chunk,) = [
        c
        for c in chunks_of(path, "contact/nominal_circle", static=True)
        if "LineStrips3D:strips" in c.to_record_batch().schema.names
    ]
    strip = np.array(chunk.to_record_batch().column("LineStrips3D:strips")[0].as_py()[0])
    a, b = contact.hertz_semi_axes()
    # float32 storage: 1e-9 m; the ellipse (x/a)^2 + (y/b)^2 = 1 through every point
    assert np.abs(np.max(np.abs(strip[:, 0])) - a) < 1e-8 and np.abs(np.max(np.abs(strip[:, 1])) - b) < 1e-8
    assert np.allclose((strip[:, 0] / a) ** 2 + (strip[:, 1] / b) ** 2, 1.0, atol=1e-5)
    back = read_recording(path)
    assert back.header.wheel_roughness_name == "sinter-wheel-1" and back.header.roughness_name == "corrugated-rail"
    assert back.header.params.contact.rail_crown_radius == pytest.approx(0.30)


def test_force_spectrum_is_recorded(recorded):
    result, path = recorded
    (chunk,) = chunks_of(path, "spectra/force", static=True)
    batch = chunk.to_record_batch()
    levels = np.array(batch.column("BarChart:values")[0].as_py()[0]["buffer"]).view(np.float64)
    centres, expected = force_spectrum(result)
    # exact: the same function on the same force; NaN (unresolved bands) is recorded as 0
    np.testing.assert_array_equal(levels, np.nan_to_num(expected, nan=0.0))
    assert len(centres) == len(levels) == 23  # 50 Hz .. 8 kHz


def test_read_recording_round_trip(recorded):
    result, path = recorded
    back = read_recording(path)
    for name in (
        "x",
        "force",
        "xi_wheel",
        "xi_rail",
        "roughness",
        "contact_length",
        "contact_area",
        "equivalent_roughness",
        "window_x",
        "window_y",
    ):
        np.testing.assert_array_equal(getattr(back, name), getattr(result, name), err_msg=name)  # exact (float64)
    np.testing.assert_allclose(back.time, result.time, rtol=0, atol=0.5e-9)  # timeline in whole ns
    np.testing.assert_array_equal(back.pressure, result.pressure)
    assert (back.model, back.line, back.time_step, back.speed) == ("3d", 0, DT, 100 / 3.6)
    assert back.parameters == result.parameters


def test_decimated_pressure_and_streaming_sink_copy_the_maps(tmp_path):
    """The per-step sink, with the loop reusing one pressure buffer, record_every=5, small chunks."""
    result = synthetic_result(n=203)
    path = tmp_path / "stream.rrd"
    buffer = np.zeros((25, 25), dtype=np.float32)  # the loop may hand out the same array every step
    with RecordingSink(rrd=path, options=RecordingOptions(record_every=5, chunk_steps=64)) as sink:
        sink.start(result)
        for k in range(result.n_steps):
            state = result.state(k)
            buffer[:] = state.pressure
            sink(StepState(**{**{f: getattr(state, f) for f in state.__slots__}, "pressure": buffer}))
        sink.finish(result)
    assert not list(tmp_path.glob("*.partial")) and path.is_file()
    back = read_recording(path)
    np.testing.assert_array_equal(back.force, result.force)
    assert back.pressure is None  # not every step has a map
    maps = {}
    for chunk in chunks_of(path, "contact/pressure", static=False):
        batch = chunk.to_record_batch()
        raw = batch.column("DepthImage:buffer").flatten().flatten().to_numpy(zero_copy_only=False)
        images = np.asarray(raw, np.uint8).view(np.float32).reshape(-1, 25, 25)
        for k, image in zip(batch.column("step").to_numpy(), images, strict=True):
            maps[int(k)] = image
    assert sorted(maps) == list(range(0, 203, 5))
    for k, image in maps.items():
        np.testing.assert_array_equal(image, result.pressure[k])  # each its own step, not the last buffer
    # the surface mesh: every 4th recorded map (steps 0, 20, 40, ...), z = a p / p0 over the window
    a, p0 = ContactParameters().hertz_radius(), ContactParameters().hertz_peak_pressure()
    surfaces = {}
    for chunk in chunks_of(path, "contact/pressure_surface", static=False):
        batch = chunk.to_record_batch()
        column = batch.column("Mesh3D:vertex_positions")
        vertices = np.asarray(column.flatten().flatten().to_numpy(zero_copy_only=False)).reshape(len(column), -1, 3)
        surfaces.update(zip(batch.column("step").to_numpy().tolist(), vertices, strict=True))
    assert sorted(surfaces) == list(range(0, 203, 20))
    k = 140
    # float32 vertices: 1e-7 relative
    np.testing.assert_allclose(surfaces[k][:, 2], result.pressure[k].ravel() * a / p0, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(surfaces[k][:, 0].reshape(25, 25)[0], result.window_x, atol=1e-9)


def test_unwritable_or_bad_paths_fail_before_the_run(tmp_path):
    parser = argparse.ArgumentParser()
    add_recording_arguments(parser)
    with pytest.raises(WheelrailError, match="does not exist"):
        sink_from_args(parser.parse_args(["--rrd", str(tmp_path / "missing" / "a.rrd")]))
    a_file = tmp_path / "file.txt"
    a_file.write_text("x")
    with pytest.raises(WheelrailError, match="not writable|does not exist"):
        check_recording_path(a_file / "a.rrd")
    with pytest.raises(WheelrailError, match="must end in .rrd"):
        check_recording_path(tmp_path / "a.npz")
    (tmp_path / "dir.rrd").mkdir()
    with pytest.raises(WheelrailError, match="is a folder"):
        check_recording_path(tmp_path / "dir.rrd")
    # the API's words (the argument's name); the command line names the option (tests/cli)
    with pytest.raises(WheelrailError, match="record_every 0: not a whole number of at least 1") as info:
        sink_from_args(parser.parse_args(["--rrd", str(tmp_path / "a.rrd"), "--record-every", "0"]))
    from wheelrail.cli.commands._common import CLI_NAMES

    assert info.value.render(CLI_NAMES).startswith("--record-every 0: not a whole number of at least 1")
    with pytest.raises(WheelrailError, match="connect 'nonsense': not a viewer address") as info:
        sink_from_args(parser.parse_args(["--connect", "nonsense"]))
    assert info.value.render(CLI_NAMES).startswith("--connect nonsense: not a viewer address")
    assert sink_from_args(parser.parse_args([])) is None
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir.rrd", "file.txt"]  # nothing written


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_read_only_folder_is_reported(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        with pytest.raises(WheelrailError, match="is not writable"):
            check_recording_path(folder / "a.rrd")
    finally:
        folder.chmod(0o700)


def test_read_only_file_system_is_reported():
    if not os.path.isdir("/proc/self"):
        pytest.skip("no /proc")
    with pytest.raises(WheelrailError, match="cannot write recording"):  # /proc refuses new files, even to root
        check_recording_path("/proc/self/run.rrd")


def test_failed_run_leaves_no_file(tmp_path):
    path = tmp_path / "failed.rrd"
    with pytest.raises(RuntimeError), RecordingSink(rrd=path) as sink:
        sink(synthetic_result(n=10).state(0))
        raise RuntimeError("the loop failed")
    assert list(tmp_path.iterdir()) == []


def test_corrupt_and_foreign_files_are_clear_errors(tmp_path):
    bad = tmp_path / "bad.rrd"
    bad.write_bytes(b"not a recording at all")
    with pytest.raises(WheelrailError, match="cannot read recording"):
        read_recording(bad)
    with pytest.raises(WheelrailError, match="does not exist"):
        read_recording(tmp_path / "none.rrd")
    import rerun as rr

    foreign = tmp_path / "foreign.rrd"
    stream = rr.RecordingStream("someone-else")
    stream.save(foreign)
    stream.log("x", rr.Scalars(1.0))
    stream.disconnect()
    with pytest.raises(WheelrailError, match="no wheelrail recording"):
        read_recording(foreign)


@pytest.mark.parametrize("model", ["hertz", "3d"])
def test_real_short_run_streams_exactly(tmp_path, model, step_arrays):
    from wheelrail.core.engine import prepare_run

    run = prepare_run("corrugated-rail", model=model, length=0.05)
    path = tmp_path / f"{model}.rrd"
    sink = RecordingSink(rrd=path, options=RecordingOptions(chunk_steps=16))
    sink.start(run, roughness=load_roughness("corrugated-rail"))
    result = run.run(sink)
    sink.finish(result)
    back = read_recording(path)
    assert back.n_steps == result.n_steps == 50
    for name in step_arrays:
        if name == "time":  # the recording keeps the step; time comes back as step * dt: one rounding, 1e-15
            np.testing.assert_allclose(back.time, result.time, rtol=1e-15, atol=1e-18)
        else:
            np.testing.assert_array_equal(getattr(back, name), getattr(result, name), err_msg=name)  # exact
    if model == "3d":
        np.testing.assert_array_equal(back.pressure, result.pressure)
        np.testing.assert_array_equal(back.contact_area, result.contact_area)
        assert back.pressure.max() > 5e8  # a loaded contact (p0 ~ 1 GPa), not an empty window
    # roughness/lines: the set's lines -3..3 at the wheel positions; line 0 is the run's own line
    steps, lines = scalar_column(path, "roughness/lines")
    assert lines.shape == (result.n_steps, 7)
    np.testing.assert_allclose(lines[:, 3], result.roughness, rtol=0, atol=1e-12)  # same samples, 1 pm


def test_sink_used_without_start_is_completed_by_finish(tmp_path):
    """As ``wheelrail run`` may use it: callback=sink.log_step, then finish(result), no start()."""
    result = synthetic_result(n=120, preload=130e3)
    path = tmp_path / "late.rrd"
    sink = RecordingSink(rrd=path, options=RecordingOptions(chunk_steps=50))
    for k in range(result.n_steps):
        sink.log_step(result.state(k))
    sink.finish(result, roughness=load_roughness("corrugated-rail"))
    back = read_recording(path)
    np.testing.assert_array_equal(back.pressure, result.pressure)
    np.testing.assert_array_equal(back.window_x, result.window_x)  # the centred 1 mm grid
    assert back.parameters["contact"]["preload"] == 130e3
    strips = [c.to_record_batch() for c in chunks_of(path, "contact/nominal_circle", static=True)]
    last = [b for b in strips if "LineStrips3D:strips" in b.schema.names][-1]
    column = last.column("LineStrips3D:strips")
    circle = np.array(column[len(column) - 1].as_py()[0])  # rows of a static entity: the last one counts
    # the circle logged at the end (the latest static value) has the run's radius, not the 65 kN default
    assert np.hypot(circle[:, 0], circle[:, 1]) == pytest.approx(5.482e-3 * 2 ** (1 / 3), abs=1e-6)
    steps, lines = scalar_column(path, "roughness/lines")  # sent once at the end, over the whole run
    np.testing.assert_array_equal(steps, np.arange(result.n_steps))
    assert lines.shape == (result.n_steps, 7) and np.all(np.abs(lines) < 1e-3)  # heights in m (µm-scale)


def test_dropped_sink_leaves_no_partial_file(tmp_path):
    import gc

    sink = RecordingSink(rrd=tmp_path / "dropped.rrd")
    sink(synthetic_result(n=5).state(0))
    assert len(list(tmp_path.glob(".dropped.rrd.*.partial"))) == 1
    del sink
    gc.collect()
    assert list(tmp_path.iterdir()) == []


def test_connect_streams_to_a_running_viewer_server(tmp_path):
    """--connect: a rerun gRPC server (what a viewer hosts) in another process receives the run."""
    import socket
    import subprocess
    import sys

    with socket.socket() as probe:  # a free port
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    server = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import rerun as rr, sys, time; rr.init('viewer'); "
            f"print(rr.serve_grpc(grpc_port={port}), flush=True); time.sleep(60)",
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert server.stdout.readline().strip() == f"rerun+http://127.0.0.1:{port}/proxy"  # listening
        path = record_result(synthetic_result(n=100), tmp_path / "both.rrd", connect=f"127.0.0.1:{port}")
        # no error: every message reached the server (an unreachable one raises after ~7 s, file kept)
        np.testing.assert_array_equal(read_recording(path).force, synthetic_result(n=100).force)
    finally:
        server.kill()
        server.wait()


def test_sink_records_only_the_roughness_it_is_given(tmp_path):
    """The run names a bundled set, but without the set itself no roughness/lines is written (nothing loaded)."""
    result = synthetic_result(n=60, model="hertz")
    assert result.roughness_name == "corrugated-rail"
    path = record_result(result, tmp_path / "plain.rrd")
    paths = {c.entity_path.lstrip("/") for c in RrdReader(path).stream()}
    assert "roughness/lines" not in paths and "contact/force" in paths
    rough = load_roughness("corrugated-rail")
    steps, lines = scalar_column(record_result(result, tmp_path / "lines.rrd", roughness=rough), "roughness/lines")
    assert lines.shape == (60, 7)
    # exact: the same interpolation of the set's line 2 (row centre + 2) at the wheel positions
    np.testing.assert_array_equal(lines[:, 5], np.interp(result.x, rough.x, rough.heights[rough.row_of_line(2)]))


@pytest.mark.slow
def test_sound_power_spectra_are_recorded_on_request(tmp_path):
    # wheelrail run --rrd F --sound-power / record_result(sound_power=True): the run's rolling noise as bar charts
    # spectra/sound_power/{rail,rail_lateral,sleeper,wheel,total} (dB re 1 pW, NaN and -inf recorded as 0: the centred
    # contact's lateral rail does not radiate) equal to run_noise's, and a
    # summary document; without the option nothing is added (the older files' entity tree is unchanged)
    from wheelrail.core.engine import simulate
    from wheelrail.core.noise.components import sound_power_parts
    from wheelrail.core.noise.run_noise import run_noise

    result = simulate("cast-iron-wheel", model="hertz", line=0, length=1.0)
    path = record_result(result, tmp_path / "noise.rrd", sound_power=True)
    expected = run_noise(result)
    for component in sound_power_parts():
        (chunk,) = chunks_of(path, f"spectra/sound_power/{component}", static=True)
        batch = chunk.to_record_batch()
        levels = np.array(batch.column("BarChart:values")[0].as_py()[0]["buffer"]).view(np.float64)
        np.testing.assert_array_equal(levels, np.nan_to_num(expected.sound_power_db[component], nan=0.0, neginf=0.0))
        assert len(levels) == 24  # 50 Hz .. 10 kHz
    assert chunks_of(path, "spectra/sound_power/summary", static=True)
    from test_blueprint import check_blueprint

    assert check_blueprint(path) == []  # the sound-power views show these bar charts and the totals
    plain = record_result(result, tmp_path / "plain.rrd")
    assert not chunks_of(plain, "spectra/sound_power/total")


def _entity_chunks(path, entity: str) -> list:
    """The rows of an entity's temporal chunks, in file order, column by column (not the row ids: new in every
    recording; nor where the chunks end)."""
    out: dict[str, list] = {}
    for chunk in chunks_of(path, entity, static=False):
        batch = chunk.to_record_batch()
        for name in batch.schema.names:
            if "RowId" not in name:
                out.setdefault(name, []).extend(batch.column(name).to_pylist())
    return out


def test_blocks_and_steps_record_the_same_file_content(tmp_path):
    """InteractionRun.run gives a RecordingSink its steps in blocks (log_block); the per-step callback
    (sink.log_step) must write the same rows: every scalar, image and surface, value for value. The block run
    keeps no maps (the loop's chunk buffer is reused), the per-step one keeps them."""
    from wheelrail.core.engine import prepare_run

    roughness = load_roughness("corrugated-rail")
    paths = {}
    for how in ("blocks", "steps"):
        run = prepare_run("corrugated-rail", model="3d", length=0.6, keep_pressure=how == "steps")
        paths[how] = tmp_path / f"{how}.rrd"
        sink = RecordingSink(rrd=paths[how], options=RecordingOptions(chunk_steps=200, record_every=3))
        sink.start(run, roughness=roughness)
        result = run.run(sink if how == "blocks" else sink.log_step)
        sink.finish(result)
    assert read_recording(paths["blocks"]).n_steps == 600
    entities = ["contact/force", "wheel/position", "roughness/lines", "contact/area", "contact/pressure"]
    for entity in [*entities, "contact/pressure_surface"]:
        blocks, steps = _entity_chunks(paths["blocks"], entity), _entity_chunks(paths["steps"], entity)
        assert len(blocks["step"]) == len(steps["step"]) > 0, entity
        assert blocks == steps, entity  # exact: the same rows, the same values


def test_direct_columns_equal_the_archetypes_columns():
    """The sink's columns built over numpy buffers (recording.columns) are what rerun's archetypes build."""
    import rerun as rr

    from wheelrail.core.recording import columns

    def arrays(column_list):
        return [(column.component_descriptor(), column.as_arrow_array()) for column in column_list]

    rng = np.random.default_rng(1)
    values, lines = rng.random(7), rng.random((7, 3))
    images = rng.random((5, 4, 3)).astype(np.float32)
    vertices = rng.random((5, 12, 3)).astype(np.float32)
    colours = rng.integers(0, 2**32, (5, 12), dtype=np.uint32)
    mesh = rr.Mesh3D.columns(vertex_positions=vertices.reshape(-1, 3), vertex_colors=colours.reshape(-1))
    cases = [
        ([columns.scalar_column(values)], rr.Scalars.columns(scalars=values)),
        ([columns.scalar_column(lines)], rr.Scalars.columns(scalars=lines)),
        ([columns.blob_column(images)], rr.DepthImage.columns(buffer=images.reshape(5, -1).view(np.uint8))),
        (
            [columns.position_column(vertices), columns.colour_column(colours)],
            [column.partition(np.full(5, 12)) for column in mesh],
        ),
    ]
    for ours, theirs in cases:
        for (mine, array), (descriptor, expected) in zip(arrays(ours), arrays(theirs), strict=True):
            assert mine == descriptor
            assert array.type == expected.type and array.equals(expected)


def test_surface_kernel_gives_numpys_vertices_and_colours():
    """The compiled surface fill equals the numpy it replaced: z = p * float32(a / p0), table_colours' colours
    (below 0, within, above the ramp's top, and a zero map), exactly."""
    from wheelrail.core.drawing.patch import PRESSURE_RANGE_P0, colour_table, packed_rgba, table_colours
    from wheelrail.core.recording.pressure import surface_kernel

    table = packed_rgba(colour_table())
    a, p0 = ContactParameters().hertz_radius(), ContactParameters().hertz_peak_pressure()
    rng = np.random.default_rng(3)
    pressure = (rng.uniform(-0.1, 2.5, (6, 19 * 25)) * p0).astype(np.float32)  # beyond the ramp at both ends
    pressure[0] = 0.0
    xy = rng.random((19 * 25, 2)).astype(np.float32)
    vertices = np.empty((6, 19 * 25, 3), np.float32)
    colours = np.empty((6, 19 * 25), np.uint32)
    scale = np.float32((len(table) - 1) / (PRESSURE_RANGE_P0 * p0))
    surface_kernel()(pressure, xy, np.float32(a / p0), scale, table, vertices, colours)
    np.testing.assert_array_equal(vertices[:, :, :2], np.broadcast_to(xy, (6, 19 * 25, 2)))
    np.testing.assert_array_equal(vertices[:, :, 2], pressure * (a / p0))
    np.testing.assert_array_equal(colours, table_colours(pressure, PRESSURE_RANGE_P0 * p0, table))
