"""Stage 2: plain data + source map → a typed :class:`Spec`, with located diagnostics."""

from robospec.model.build import SpecModelResult, build_spec
from robospec.model.spec import Spec

__all__ = ["Spec", "SpecModelResult", "build_spec"]
