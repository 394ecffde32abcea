"""wheelrail.core: physics and data of vertical wheel/rail interaction (no GUI imports).

The model is the one of Pieringer, Kropp & Thompson, "Investigation of the dynamic contact filter effect in
vertical wheel/rail interaction using a 2D and a 3D non-Hertzian contact model", Wear 271 (2011) 328-338.
All quantities are SI (m, s, N, Pa, kg) inside the package.
"""

from wheelrail.core.errors import WheelrailError

__all__ = ["WheelrailError"]
