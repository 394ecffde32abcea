"""Preparing a run (:func:`prepare_run`) and running it in one call (:func:`simulate`).

:func:`prepare_run` checks the inputs and the run-in (``history.run_in``), lays the roughness along the track
(``track_lines``), builds the loop's history with the contact model prepared on it (``history.run_history``) and
hands them to an :class:`~wheelrail.core.engine.run.InteractionRun`.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from wheelrail.core.engine.history import run_history, run_in
from wheelrail.core.engine.memory import check_run_memory
from wheelrail.core.engine.results import RunHeader, RunResult, StepState
from wheelrail.core.engine.run import InteractionRun
from wheelrail.core.engine.track_lines import TrackRoughness, track_roughness
from wheelrail.core.errors import WheelrailError
from wheelrail.core.models import ModelEntry, ModelTraits, model_entry
from wheelrail.core.parameters import ModelParameters, TrackNumerics
from wheelrail.core.wheel import checked_wheel_system

if TYPE_CHECKING:  # the roughness package is imported with the first set a run reads
    from wheelrail.core.roughness import RoughnessLike

__all__ = ["checked_inputs", "interaction_wheel", "irregular_surface", "prepare_run", "simulate"]


def checked_inputs(
    model: str, line, params: ModelParameters | None, run_in_length
) -> tuple[ModelEntry, ModelParameters, int, float, bool]:
    """The model's registry entry, the parameters (default: the paper's), the line number, the run-in length, m,
    and whether the run starts steady (``history.run_in``: None, the default run-in)."""
    entry = model_entry(model)
    params = ModelParameters() if params is None else params
    if not isinstance(params, ModelParameters):
        raise WheelrailError("params must be a wheelrail.core.parameters.ModelParameters")
    if isinstance(line, bool) or not isinstance(line, int | np.integer):
        raise WheelrailError(f"line must be an integer line number, got {line!r}")
    return entry, params, int(line), *run_in(params, run_in_length)


def irregular_surface(
    traits: ModelTraits, track: TrackRoughness, params: ModelParameters
) -> tuple[np.ndarray, np.ndarray | None, TrackRoughness]:
    """A run's discrete irregularities (``RunParameters.irregularities``) as its model meets them.

    They are checked against the run (``irregularities.check_irregularities``: the wheel's radius, the run's
    first and last wheel positions, the sleeper bay), their surface deviation laid on the rows of ``track`` by
    position (the chosen line is y = 0), and the model's law says what it is prepared on
    (``ContactLaw.irregular_surface``). Returns the lines the model is prepared on, the line added to its
    equivalent roughness (or None) and the roughness with the irregularities, as the run records it; without
    irregularities ``(track.lines, None, track)``.
    """
    run = params.run
    if not run.irregularities:
        return track.lines, None, track
    from wheelrail.core.engine.laws.base import law_class
    from wheelrail.core.irregularities import check_irregularities, surface_deviation, wheel_centre_trajectory

    dx, radius = run.element_size, params.contact.radius_along
    check_irregularities(
        run.irregularities,
        wheel_radius=radius,
        run_start=track.x_start,
        run_end=track.x_start + (track.n_steps - 1) * dx,
        sleeper_spacing=params.track.support.sleeper_spacing,
    )
    deviation = surface_deviation(run.irregularities, np.arange(track.lines.shape[1]) * dx, track.window_y,
                                  wheel_radius=radius)  # fmt: skip

    def centre_input() -> np.ndarray:
        line = deviation[track.centre_row]
        return line if run.irregularity_input == "raw" else wheel_centre_trajectory(line, dx, radius)

    lines, offset = law_class(traits).irregular_surface(track.lines, deviation, centre_input)
    return lines, offset, replace(track, lines=track.lines + deviation)


def interaction_wheel(wheel, params) -> tuple[tuple | None, str, dict | None]:
    """What ``prepare_run``'s ``wheel_system`` gives the loop and records in the run's header:
    ``(system, wheel_model, profile description)``.

    ``wheel``: None (the paper's 2-DOF wheel: ``(None, "2dof", None)``), a modal wheel's cross-section (a
    ``WheelProfile`` or ``OutlineProfile``: its clamped modes to 10 kHz, n = 0..10, cached as ``wheel_modes``,
    as ``modal_wheel.time_domain.modal_wheel_system`` at the run's time step, recorded as ``"modal"`` with
    ``profile.describe()``) or a ``(Phi, Gamma0, Gamma1)`` built by the caller (recorded as ``"given"``: its wheel
    is not known here).
    """
    if wheel is None:
        return None, "2dof", None
    from wheelrail.core.modal_wheel.modes import wheel_modes
    from wheelrail.core.modal_wheel.profile import OutlineProfile, WheelProfile
    from wheelrail.core.modal_wheel.time_domain import modal_wheel_system

    if isinstance(wheel, WheelProfile | OutlineProfile):
        return modal_wheel_system(wheel_modes(wheel), params.wheel, params.run.time_step), "modal", wheel.describe()
    return wheel, "given", None


def prepare_run(
    roughness: RoughnessLike,
    *,
    wheel_roughness: RoughnessLike | None = None,
    model: str = "hertz",
    line: int = 0,
    params: ModelParameters | None = None,
    length: float | None = None,
    run_in_length: float | None = None,
    keep_pressure: bool = True,
    track_numerics: TrackNumerics | None = None,
    wheel_system: tuple | None = None,
) -> InteractionRun:
    """Set up a wheel/rail interaction run.

    Parameters
    ----------
    roughness : RoughnessSet, str or path
        Roughness as a set of lines (a bundled set name, a CSV/NPZ path, or a ``RoughnessSet``): a rail set
        or a wheel set, the other surface smooth (paper 3.3), or the rail set when ``wheel_roughness`` is
        given. Heights are taken positive where the surface stands out, so for either kind r = height.
    wheel_roughness : RoughnessSet, str or path, optional
        A wheel set on the same wheel: the combined roughness r = r_rail + r_wheel (paper eq. 3's
        r = r_W - r_R with z downwards), paired by lateral position: the wheel set interpolated across onto
        the rail's lines (refused where it has no data, see ``track_lines.run_lines``); its lines repeat with
        its circumference, which must be within 1 % of 2 pi R of the rolling radius R
        (``inputs.ranges.check_wheel_circumference``). ``roughness`` must then be a rail set and this a wheel set
        (else one WheelrailError).
    model : str
        A registered contact model (``wheelrail.core.models.model_names()``).
    line : int
        Roughness line -M..M (of the rail set when a wheel set is added); for a model with a lateral window
        the line it is centred on.
    params : ModelParameters, optional
        Default: the paper's values (65 kN, 100 km/h, 1 mm elements). ``params.run.irregularities``: discrete
        irregularities on the run (a wheel flat, a joint, a weld, a squat), each model meeting them as its law
        says (:func:`irregular_surface`).
    length : float, optional
        Run length, m. Default: ``track_lines.usable_length`` (the rail data less the margins, or one wheel
        circumference: wheel data repeats around it).
    run_in_length : float, optional
        Run-in before step 0 on the roughness under step 0, m (discarded). Default: the run starts from the
        moving load's periodic steady state (``steady_start``: no start-up transient) and runs in for
        ``DEFAULT_RUN_IN_TIME`` (0.5 ms) at its speed. A run-in given starts from the preload at rest (history
        filled with P, the roughness faded in over its first half); so does the default where the sleeper bay
        is no whole number of elements, with 0.3 s (``history.default_run_in_length``).
    keep_pressure : bool
        Keep every pressure map in the result (steps x ny x nx float32), for models that have them.
    track_numerics : TrackNumerics, optional
        Numerics of the track's Green's functions (default ``TrackNumerics()``); the header records the fields
        that differ from the default.
    wheel_system : WheelProfile, OutlineProfile or tuple, optional
        Default the paper's 2-DOF wheel; a modal wheel's cross-section, or a ``(Phi, Gamma0, Gamma1)``
        (``modal_wheel.time_domain.modal_wheel_system``); the header says which (:func:`interaction_wheel`).

    Returns
    -------
    InteractionRun
        The run; no step computed yet (a steady start fills its history at the first step).

    Raises
    ------
    WheelrailError
        For an unknown model, a line outside the set, parameters outside the accepted ranges, a run that would
        not fit in memory or whose coupled step would be unstable, or a rail and wheel set that do not pair.

    See Also
    --------
    simulate : prepares and runs in one call.
    wheelrail.core.models.model_names : the registered contact models.
    wheelrail.core.roughness.load_roughness : reads a roughness set.

    References
    ----------
    .. [1] A. Pieringer, W. Kropp, D.J. Thompson, "Investigation of the dynamic contact filter effect in vertical
       wheel/rail interaction using a 2D and a 3D non-Hertzian contact model", Wear 271 (2011) 328-338.

    Examples
    --------
    A run prepared but not started; its steps are computed as they are asked for:

    >>> from wheelrail.core.engine import prepare_run
    >>> run = prepare_run("corrugated-rail", model="2d", line=0, length=0.2)
    >>> run.n_steps
    200
    >>> forces = [state.force for state in run.steps()]   # one StepState per step, N
    >>> len(forces), min(forces) > 0.0
    (200, True)
    """
    if track_numerics is not None and not isinstance(track_numerics, TrackNumerics):
        raise WheelrailError(
            f"prepare_run: track_numerics must be TrackNumerics or None, got {type(track_numerics).__name__}"
        )
    from wheelrail.core.inputs.numerics import numerics_changes

    if wheel_system is not None:  # the modal wheel's modules (and scipy's) load only for a run that uses them
        from wheelrail.core.modal_wheel.profile import OutlineProfile, WheelProfile

        if not isinstance(wheel_system, WheelProfile | OutlineProfile):
            wheel_system = checked_wheel_system(wheel_system)  # a caller's (Phi, Gamma0, Gamma1)
    entry, params, line, run_in_length, steady = checked_inputs(model, line, params, run_in_length)
    track, name, wheel_name = track_roughness(
        roughness,
        wheel_roughness,
        entry.traits,
        line,
        params,
        length,
        lambda run_length: check_run_memory(entry, params, run_length, run_in_length, keep_pressure),
    )
    lines, offset, track = irregular_surface(entry.traits, track, params)  # checked before the track is built
    wheel_system, wheel_model, wheel_profile = interaction_wheel(wheel_system, params)
    contact = entry.create()
    history, inputs = run_history(
        track, params, run_in_length, steady, contact, track_numerics, wheel_system, surface=(lines, offset)
    )
    header = RunHeader(
        model=entry.name,
        line=line,
        roughness_name=name,
        params=params,
        run_in_length=history.n_run_in * params.run.element_size,
        wheel_roughness_name=wheel_name,
        wheel_model=wheel_model,
        wheel_profile=wheel_profile,
        track_numerics=numerics_changes(track_numerics),
    )
    return InteractionRun(
        header=header,
        contact=contact,
        inputs=inputs,
        track=track,
        history=history,
        keep_pressure=keep_pressure,
    )


def simulate(
    roughness: RoughnessLike,
    *,
    model: str = "hertz",
    line: int = 0,
    params: ModelParameters | None = None,
    length: float | None = None,
    callback: Callable[[StepState], None] | None = None,
    cancel: threading.Event | None = None,
    progress: Callable[[int, int], None] | None = None,
    **options,
) -> RunResult:
    """Run the wheel/rail interaction and return the whole-run result.

    Parameters
    ----------
    roughness, model, line, params, length
        As for :func:`prepare_run`.
    callback : callable, optional
        ``callback(state)`` with the :class:`StepState` of every step.
    cancel : threading.Event, optional
        Setting it stops the run between steps; the steps done so far are returned.
    progress : callable, optional
        ``progress(done, total)`` now and then.
    **options
        The other keywords of :func:`prepare_run`.

    Returns
    -------
    RunResult
        Force, displacements, roughness, contact size (and pressure maps) per step, SI units.

    Raises
    ------
    WheelrailError
        For any input :func:`prepare_run` refuses, or if the contact model fails during the run.

    See Also
    --------
    prepare_run : the same run, stepped on demand.
    wheelrail.core.spectra.force.force_spectrum : the force's third-octave spectrum.

    Examples
    --------
    Half a metre of the bundled corrugated rail under the Hertz spring, at the paper's 100 km/h and 65 kN:

    >>> from wheelrail.core.engine import simulate
    >>> result = simulate("corrugated-rail", model="hertz", line=0, length=0.5)
    >>> result.force.size, result.time_step          # one step per 1 mm element: dt = 1 mm / (100 km/h), s
    (500, 3.6e-05)
    >>> round(float(result.force.mean()) / 1e3, 1)     # kN: the preload and the roughness's dynamic force
    65.2
    >>> result.loss_of_contact_steps, result.run_in_length   # the run-in after the steady start: 0.5 ms, m
    (0, 0.014)
    """
    run = prepare_run(roughness, model=model, line=line, params=params, length=length, **options)
    if cancel is not None:
        run._cancel = cancel
    return run.run(callback, progress)
