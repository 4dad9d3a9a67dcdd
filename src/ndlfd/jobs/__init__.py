"""The built-in jobs: ``ndlfd demo``, ``ndlfd reproduce`` and ``ndlfd evaluate``.

Each job runs the library end to end on built-in data and writes a folder of
results:

==============================  ===============================================
:func:`run_demo` (``demo``)     learn from synthetic squares and LASA, generate
:func:`reproduce`               the paper's Fig. 2, 3, 5 and 6, with a report
:func:`evaluate`                held-out LASA against peer baselines
==============================  ===============================================

The modules :mod:`~ndlfd.jobs.demo`, :mod:`~ndlfd.jobs.reproduction` and
:mod:`~ndlfd.jobs.evaluation` hold them; ``_report`` is their shared report
layer (Markdown tables, a folder written atomically).
"""

from . import demo, evaluation, reproduction
from .demo import run_demo
from .evaluation import evaluate
from .reproduction import reproduce

__all__ = ["demo", "evaluate", "evaluation", "reproduce", "reproduction", "run_demo"]
