"""The modal wheel's bounded work: the modes' cost said before they are computed and refused beyond a stated
limit; an outline file bounded in kind, bytes and points; a mesh whose size does not grow with the outline's
number of points."""

from __future__ import annotations

import io
import os
import re

import numpy as np
import pytest

from wheelrail.cli import main
from wheelrail.cli.commands.wheel import _announce
from wheelrail.core.errors import WheelrailError
from wheelrail.core.modal_wheel import NAMED_WHEELS, named_profile, outline_profile, read_outline, wheel_modes
from wheelrail.core.modal_wheel import modes as modes_module
from wheelrail.core.modal_wheel.mesh import _resampled, mesh_outline
from wheelrail.core.modal_wheel.modes import MAX_ELEMENTS, WORK_LIMIT, modes_cost
from wheelrail.core.modal_wheel.section import MAX_OUTLINE_BYTES, MAX_OUTLINE_POINTS


@pytest.mark.parametrize("name", list(NAMED_WHEELS))
@pytest.mark.parametrize("size", [0.002, 0.005, 0.012, 0.03])
def test_the_element_count_is_known_before_meshing(name, size):
    profile = named_profile(name)
    cost = modes_cost(profile, 10e3, 10, size)
    meshed = len(mesh_outline(profile.outline(), size, keep=profile.contact_point()).triangles)
    assert cost.elements == pytest.approx(meshed, rel=0.1)
    assert cost.work == cost.elements * 11 and cost.harmonics == 11


