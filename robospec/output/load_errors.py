"""A robot ManiSkill's loaders cannot load, as a located diagnostic (RS514) and a
:class:`~robospec.diagnostics.SpecError`, never a traceback.

ManiSkill reads the description when an environment loads the agent (``gym.make``), long after
``robospec.register`` or a built package's import registered it. Whatever its URDF or MJCF loader
raises there (a ``KeyError`` in ``_build_geom``, SAPIEN's ``invalid moment of inertia``) is one
:class:`~robospec.maniskill.crash.Crash`, told at the description element the loader was reading
(from its local variables), and :func:`load_failure` says it as ``robospec check`` does. The
agents ``register`` loads are guarded (:func:`guard`): their loading raises ``SpecError`` with
that diagnostic, the loader's exception as its cause (robospec.maniskill.load_guard, which a
built package's agents use too).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import LOAD_FAILURE
from robospec.maniskill.crash import Crash, Element, from_exception
from robospec.maniskill.load_guard import guard_loading, line_in

if TYPE_CHECKING:  # register() imports this module on its warm path: no spec model there
    from mani_skill.agents.base_agent import BaseAgent

    from robospec.checks.context import CheckContext


def guard(agent_cls: type[BaseAgent], spec_file: Path) -> None:
    """Make loading ``agent_cls`` (compiled from ``spec_file``) raise ``SpecError`` with a
    located RS514 where ManiSkill's loaders raise."""
    guard_loading(agent_cls, lambda uid, exc: located(spec_file, uid, exc))


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
    return line_in(text, element)


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
