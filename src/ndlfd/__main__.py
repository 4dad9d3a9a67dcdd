"""``python -m ndlfd``: the ``ndlfd`` command line (the same as ``ndlfd``)."""

import sys

from .cli import main

sys.exit(main())
