"""A robot ManiSkill's loaders cannot load, as a located diagnostic (RS514) and a
:class:`~robospec.diagnostics.SpecError`, never a traceback.

ManiSkill reads the description when an environment loads the agent (``gym.make``), long after
``robospec.register`` or a built package's import registered it. Whatever its URDF or MJCF loader
raises there (a ``KeyError`` in ``_build_geom``, SAPIEN's ``invalid moment of inertia``) is one
:class:`~robospec.maniskill.crash.Crash`, told at the description element the loader was reading
(from its local variables), and :func:`load_failure` says it as ``robospec check`` does. The
agents ``register`` loads are guarded (:func:`guard`): their loading raises ``SpecError`` with
that diagnostic, the loader's exception as its cause.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robospec.diagnostics import Diagnostic, Location, SpecError, error
from robospec.maniskill.crash import Crash, Element, from_exception

if TYPE_CHECKING:  # register() imports this module on its warm path: no spec model there
    from robospec.checks.context import CheckContext

LOAD_FAILURE = "RS514"
# set on a guarded _load_articulation: a class guarded twice (register() again) is guarded once
_GUARDED = "_robospec_load_guard"


def guard(agent_cls: type, spec_file: Path) -> None:
    """Make loading ``agent_cls`` (compiled from ``spec_file``) raise ``SpecError`` with a
    located RS514 where ManiSkill's loaders raise."""
    _guard(agent_cls, lambda uid, exc: located(spec_file, uid, exc))


def guard_described(agent_cls: type) -> None:
    """:func:`guard` for an agent of a built package, whose spec it does not carry: RS514 at
    the element of the description file the agent loads (the package's copy, lines kept)."""
    _guard(agent_cls, lambda uid, exc: [_in_description(agent_cls, uid, exc)])


def _guard(agent_cls: type, diagnose: Callable[[str, BaseException], list[Diagnostic]]) -> None:
    original = agent_cls._load_articulation  # type: ignore[attr-defined]
    if getattr(original, _GUARDED, False):
        return

    @functools.wraps(original)
    def _load_articulation(self: Any, *args: Any, **kwargs: Any) -> Any:
        try:
            return original(self, *args, **kwargs)
        except SpecError:
            raise
        except Exception as exc:
            raise SpecError(diagnose(str(self.uid), exc)) from exc

    setattr(_load_articulation, _GUARDED, True)
    agent_cls._load_articulation = _load_articulation  # type: ignore[attr-defined]


def _in_description(agent_cls: type, uid: str, exc: BaseException) -> Diagnostic:
    """RS514 at the element the loader was reading, found by its tag and name in the file."""
    crash = from_exception(exc)
    path = getattr(agent_cls, "urdf_path", None) or getattr(agent_cls, "mjcf_path", None) or ""
    element = crash.element
    line = None
    if element is not None and path:
        try:
            line = element.line or _line_in(Path(path).read_text(), element)
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


def located(spec_file: Path, uid: str, exc: BaseException) -> list[Diagnostic]:
    """The diagnostics of a load that raised ``exc``: RS514 at the element, from the spec
    compiled again (only now, once it failed); its errors if it no longer compiles."""
    from robospec.pipeline import compile_spec

    crash = from_exception(exc)
    result = compile_spec(spec_file)
    if result.context is None:
        errors = [d for d in result.diagnostics if d.is_error]
        return errors or [
            error(
                Location(str(spec_file)),
                LOAD_FAILURE,
                f"ManiSkill cannot load '{uid}': {crash.what} ({crash.where()})",
            )
        ]
    return [load_failure(result.context, uid, crash)]


def description_location(context: CheckContext, element: Element | None) -> Location:
    """Where ``element`` is written in the robot description, else the spec's ``description``
    key."""
    if element is not None:
        line = _element_line(context, element)
        if line is not None:
            return context.at_description(line)
    return context.key(("description",))


def described_name(context: CheckContext, element: Element) -> str:
    """The element's name as the description writes it: ManiSkill names PhysX joints and links
    ``scene-0-<uid>_<name>``, so a name the description does not know is matched by the
    longest known name it ends with."""
    facts = context.description
    known = [link.name for link in facts.links] + [joint.name for joint in facts.joints]
    if element.name in known:
        return element.name
    endings = [name for name in known if element.name.endswith("_" + name)]
    return max(endings, key=len) if endings else element.name


def _element_line(context: CheckContext, element: Element) -> int | None:
    facts = context.description
    name = described_name(context, element)
    if element.tag == "link":
        found = next((link for link in facts.links if link.name == name), None)
        if found is not None:
            return found.line
    if element.tag == "joint":
        joint = next((j for j in facts.joints if j.name == name), None)
        if joint is not None:
            return joint.line
    return _search(context, Element(element.tag, name))


def _search(context: CheckContext, element: Element) -> int | None:
    """The line of the first ``<tag name="name">`` in the description's text."""
    try:
        text = context.robot.description.read_text()
    except OSError:
        return None
    return _line_in(text, element)


def _line_in(text: str, element: Element) -> int | None:
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


def _element_words(context: CheckContext, crash: Crash) -> str:
    element = crash.element
    if element is None:
        return ""
    return f' at <{element.tag} name="{described_name(context, element)}">'


def load_failure(context: CheckContext, uid: str, crash: Crash, also: str = "") -> Diagnostic:
    """RS514: ManiSkill cannot load the robot, at the element its loader was reading. ``also``
    ends the hint (check: that the other robots were still checked)."""
    return error(
        description_location(context, crash.element),
        LOAD_FAILURE,
        f"ManiSkill cannot load '{uid}': {crash.what}{_element_words(context, crash)} "
        f"({crash.where()})",
        "the loader rejects the description here: mend the element (robospec validate tells "
        "what it knows about the description before anything loads)"
        + (f"; {also}" if also else ""),
    )
