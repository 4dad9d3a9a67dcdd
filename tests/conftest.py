"""Test configuration.

On CI (``CI`` set in the environment) hypothesis runs derandomized, so a green
commit stays green; locally it explores new examples on every run and keeps
failures in ``.hypothesis/`` to replay them.
"""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("dev", print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") else "dev")
