"""The learner: :class:`KeypointHMM` and the stages it composes.

=====================  ==========================================================
module                 what it holds
=====================  ==========================================================
``_estimator``         :class:`KeypointHMM`: parameters, ``fit``, ``generate``,
                       ``sample``, ``decode``/``timing``, ``save``/``load``
``_params``            the parameters' names and checks
``_spec``              the demonstration spec: groups, levels, the scaler from
                       range statistics, preparing and reducing one
                       demonstration (fit and generation)
``_passes``            the fit's two passes (ranges; statistics)
``_stats``             the fit statistics (:class:`RangeStats`, :class:`FitStats`)
``_exact``             exact sums (integer limbs)
``_fit_kernels``       compiled per-demonstration work of a fit (extremes,
                       limbs, segment states), bit for bit the numpy code
``_templates``         which demonstrations are kept whole (templates)
``_segments``          the key-point HMM and the segment model
``_decoding``          decoders (:data:`DECODERS`)
``_generation``        the plan, the band and the generations (:data:`GENERATIONS`)
``_sampling``          drawing paths (``sample``): route, skeleton (FFBS), weights
``_blend``             alignment to the skeleton and blending
``_conditioning``      start/goal weights and pinning
``_persist``           saving and loading, one reader per format version
=====================  ==========================================================
"""

from ._blend import MATCH_WINDOW
from ._conditioning import minimum_jerk, pin_offset
from ._decoding import DECODERS, STARTS
from ._estimator import KeypointHMM
from ._generation import GENERATIONS
from ._params import check_params
from ._routes import demo_routes, route_columns
from ._spec import AUTO_GROUPS, DEFAULT_LEVELS, NORMALIZATIONS, resolve_groups
from ._stats import FitStats, RangeStats

__all__ = [
    "AUTO_GROUPS",
    "DECODERS",
    "DEFAULT_LEVELS",
    "GENERATIONS",
    "MATCH_WINDOW",
    "NORMALIZATIONS",
    "STARTS",
    "FitStats",
    "KeypointHMM",
    "RangeStats",
    "check_params",
    "demo_routes",
    "minimum_jerk",
    "pin_offset",
    "resolve_groups",
    "route_columns",
]
