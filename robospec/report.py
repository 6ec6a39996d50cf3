"""The old import path of the diagnostic renderers, kept while callers move to
:mod:`robospec.reporting` (one module per format)."""

from __future__ import annotations

from robospec.reporting import render, summary

__all__ = ["render", "summary"]
