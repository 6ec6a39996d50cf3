"""RS514-RS517: a robot, a control mode or a check that crashed ManiSkill or SAPIEN, as a located
diagnostic instead of a traceback (or a dead process) that loses every other robot's results.

- RS514: ManiSkill cannot load the robot: every control mode fails the same way while the
  description is read (SAPIEN's ``invalid moment of inertia`` assertion, a ``<transmission>``
  its URDF parser cannot read, an MJCF height field). At the description element the loader
  was reading when it can be told, else at the spec's ``description:``.
- RS515: checking the robot killed the process (a segmentation fault or an abort in SAPIEN's or
  PhysX's native code). ``robospec check`` runs each robot in a worker process, so the others
  are still checked; the diagnostic says what the check was doing, the last ManiSkill/SAPIEN
  frame, and what SAPIEN said before it died (missing mesh files, for example).
- RS516: one control mode cannot be made (its controllers crash ManiSkill) while the others
  load: at the mode, and the other modes are still checked.
- RS517: a check crashed inside ManiSkill or SAPIEN while stepping the robot: at the mode it
  was running.

Each names the ManiSkill/SAPIEN file and line (relative to the package) and whether the crash is
upstream's code or robospec's own (then it asks for a report).
"""

from __future__ import annotations

from collections.abc import Sequence

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, Location, error
from robospec.maniskill.upstream_output import UpstreamMessage
from robospec.physics.crash import USER, Crash, Element

OTHERS_CHECKED = "every other robot was still checked"


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
    from lxml import etree

    try:
        text = context.robot.description.read_text()
        root = etree.fromstring(text.encode("utf-8"))
    except (OSError, ValueError, etree.XMLSyntaxError):
        return None
    for found in root.iter(element.tag):
        if found.get("name") == element.name:
            return found.sourceline
    return None


def _element_words(context: CheckContext, crash: Crash) -> str:
    element = crash.element
    if element is None:
        return ""
    return f' at <{element.tag} name="{described_name(context, element)}">'


def load_failure(context: CheckContext, uid: str, crash: Crash) -> Diagnostic:
    return error(
        description_location(context, crash.element),
        "RS514",
        f"ManiSkill cannot load '{uid}': {crash.what}{_element_words(context, crash)} "
        f"({crash.where()})",
        "the loader rejects the description here: mend the element (robospec validate tells "
        f"what it knows about the description before anything loads); {OTHERS_CHECKED}",
    )


def process_died(
    context: CheckContext,
    uid: str,
    crash: Crash,
    doing: str,
    said: Sequence[UpstreamMessage] = (),
) -> Diagnostic:
    # Python code cannot kill the process: native code did, below the last Python frame
    frame = crash.frame
    if frame is None:
        where = "in native code"
    elif crash.upstream:
        where = f"in native code below {frame.owner}'s {frame.describe()}: upstream's crash"
    elif frame.owner == USER:
        where = f"in native code below {frame.describe()}, the spec's own code (a hook)"
    else:
        owner = f"{frame.owner}'s " if frame.owner else ""
        where = f"in native code below {owner}{frame.describe()}"
    last_words = _last_words(said)
    return error(
        context.key(("description",)),
        "RS515",
        f"checking '{uid}' killed the check process: {crash.what} while {doing}, {where}"
        + (f"; before it: {last_words}" if last_words else ""),
        "what SAPIEN said before the crash often names its cause (a missing mesh, an invalid "
        f"inertia); {OTHERS_CHECKED}",
    )


def _last_words(said: Sequence[UpstreamMessage]) -> str:
    """SAPIEN's and ManiSkill's errors (else warnings) before the crash, most said first."""
    for levels in (("error", "critical"), ("warning",)):
        chosen = [m for m in said if m.level in levels]
        if chosen:
            chosen.sort(key=lambda m: -m.count)
            shown = "; ".join(
                f"{m.source} {m.level}: {m.text}"
                + (f" (e.g. {m.example})" if m.example else "")
                + (f" ({m.count}x)" if m.count > 1 else "")
                for m in chosen[:3]
            )
            return shown + (f"; and {len(chosen) - 3} more" if len(chosen) > 3 else "")
    return ""


def mode_failure(context: CheckContext, mode: str, crash: Crash) -> Diagnostic:
    return error(
        context.key(("control_modes", mode)),
        "RS516",
        f"control mode '{mode}' cannot be made: {crash.what} ({crash.where()})",
        "ManiSkill crashes building this mode's controllers; the other modes were checked",
    )


def check_failure(context: CheckContext, check: str, mode: str | None, crash: Crash) -> Diagnostic:
    where = context.key(("control_modes", mode)) if mode else context.key(("description",))
    in_mode = f" in mode {mode}" if mode else ""
    return error(
        where,
        "RS517",
        f"the {check} check crashed{in_mode}: {crash.what} ({crash.where()})",
        "ManiSkill or SAPIEN raised while stepping the robot; the other checks were run",
    )
