"""wheelrail: time-domain vertical wheel/rail interaction and the dynamic contact filter.

The model of Pieringer, Kropp & Thompson, "Investigation of the dynamic contact filter effect in vertical
wheel/rail interaction using a 2D and a 3D non-Hertzian contact model", Wear 271 (2011) 328-338.

Sub-packages: ``wheelrail.core`` (physics and data, no GUI), ``wheelrail.explorer`` (the browser GUI) and
``wheelrail.sample_data`` (the bundled roughness sets); ``wheelrail.cli`` is the ``wheelrail`` command. This
package itself imports nothing, so that importing any of them stays cheap.
"""

__version__ = "0.1.0"  # the one place the version is written (pyproject.toml reads it)
