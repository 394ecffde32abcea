"""Inputs and their ranges: what a user can set, what each number may be, and the checks that say so.

The modules, each imported by its path (the package imports none of them):

* :mod:`.declared`: the user-facing inputs, each declared once (key, place in ``ModelParameters``, unit, label,
  group), from which the command line's options, the explorer's fields and the error wording derive;
* :mod:`.ranges`: the accepted range of every physical input, with its reason, and the rules that relate inputs
  to each other (the patch against the radii, a wheel set's circumference);
* :mod:`.checks`: the value checks every module of core uses, each one :class:`~wheelrail.core.errors.WheelrailError`
  line naming the value, its unit and what it got.

The model's parameters themselves, the frozen dataclasses that validate against these ranges, are
:mod:`wheelrail.core.parameters`.
"""
