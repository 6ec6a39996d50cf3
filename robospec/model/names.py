"""The shapes of names in a spec, in one place that imports nothing.

The spec models check names against these patterns, the resolver tells globs from names with
them, and the authoring tools (``robospec new``, ``--uid``) and the narrowed JSON Schema use the
same ones, so a name one of them accepts the others accept too. Kept free of pydantic so the
``validate`` path and the authoring tools can import it cheaply.
"""

from __future__ import annotations

import re

UID_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.\-]{0,63}$"  # an agent's uid
NAME_PATTERN = r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,63}$"  # a group, keyframe, camera... name
PREFIX_PATTERN = r"^[A-Za-z0-9_.\-]{1,32}$"  # what a part's clashing names are given
GLOB_PATTERN = r"[*?\[]"  # a joint or link pattern holding one of these is a glob

GLOB = re.compile(GLOB_PATTERN)
