"""A uid given outside a spec (``robospec import --uid``, ``robospec new --uid``), checked
against the spec model's own pattern before anything is written."""

from __future__ import annotations

import re

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import INVALID_IDENTIFIER
from robospec.model.names import UID_PATTERN


def invalid_uid(uid: str, at: Location | None = None) -> Diagnostic | None:
    """RS105 when ``uid`` could not be a spec's uid, else None; reported at ``at`` (default:
    ``<uid>``)."""
    if re.match(UID_PATTERN, uid):
        return None
    return error(
        at or Location("<uid>"),
        INVALID_IDENTIFIER,
        f"invalid uid {uid!r}",
        "use letters, digits, '_', '-' and '.', starting with a letter or digit",
    )
