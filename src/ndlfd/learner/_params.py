"""The parameters of KeypointHMM: their names, their checks, their JSON form."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .._errors import NotFittedError, ValidationError
from .._validation import (
    check_n_time_bins,
    check_nonnegative_scalar,
    check_positive_int,
)
from ..dp import DISTANCES
from ._decoding import DECODERS, STARTS
from ._generation import GENERATIONS
from ._spec import NORMALIZATIONS
from ._templates import seed_word

__all__ = [
    "PARAM_NAMES",
    "ParamsMixin",
    "check_fitted",
    "check_params",
    "jsonable",
    "same",
]

#: The constructor parameters, in order.
PARAM_NAMES = (
    "groups",
    "levels",
    "epsilon",
    "n_time_bins",
    "n_points",
    "distance",
    "normalization",
    "weights",
    "pseudo_transition",
    "pseudo_emission",
    "start",
    "generation",
    "decoder",
    "derive_velocity",
    "n_jobs",
    "max_templates",
    "match_window",
    "n_routes",
    "route_groups",
    "frame_hands",
    "random_state",
)

#: Parameters named by a registry: an unknown name lists the choices.
_CHOICES = {
    "normalization": NORMALIZATIONS,
    "start": STARTS,
    "generation": GENERATIONS,
    "decoder": DECODERS,
    "distance": DISTANCES,
}


def check_params(p: Mapping) -> None:
    """Check the parameters as :meth:`KeypointHMM.fit` does before reading data.

    ``ndlfd fit`` calls it before it connects to a scheduler and reads files.

    Parameters
    ----------
    p : mapping
        Every name of :data:`PARAM_NAMES` (``KeypointHMM.get_params()``).

    Raises
    ------
    ValidationError
        A value out of its range or choices.
    """
    for name, registry in _CHOICES.items():
        registry.get(p[name])
    if p["n_points"] is None:
        check_nonnegative_scalar(p["epsilon"], "epsilon")
    else:
        check_positive_int(p["n_points"], "n_points", minimum=2)
    check_n_time_bins(p["n_time_bins"], "n_time_bins")
    if p["pseudo_transition"] is not None:
        check_nonnegative_scalar(p["pseudo_transition"], "pseudo_transition")
    check_nonnegative_scalar(p["pseudo_emission"], "pseudo_emission")
    if p["n_jobs"] is not None:
        check_positive_int(p["n_jobs"], "n_jobs")
    if p["max_templates"] is not None:
        check_positive_int(p["max_templates"], "max_templates")
    w = check_nonnegative_scalar(p["match_window"], "match_window")
    if w > 0.5:
        raise ValidationError(
            f"match_window must be between 0 and 0.5; got {p['match_window']!r}"
        )
    if p["n_routes"] is not None:
        check_positive_int(p["n_routes"], "n_routes")
    rg = p["route_groups"]
    if rg is not None and (
        isinstance(rg, str) or not all(isinstance(g, str) for g in rg) or len(rg) == 0
    ):
        raise ValidationError(
            "route_groups must be a non-empty list of group names, e.g."
            f" ['position']; got {rg!r}"
        )
    fh = p["frame_hands"]
    if fh is not None and not (
        isinstance(fh, Mapping)
        and all(
            isinstance(k, str)
            and not isinstance(v, str)
            and isinstance(v, (list, tuple))
            and len(v) > 0
            and all(isinstance(h, str) for h in v)
            for k, v in fh.items()
        )
    ):
        raise ValidationError(
            "frame_hands must map a frame's name to a non-empty list of hands,"
            f" e.g. {{'socket': ['left'], 'peg': ['right']}}; got {fh!r}"
        )
    rs = p["random_state"]
    if not (rs is None or isinstance(rs, (np.random.Generator, np.random.RandomState))):
        seed_word(rs)  # checks an int (cheap)
    if p["weights"] is not None and not isinstance(p["weights"], Mapping):
        raise ValidationError(
            f"weights must be a mapping of group to weight; got {p['weights']!r}"
        )


def same(a, b) -> bool:
    """``a == b`` for parameter values that may be arrays or Generators."""
    try:
        return bool(a == b)
    except (ValueError, TypeError):
        return a is b


def jsonable(params: dict) -> dict:
    """The parameters as JSON values (a Generator ``random_state`` is dropped)."""
    out = {}
    for k, v in params.items():
        if isinstance(v, np.generic):
            v = v.item()
        if isinstance(v, Mapping):
            v = {
                str(kk): (vv.item() if isinstance(vv, np.generic) else vv)
                for kk, vv in v.items()
            }
        if k == "random_state" and not (v is None or isinstance(v, int)):
            v = None  # a Generator is not stored; generation is deterministic
        out[k] = v
    return out


def check_fitted(est) -> None:
    """Raise :class:`~ndlfd.NotFittedError` unless ``est`` was fitted."""
    if not hasattr(est, "model_"):
        raise NotFittedError(
            f"this {type(est).__name__} is not fitted yet; call fit(demos) first"
        )


class ParamsMixin:
    """The scikit-learn parameter protocol over :data:`PARAM_NAMES`."""

    def get_params(self, deep: bool = True) -> dict:
        """Return the constructor parameters (scikit-learn convention)."""
        return {k: getattr(self, k) for k in PARAM_NAMES}

    def set_params(self, **params):
        """Set constructor parameters (scikit-learn convention)."""
        for k, v in params.items():
            if k not in PARAM_NAMES:
                raise ValidationError(
                    f"unknown parameter {k!r}; expected one of: "
                    + ", ".join(PARAM_NAMES)
                )
            setattr(self, k, v)
        return self

    def __repr__(self) -> str:
        defaults = type(self)().get_params()
        changed = {
            k: v for k, v in self.get_params().items() if not same(v, defaults[k])
        }
        inner = ", ".join(f"{k}={v!r}" for k, v in changed.items())
        return f"{type(self).__name__}({inner})"
