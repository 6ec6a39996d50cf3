"""The loading of a robospec agent, guarded: what ManiSkill's loaders raise while an
environment loads it becomes a :class:`~robospec.diagnostics.SpecError` with a located RS514,
its cause the loader's exception, never a bare traceback.

``robospec.register`` guards the agents it registers, located through their specs
(robospec.output.load_errors: the diagnostic ``robospec check`` gives); a built package, where
robospec is installed, guards its own through :func:`guard_described`, located in the
description file the agent loads (the package's copy keeps every element on its line).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robospec.diagnostics import Diagnostic, Location, SpecError, error
from robospec.diagnostics.codes import LOAD_FAILURE
from robospec.maniskill.crash import Element, from_exception

if TYPE_CHECKING:
    from mani_skill.agents.base_agent import BaseAgent

# set on a guarded _load_articulation: a class guarded twice (register() again) is guarded once
_GUARDED = "_robospec_load_guard"


def guard_loading(
    agent_cls: type[BaseAgent], diagnose: Callable[[str, BaseException], list[Diagnostic]]
) -> None:
    """Make loading ``agent_cls`` raise ``SpecError(diagnose(uid, exception))`` where
    ManiSkill's loaders raise."""
    original = agent_cls._load_articulation
    if getattr(original, _GUARDED, False):
        return

    @functools.wraps(original)
    def _load_articulation(self: BaseAgent, *args: Any, **kwargs: Any) -> None:
        try:
            return original(self, *args, **kwargs)
        except SpecError:
            raise
        except Exception as exc:
            raise SpecError(diagnose(str(self.uid), exc)) from exc

    setattr(_load_articulation, _GUARDED, True)
    agent_cls._load_articulation = _load_articulation  # type: ignore[method-assign]


def guard_described(agent_cls: type[BaseAgent]) -> None:
    """:func:`guard_loading` for an agent of a built package, which carries no spec: RS514 at
    the element of the description file the agent loads (the package's copy, lines kept)."""
    guard_loading(agent_cls, lambda uid, exc: [_in_description(agent_cls, uid, exc)])


def _in_description(agent_cls: type, uid: str, exc: BaseException) -> Diagnostic:
    """RS514 at the element the loader was reading, found by its tag and name in the file."""
    crash = from_exception(exc)
    path = getattr(agent_cls, "urdf_path", None) or getattr(agent_cls, "mjcf_path", None) or ""
    element = crash.element
    line = None
    if element is not None and path:
        try:
            line = element.line or line_in(Path(path).read_text(), element)
        except OSError:
            line = None
    # the name as the description writes it, not PhysX's scene-0-<uid>_<name>
    shown = element.name.split(f"{uid}_", 1)[-1] if element is not None else ""
    words = f' at <{element.tag} name="{shown}">' if element is not None else ""
    return error(
        Location(str(path), line or 1),
        LOAD_FAILURE,
        f"ManiSkill cannot load '{uid}': {crash.what}{words} ({crash.where()})",
        "the loader rejects the description here: mend the element (robospec validate of the "
        "spec tells what it knows about the description before anything loads)",
    )


def line_in(text: str, element: Element) -> int | None:
    """The line of the first ``<tag name="name">`` in ``text``."""
    from lxml import etree

    try:
        root = etree.fromstring(text.encode("utf-8"))
    except (ValueError, etree.XMLSyntaxError):
        return None
    for found in root.iter(element.tag):
        if found.get("name") == element.name:
            return found.sourceline
    # ManiSkill names PhysX links and joints scene-0-<uid>_<name>: the longest name it ends with
    endings = [
        (len(str(found.get("name"))), found.sourceline)
        for found in root.iter(element.tag)
        if found.get("name") and element.name.endswith("_" + str(found.get("name")))
    ]
    return max(endings)[1] if endings else None
