"""Test configuration.

Hypothesis runs derandomized by default, locally and on CI alike: the examples
are a fixed function of each test, so a green commit stays green and a red one
is red for everybody. Searching for new counterexamples is a separate, explicit
step: ``make test-explore`` (that is, ``NDLFD_HYPOTHESIS=explore``) loads the
exploring profile, which draws fresh random examples on every run and keeps the
failures it finds in ``.hypothesis/`` to replay them. A counterexample found
that way belongs in the suite as an explicit ``@example`` or known-answer test.
"""

import os

from hypothesis import settings

settings.register_profile("deterministic", derandomize=True, print_blob=True)
settings.register_profile("explore", print_blob=True)

_PROFILES = ("deterministic", "explore")
_profile = os.environ.get("NDLFD_HYPOTHESIS", "deterministic") or "deterministic"
if _profile not in _PROFILES:
    raise ValueError(
        f"NDLFD_HYPOTHESIS must be one of {', '.join(_PROFILES)}; got {_profile!r}"
    )
settings.load_profile(_profile)
