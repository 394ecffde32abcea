"""A study's run file carries the digest of its arrays: an edited file is computed again, with a warning."""

from __future__ import annotations

import io
import warnings

import numpy as np
import pytest

from wheelrail.core.spectra.force import resolved_force_bands
from wheelrail.core.study.specs import RunSpec, RunSummary
from wheelrail.core.study.store import cache_path, load_cached, save_cached


def _spec_and_summary():
    spec = RunSpec(source="corrugated-rail", set_label="r", set_digest="0" * 64, model="hertz", length=1.0)
    n_steps = 1000
    centres, resolved = resolved_force_bands(n_steps, spec.params.run.time_step)
    levels = np.where(resolved, np.linspace(60.0, 40.0, centres.size), np.nan)
    summary = RunSummary(
        key=spec.key,
        band_centres=centres,
        levels=levels,
        force_mean=65e3,
        force_std=900.0,
        force_min=62e3,
        force_max=68e3,
        loss_of_contact_steps=0,
        n_steps=n_steps,
        run_time=1.5,
    )
    return spec, summary


def _rewrite(path, change) -> None:
    """What a hand edit does: load the arrays, change some, save them all again (the digest as it was)."""
    with np.load(path) as data:
        arrays = {name: data[name] for name in data.files}
    change(arrays)
    out = io.BytesIO()
    np.savez(out, **arrays)
    path.write_bytes(out.getvalue())


def test_an_intact_run_file_is_trusted(tmp_path):
    spec, summary = _spec_and_summary()
    save_cached(tmp_path, summary)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        back = load_cached(tmp_path, spec)
    np.testing.assert_array_equal(back.levels, summary.levels)


@pytest.mark.parametrize(
    "change",
    [
        lambda arrays: arrays.update(levels_db=arrays["levels_db"] + 50.0),  # +50 dB: every range check passes
        lambda arrays: arrays.update(force_mean=np.array(65.5e3)),
        lambda arrays: arrays.pop("digest"),  # written without one (by hand, or by an earlier version)
    ],
    ids=["levels +50 dB", "force mean", "no digest"],
)
def test_an_edited_run_file_is_recomputed_with_a_warning(tmp_path, change):
    spec, summary = _spec_and_summary()
    save_cached(tmp_path, summary)
    _rewrite(cache_path(tmp_path, spec.key), change)
    with pytest.warns(UserWarning, match=r"unusable study run file .*(digest|missing arrays digest)"):
        assert load_cached(tmp_path, spec) is None


def test_a_specs_key_is_worked_out_once(monkeypatch):
    # a study reads each run's key several times (unique runs, its run file, the summary, the tables): the key
    # hashes the run's whole description once a spec
    spec, _ = _spec_and_summary()
    calls = []
    described = RunSpec.description
    monkeypatch.setattr(RunSpec, "description", lambda self: calls.append(1) or described(self))
    fresh = RunSpec(source="corrugated-rail", set_label="r", set_digest="0" * 64, model="hertz", length=2.0)
    assert fresh.key == fresh.key != spec.key
    assert len(calls) == 1