def test_runaway_modes_are_refused_before_anything_is_assembled(monkeypatch, capsys):
    def assembled(*args, **kwargs):
        raise AssertionError("assembled")

    monkeypatch.setattr(modes_module, "harmonic_matrices", assembled)
    argv = ["wheel", "--element-size-mm", "2", "--max-harmonic", "40", "--max-frequency-hz", "30000"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("wheelrail wheel: error: --element-size-mm 2: these modes are about")
    assert f"more than the {WORK_LIMIT:,} units" in err and "use larger elements, fewer harmonics" in err
    with pytest.raises(WheelrailError) as caught:
        wheel_modes(named_profile("freight_920"), max_frequency=30e3, max_harmonic=40, element_size=0.002)
    assert caught.value.parameter == "wheel_element_size"


def test_the_cost_is_said_before_computing_and_not_for_modes_already_known(monkeypatch, tmp_path):
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(modes_module, "_MEMORY", {})
    said = []
    settings = {"max_frequency": 2e3, "max_harmonic": 2, "element_size": 0.02, "announce": said.append}
    wheel_modes(named_profile("wheel_640"), **settings)
    assert len(said) == 1 and said[0].harmonics == 3 and "units of work, about" in said[0].describe()
    wheel_modes(named_profile("wheel_640"), **settings)
    assert len(said) == 1


def test_the_command_line_says_the_cost_on_a_terminal_only():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    terminal = Terminal()
    say = _announce(terminal)
    say(modes_cost(named_profile("freight_920"), 10e3, 10, 0.012))
    said = terminal.getvalue()
    assert re.fullmatch(
        r"wheelrail wheel: computing the modes once \(then cached\): about \d+ elements x 11 "
        r"harmonics up to 10000 Hz: [\d,]+ units of work, about \d+ s of CPU\n",
        said,
    ), said
    assert _announce(io.StringIO()) is None  # a pipe stays clean


@pytest.mark.parametrize("size_mm", ["1", "60", "nan", "inf"])
def test_the_element_size_range_is_core_s(size_mm, capsys):
    assert main(["wheel", "--element-size-mm", size_mm]) == 2
    err = capsys.readouterr().err
    assert "is outside the accepted 2 to 50 mm (at most 5 times the thinnest part a wheel may have, 10 mm" in err


def _dense_outline(count: int) -> np.ndarray:
    outline = named_profile("freight_920").outline()
    perimeter = np.sum(np.hypot(*(np.roll(outline, -1, axis=0) - outline).T))
    return _resampled(outline, perimeter / (count - len(outline)))


def _write(path, points_m) -> None:
    path.write_text("r_mm,z_mm\n" + "".join(f"{r * 1e3:.6f},{z * 1e3:.6f}\n" for r, z in points_m), encoding="utf-8")


def test_a_densely_measured_outline_meshes_as_the_drawn_one(tmp_path):
    dense = _dense_outline(MAX_OUTLINE_POINTS - 50)
    assert len(dense) > 4000
    path = tmp_path / "dense.csv"
    _write(path, dense)
    profile = read_outline(path, contact_z_mm=0.0)
    drawn = named_profile("freight_920")
    for size in (0.004, 0.02):
        meshed = mesh_outline(profile.outline(), size, keep=profile.contact_point())
        assert len(meshed.triangles) == pytest.approx(len(mesh_outline(drawn.outline(), size).triangles), rel=0.02)
    settings = {"max_frequency": 2e3, "max_harmonic": 2, "element_size": 0.02, "use_cache": False}
    np.testing.assert_allclose(wheel_modes(profile, **settings).frequency, wheel_modes(drawn, **settings).frequency,
                               rtol=2e-3)  # fmt: skip


@pytest.mark.parametrize("count", [MAX_OUTLINE_POINTS + 200, 20_000])
def test_an_outline_of_too_many_points_is_refused(tmp_path, count):
    path = tmp_path / "many.csv"
    _write(path, _dense_outline(count))
    with pytest.raises(WheelrailError, match=f"at most {MAX_OUTLINE_POINTS} points"):
        read_outline(path, contact_z_mm=0.0)
    with pytest.raises(WheelrailError, match=f"at most {MAX_OUTLINE_POINTS} points"):
        outline_profile(_dense_outline(count), contact_z=0.0)


def test_an_outline_file_larger_than_the_limit_is_refused_unread(tmp_path):
    path = tmp_path / "big.csv"
    with path.open("wb") as handle:
        handle.truncate(200 * MAX_OUTLINE_BYTES)  # sparse: 200 MB of zeros
    with pytest.raises(WheelrailError, match="larger than 1 MB"):
        read_outline(path, contact_z_mm=0.0)


@pytest.mark.parametrize("make", ["fifo", "folder", "device"])
def test_an_outline_that_is_not_a_regular_file_is_refused_before_it_is_opened(tmp_path, make, capsys):
    if make == "fifo":
        path = tmp_path / "pipe.csv"
        os.mkfifo(path)  # opening it for reading would wait for a writer
    elif make == "folder":
        path = tmp_path
    else:
        path = "/dev/zero"  # would be read without end
    with pytest.raises(WheelrailError, match="is not a regular file"):
        read_outline(path, contact_z_mm=0.0)
    assert main(["wheel", "--outline", str(path)]) == 2
    err = capsys.readouterr().err
    assert "--outline: the wheel outline" in err and "not a regular file" in err and err.count("\n") == 1


def test_a_mesh_too_large_to_assemble_is_refused_whatever_the_harmonics(monkeypatch):
    # the largest wheel at 2 mm elements and one harmonic: little work, but a mesh whose assembly needs gigabytes
    monkeypatch.setattr(modes_module, "harmonic_matrices", lambda *args: pytest.fail("assembled"))
    big = named_profile("freight_920")
    big = type(big)(**{**{k: v for k, v in big.describe().items() if k != "kind"}, "wheel_radius": 1.25})
    cost = modes_cost(big, 10e3, 0, 0.002)
    assert cost.elements > MAX_ELEMENTS and cost.work < WORK_LIMIT
    with pytest.raises(WheelrailError, match=f"more than the {MAX_ELEMENTS:,} allowed") as caught:
        wheel_modes(big, max_frequency=10e3, max_harmonic=0, element_size=0.002, use_cache=False)
    assert caught.value.parameter == "wheel_element_size"
