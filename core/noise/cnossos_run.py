"""The CNOSSOS-EU rolling-noise source beside a run of this project's models, on the run's own roughness.

One rule, used by the explorer's Noise tab, ``wheelrail noise --run`` and the ``noise`` study, for what "the
directive's source for the same case" means:

- roughness: the run's own combined roughness (rail plus wheel set, the line under the wheel, as the run saw it
  unfiltered: ``RunResult.roughness``) in the 24 bands at the run's speed, over the same record as the force
  spectrum (the first :data:`wheelrail.core.spectra.force.FORCE_SKIP` s dropped, one Hann window); the directive
  allows measured roughness in place of Tables G-1a and G-1b;
- contact filter: A3 (Table G-2) for the run's preload and its own wheel diameter 2 R (the rule of
  ``wheelrail filters``), or a filter given in its place (a model's dynamic filter);
- track transfer L_H,tr: :data:`CNOSSOS_TRACK_TYPE`, the class nearest the model track: concrete mono-block
  sleepers; the model's 120 MN/m rail pads are softer than the directive's "soft" class (< 150 MN/m), so the
  softest class is the nearest;
- vehicle transfer L_H,veh: the Table G-3b wheel diameter nearest 2 R
  (:func:`wheelrail.core.noise.twins.nearest_table_diameter_mm`); the two diameters differ in general (the paper's
  2R = 0.78 m takes the 0.84 m column), so the summary states both: ``contact_filter_wheel_diameter_m`` (2 R, or
  None where a model's dynamic filter replaces A3) and ``vehicle_transfer_wheel_diameter_m`` (the column; the
  directive's own ``wheel_diameter_m`` key holds the same), with ``model_wheel_diameter_m`` (2 R);
- one axle (N_a = 1), so that it stands beside the model's sound power per axle (two wheels on two rails).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from wheelrail.core.noise.cnossos import CnossosResult, cnossos_rolling_noise, contact_filter_a3
from wheelrail.core.spectra.bands import NOISE_BAND_RANGE
from wheelrail.core.spectra.levels import ROUGHNESS_REFERENCE

CNOSSOS_TRACK_TYPE = "mono-block-soft"

__all__ = ["CNOSSOS_TRACK_TYPE", "cnossos_beside", "cnossos_beside_run", "run_roughness_db"]


def run_roughness_db(result) -> np.ndarray:
    """The run's combined roughness under the wheel in the 24 bands 50 Hz - 10 kHz at its speed, dB re 1 um
    (NaN where a band is not resolved: above v / (2 dx), or below what the record holds)."""
    from wheelrail.core.engine.results import result_of_run
    from wheelrail.core.spectra.force import force_spectrum

    result = result_of_run("run_roughness_db: result", result)
    _, levels = force_spectrum(
        np.asarray(result.roughness, dtype=float), result.time_step, band_range=NOISE_BAND_RANGE
    )  # dB re 1 m: the force spectrum's reference is 1 (N)
    return np.asarray(levels, dtype=float) - 20 * np.log10(ROUGHNESS_REFERENCE)


def cnossos_beside(
    params, roughness_label: str, roughness_db, *, contact_filter: tuple | None = None, rule: str = "proportional"
) -> CnossosResult:
    """The CNOSSOS-EU source of one axle for the wheel, contact and speed of ``params`` (a
    :class:`wheelrail.core.parameters.ModelParameters`) on a combined roughness (24 bands, dB re 1 um; NaN bands
    are left out), by the rule of the module docstring. ``contact_filter``: ``(name, dB on the 24 bands)`` in the
    place of A3."""
    from wheelrail.core.noise.twins import nearest_table_diameter_mm

    contact, speed = params.contact, params.run.speed
    model_diameter = 2 * contact.radius_along
    filter_diameter = model_diameter if contact_filter is None else None
    if contact_filter is None:
        contact_filter = ("A3", contact_filter_a3(contact.preload, model_diameter, speed, rule))
    roughness_db = np.asarray(roughness_db, dtype=float)
    column = nearest_table_diameter_mm(contact.radius_along) / 1e3
    result = cnossos_rolling_noise(
        speed,
        track_type=CNOSSOS_TRACK_TYPE,
        wheel_diameter=column,
        load=contact.preload,
        axles=1,
        rule=rule,
        contact_filter=contact_filter,
        roughness=(roughness_label, np.where(np.isfinite(roughness_db), roughness_db, -np.inf)),
    )
    diameters = {
        "model_wheel_diameter_m": model_diameter,
        "contact_filter_wheel_diameter_m": filter_diameter,
        "vehicle_transfer_wheel_diameter_m": column,
    }
    return dataclasses.replace(result, configuration={**result.configuration, **diameters})


def cnossos_beside_run(result, *, rule: str = "proportional") -> CnossosResult:
    """:func:`cnossos_beside` for a finished run (:class:`wheelrail.core.engine.results.RunResult`) on its own
    roughness."""
    from wheelrail.core.engine.results import result_of_run

    result = result_of_run("cnossos_beside_run: result", result)
    label = f"{result.roughness_name} line {result.line}"
    if result.wheel_roughness_name is not None:
        label += f" + {result.wheel_roughness_name}"
    return cnossos_beside(result.header.params, f"{label} (the run's)", run_roughness_db(result), rule=rule)
