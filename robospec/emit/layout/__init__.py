"""Generated code laid out exactly as ``ruff format`` (black's style) would lay it out.

:mod:`.document` is the layout model (groups that break when they do not fit), :mod:`.literals`
writes strings and numbers, :mod:`.expressions` and :mod:`.statements` follow ruff's rules for
the Python the emitter writes (:mod:`.analysis` answers the questions those rules ask of an
expression, :mod:`.parentheses` says where Python needs parentheses), and :mod:`.imports`
orders imports as isort does. Nothing here runs ruff: it is a development tool, and the core
install stays light (docs/development.md weighs calling ruff or black instead, measured by
benchmarks/formatter.py); tests run the real ruff over every example spec's module and over
random code to prove the two agree.
"""

from robospec.emit.layout.statements import LINE_LENGTH, format_module

__all__ = ["LINE_LENGTH", "format_module"]
