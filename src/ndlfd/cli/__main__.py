"""``python -m ndlfd.cli``: the ``ndlfd`` command line."""

import sys

from ._main import main

sys.exit(main())
