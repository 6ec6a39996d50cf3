"""When a spec may take a uid ManiSkill already registers (the uids themselves come from the
installed ManiSkill: :func:`robospec.maniskill.installed.registered_uids`). A spec may not reuse
one: ManiSkill's ``register_agent`` would skip the spec's class with only a warning — unless the
spec or the caller says the replacement is on purpose (:func:`override_allowed`)."""

from __future__ import annotations

Overrides = bool | frozenset[str]
"""Uids a caller lets specs take over (``register(..., override=...)``): True for any."""


def override_allowed(uid: str, declared: bool, overrides: Overrides) -> bool:
    """Whether a spec's agent may replace one already registered under ``uid``: the spec
    declares ``override: true``, or the caller allows it for this uid or for every uid."""
    return declared or overrides is True or (isinstance(overrides, frozenset) and uid in overrides)
