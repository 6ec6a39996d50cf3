"""RS522: ManiSkill or SAPIEN reported an error while ``robospec check`` ran the robot.

What ManiSkill and SAPIEN print while a robot is checked is gathered per robot
(:mod:`robospec.maniskill.upstream_output`) and listed under its table. A message said at level
``error`` or ``critical`` — a collision hull that could not be built, a tendon that could not be
created, a mesh that failed to load — is also a finding of its own, an error: the robot loaded,
but not as its description says. It is located where robospec can trace it: at the element of
the description that names the file the message names, else at the spec's ``description``.

Passing: the Panda: SAPIEN says nothing above a warning.
Failing: a description whose collision mesh SAPIEN cannot turn into a hull: SAPIEN logs an
error naming the file, and RS522 points at the ``<collision>`` that names it.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import PurePath

from robospec.checks.context import CheckContext
from robospec.diagnostics import Location, error
from robospec.diagnostics.codes import SIMULATOR_ERROR
from robospec.maniskill.upstream_output import UpstreamMessage
from robospec.physics.findings import Finding, Status

NAME = "upstream"
LEVELS = ("error", "critical", "fatal")


def findings(context: CheckContext, messages: Sequence[UpstreamMessage]) -> list[Finding]:
    """One failing finding per distinct error or critical message."""
    found = []
    for message in messages:
        if message.level.lower() not in LEVELS:
            continue
        at = _traced(context, message) or context.key(("description",))
        said = message.text.replace("<path>", message.example or "<path>")
        times = f" ({message.count} times)" if message.count > 1 else ""
        diagnostic = error(
            at,
            SIMULATOR_ERROR,
            f"{message.source} reported an {message.level.lower()} while the robot ran: "
            f"{said}{times}",
            message.meaning
            or "the robot loaded, but not as its description says: look at the element named",
        )
        summary = f"{message.source} {message.level.lower()}: {said}"[:120]
        found.append(Finding(NAME, None, "-", Status.FAIL, summary, {}, (diagnostic,)))
    return found


def _traced(context: CheckContext, message: UpstreamMessage) -> Location | None:
    """The description element naming the file the message names, when one does."""
    named = message.example or ""
    if not named:
        return None
    name = PurePath(named).name
    description = context.description
    for mesh in description.mesh_files:
        candidates = [mesh.uri, mesh.path or "", mesh.loader_path or ""]
        if any(c and (c == named or PurePath(c).name == name) for c in candidates):
            return context.at_description(mesh.line)
    return None
