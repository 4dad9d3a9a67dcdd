"""The reduction stage: key points of a trajectory by n-D Douglas–Peucker.

Users call :func:`ndlfd.simplify` and :func:`ndlfd.simplify_many` (the same
functions, re-exported there); the learner and the command line import them,
and the distance registry, from here.

=====================  ==========================================================
module                 what it holds
=====================  ==========================================================
``_simplify``          the checked doorway: :func:`simplify`,
                       :func:`simplify_many`, the distance registry
                       (:data:`DISTANCES`), the threads
``_kernels``           the column-major numba scans and epsilon-mode kernels,
                       and every distance's key
``_generic``           the row-major any-mode scan (``"paper"``, and the budget's)
``_tree``              bounding boxes of point blocks: exact pruning of long
                       lopsided scans
``_exact``             the leave-one-out line and segment keys, monotone in each
                       coordinate, and their exact box bounds (what lets the
                       tree skip ties)
``_budget``            the ``n_points`` budget
=====================  ==========================================================

Imports run one way: ``_simplify`` over ``_budget`` over ``_generic`` over
``_kernels`` over ``_tree`` over ``_exact``.
"""

from ._simplify import DISTANCES, DistanceMode, simplify, simplify_many

__all__ = ["DISTANCES", "DistanceMode", "simplify", "simplify_many"]
