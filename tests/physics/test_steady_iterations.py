"""The steady start's iterations in compiled code that releases the GIL (``core/engine/steady_start.py``): a study's
runs in parallel threads then share only the law's call and two dispatches an iteration; the same steady state as
numpy's FFT and least squares give."""

from __future__ import annotations

import numpy as np
import pytest

from wheelrail.core.engine import prepare_run
from wheelrail.core.engine import steady_start as steady


def test_the_least_squares_are_numpys_of_least_norm():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(650, 5)), rng.normal(size=650)
    expected = np.linalg.lstsq(a, b, rcond=None)[0]
    assert np.allclose(steady._least_squares(a, b), expected, rtol=1e-12, atol=0.0)
    twice = np.column_stack([a[:, :3], a[:, 2], a[:, 4]])  # two equal changes: singular normal equations
    expected = np.linalg.lstsq(twice, b, rcond=None)[0]
    assert np.allclose(steady._least_squares(twice, b), expected, rtol=1e-12, atol=1e-15)
    assert np.array_equal(steady._least_squares(np.zeros((9, 2)), np.ones(9)), np.zeros(2))


def test_the_preconditioner_is_the_circulant_inverse_by_fft():
    rng = np.random.default_rng(4)
    column, x = rng.normal(size=650) * 1e-9, rng.normal(size=650)
    k = 3e9
    expected = np.fft.irfft(np.fft.rfft(x) / (1.0 + k * np.fft.rfft(column)), 650)
    assert np.allclose(steady._circular(steady._circulant_inverse(column, k), x), expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize("model", ["hertz", "2d"])
def test_an_iteration_calls_no_numpy_least_squares_or_fft(monkeypatch, model):
    calls = []
    for module, name in ((np.linalg, "lstsq"), (np.fft, "rfft"), (np.fft, "irfft")):
        real = getattr(module, name)
        monkeypatch.setattr(module, name, lambda *a, real=real, name=name, **k: calls.append(name) or real(*a, **k))
    run = prepare_run("corrugated-rail", model=model, line=0, length=0.06)
    run.run()
    assert run.steady.iterations > 5
    assert calls == ["rfft", "irfft"]  # the preconditioner's inverse, once a start
    for compiled in (steady._approach, steady._iterate):
        assert compiled.targetoptions["nogil"]
