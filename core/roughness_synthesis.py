"""Former home of :mod:`wheelrail.core.roughness.synthesis`, kept so that its import path and
``python3 -m wheelrail.core.roughness_synthesis --out sample_data`` (the name the bundled sets' descriptions
carry) keep working: importing this module gives the synthesis module itself."""

import sys

from wheelrail.core.roughness import synthesis

if __name__ == "__main__":
    sys.exit(synthesis.main())
else:
    sys.modules[__name__] = synthesis
