"""The contact laws as the run engine steps them: one object per run that owns its stepping.

``base``: :class:`~wheelrail.core.engine.laws.base.ContactLaw`, the interface the loop calls (advance a chunk, run in,
the steady law, the memory needs, the surface's input) and the per-step law of a model solved from Python;
``one_line``: the compiled one-line laws (``hertz*``, ``2d``); ``halfspace``: the ``3d`` law with its window, its
tabulated run-in and its pressure maps. A model's registry entry names its law (``ModelTraits.law``); adding a
compiled law is one module with a :class:`~wheelrail.core.engine.laws.base.CompiledLaw` subclass and one entry.
"""
