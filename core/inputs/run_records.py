"""A run's discrete irregularities as ``RunParameters`` holds them: checked (:func:`check_run_irregularities`), and
written to and read from the plain dicts of ``parameters.as_dict`` (each with its ``kind``) that headers,
recordings and cache keys hold (:func:`tagged_run`, :func:`untagged_run`).

The irregularities' package (``wheelrail.core.irregularities``, compiled code) is imported only for a run that has
some, so that parameters stay cheap to build; this module imports no other input module (``parameters`` imports
it).
"""

from __future__ import annotations

from wheelrail.core.errors import Blame, WheelrailError

__all__ = ["IRREGULARITY_INPUT_VALUES", "check_run_irregularities", "tagged_run", "untagged_run"]

# what the Hertz models are driven by over an irregularity, the default first (declared.CHOICES' irregularity_input)
IRREGULARITY_INPUT_VALUES = ("trajectory", "raw")


def check_run_irregularities(run) -> None:
    """Check a ``RunParameters``' ``irregularity_input`` (the choice of that key) and ``irregularities`` (each a
    ``WheelFlat``, ``RailJoint``, ``DippedWeld`` or ``Squat``; held as a tuple), else one WheelrailError."""
    if run.irregularity_input not in IRREGULARITY_INPUT_VALUES:
        raise WheelrailError(
            f"must be one of {', '.join(IRREGULARITY_INPUT_VALUES)}",
            Blame("irregularity_input", run.irregularity_input),
        )
    if run.irregularities != ():
        from wheelrail.core.irregularities.shapes import checked_items

        object.__setattr__(run, "irregularities", checked_items(run.irregularities, "RunParameters.irregularities"))


def tagged_run(params, values: dict) -> dict:
    """``values`` (``dataclasses.asdict`` of ``params``, a ``ModelParameters`` or a ``RunParameters``) with the
    run's irregularities each as ``irregularities.shapes.as_record`` writes it (its ``kind`` and fields); a run
    without irregularities at the default input leaves both keys out, so that its dict, and every cache key and
    record made of it, stays what it was before runs had irregularities. Other parameters as they are."""
    run = getattr(params, "run", params)
    items = getattr(run, "irregularities", None)
    target = values.get("run", values)
    if items is None or not isinstance(target, dict):
        return values
    if not items and run.irregularity_input == IRREGULARITY_INPUT_VALUES[0]:
        target.pop("irregularities", None)
        target.pop("irregularity_input", None)
    elif items:
        from wheelrail.core.irregularities.shapes import as_record

        target["irregularities"] = [as_record(item) for item in items]
    return values


def untagged_run(cls: type, values: dict) -> dict:
    """The keyword arguments ``values`` of ``cls`` with a ``RunParameters``' irregularities read back from their
    records (``irregularities.shapes.from_record``)."""
    if cls.__name__ != "RunParameters" or not values.get("irregularities"):
        return values
    from wheelrail.core.irregularities.shapes import from_record

    if not isinstance(values["irregularities"], list | tuple):
        raise WheelrailError("RunParameters: irregularities must be a list of records")
    return {**values, "irregularities": tuple(from_record(item) for item in values["irregularities"])}
