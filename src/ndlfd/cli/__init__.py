"""The ``ndlfd`` command line.

Every sub-command turns an :class:`~ndlfd.NdlfdError` (and a file-system error)
into one line on standard error and exit status 2, naming the command-line flag
at fault; an :class:`~ndlfd.NdlfdWarning` is one line too. Settings are checked
against their documented ranges before any work starts (and against the data
as soon as it is read), output paths before anything is computed. Outputs are
written atomically, so a failed run never leaves a half-written file behind.

**Where each part lives.** ``_options`` holds what every command shares (the
parser class, flag parsing and range checks, output checks, the column mapping
flags, reading demonstrations with them, the one-line reports); each command is
one module: ``_simplify``, ``_fit``, ``_generate``, ``_plot`` and ``_jobs``
(``demo``, ``reproduce``, ``evaluate``); ``_main`` builds the parser and runs
:func:`main`. A new command is a module with an ``add_<command>(sub)`` function
that adds its sub-parser (flags, help, ``set_defaults(func=...)``) using the
shared options, called from ``_main.build_parser``.
"""

from ._main import build_parser, main

__all__ = ["build_parser", "main"]
