"""The numbers of a description attribute (``pos="0 0 0.1"``), read one way for every reader."""

from __future__ import annotations

import math


def finite_numbers(text: str | None, count: int | None = None) -> tuple[float, ...] | None:
    """The numbers of an attribute, or None when it is absent, malformed, not finite or not
    ``count`` numbers long."""
    if text is None:
        return None
    try:
        values = tuple(float(part) for part in text.split())
    except ValueError:
        return None
    if count is not None and len(values) != count:
        return None
    return values if all(math.isfinite(v) for v in values) else None
