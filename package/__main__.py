"""``python -m wheelrail``: the ``wheelrail`` command."""

import sys

from wheelrail.cli import main

sys.exit(main())
