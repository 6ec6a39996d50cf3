"""Stage 2: plain data + source map → a typed :class:`Spec`, with located diagnostics.

The models are written with pydantic (robospec.model.spec and its neighbours); what stage 2
validates with, and returns, is their frozen form (robospec.model.frozen), which needs no
pydantic.
"""

from robospec.model.frozen import Spec
from robospec.model.validate import SpecModelResult, build_spec

__all__ = ["Spec", "SpecModelResult", "build_spec"]
