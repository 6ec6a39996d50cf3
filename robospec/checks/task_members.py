"""RS330: a task the spec names calls an agent member the spec does not define. RS331: the spec
names a task the installed ManiSkill does not register (without ManiSkill installed, 3.0.1's
tasks stand in).

``tasks:`` lists the ManiSkill tasks the robot is meant for (task ids, or a folder of them:
``tabletop``). What each task reads off its agent comes from ManiSkill's own source
(:mod:`robospec.maniskill.tasks`): ``PickCube-v1`` calls ``agent.tcp_pose``,
``agent.is_grasping`` and ``agent.is_static``, which ManiSkill's ``BaseAgent`` leaves to each
robot; without them the task fails at ``reset`` with a bare ``NotImplementedError`` or
``AttributeError``. A spec that ``extends`` a Python class may inherit them: it is not checked
here (``robospec check --task`` runs the task and says).

Passing::

    tcp: panda_hand_tcp
    grasping:
      is_grasping: {fingers: [{link: panda_leftfinger, opening: +y},
                              {link: panda_rightfinger, opening: -y}]}
    is_static: {joints: arm}
    tasks: [PickCube-v1]

Failing (RS330: PickCube-v1 calls agent.is_grasping: add `grasping:`)::

    tcp: panda_hand_tcp
    tasks: [PickCube-v1]
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from robospec.checks.context import CheckContext
from robospec.checks.member_names import defined_members
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import TASK_MEMBER_UNDEFINED, UNKNOWN_TASK
from robospec.diagnostics.suggest import did_you_mean

# member -> (the spec section that defines it, how)
SECTIONS: dict[str, tuple[str, str]] = {
    "tcp": ("tcp", "`tcp:` (the link at the tool centre point, or the midpoint of two fingers)"),
    "tcp_pos": ("tcp", "`tcp:`"),
    "tcp_pose": ("tcp", "`tcp:`"),
    "is_grasping": (
        "grasping",
        "`grasping: {is_grasping: {fingers: [{link: ..., opening: ...}, {link: ..., opening: "
        "...}]}}`",
    ),
    "is_static": ("is_static", "`is_static: {joints: arm}`"),
    "is_standing": ("is_standing", "`is_standing: {height: {above: ...}}`"),
    "is_fallen": ("is_fallen", "`is_fallen: {height: {below: ...}}`"),
}
# what a task reads off its agent that is no member: several robots at once
SEVERAL_ROBOTS = "agents"


def mend(member: str, spec: Any = None) -> str:
    """How a spec defines ``member`` (``spec``: the spec, when what it has matters)."""
    tcp = getattr(spec, "tcp", None)
    if member == "tcp" and tcp is not None and getattr(tcp, "link", 1) is None:
        return "give `tcp:` a link too (`tcp: {link: ..., midpoint: [...], orientation: ...}`)"
    found = SECTIONS.get(member)
    if found is not None:
        return f"add {found[1]}"
    return (
        f"add `named_links: {{{member}: ...}}` or `link_states: {{{member}: ...}}` if it is a "
        f"link or a link's pose, else define it in Python (`hooks.methods` or `extends`)"
    )


def check(context: CheckContext) -> Iterator[Diagnostic]:
    spec = context.spec
    if not spec.tasks:
        return
    from robospec.maniskill.tasks import installed_tasks

    scan = installed_tasks()
    defined = {name for name, _ in defined_members(context)}
    for index, name in enumerate(spec.tasks):
        at = context.key(("tasks", index))
        if name in scan.tasks:
            ids = [name]
        elif name in scan.families:
            ids = scan.family(name)
        else:
            known = [*scan.tasks, *scan.families]
            suggestion = did_you_mean(name, known)
            yield error(
                at,
                UNKNOWN_TASK,
                f"ManiSkill registers no task '{name}'"
                + (f" ({suggestion})" if suggestion else ""),
                "name a task id (PickCube-v1) or a folder of tasks: " + ", ".join(scan.families),
            )
            continue
        if spec.extends is not None:
            continue  # the Python class may define them: check --task says
        callers: dict[str, list[str]] = {}
        for task in ids:
            for member in scan.needed(task):
                if member != SEVERAL_ROBOTS and member not in defined:
                    callers.setdefault(member, []).append(task)
        for member, tasks in callers.items():
            shown = ", ".join(tasks[:3]) + (f" and {len(tasks) - 3} more" if len(tasks) > 3 else "")
            who = tasks[0] if len(tasks) == 1 else f"{name} tasks ({shown})"
            yield error(
                at,
                TASK_MEMBER_UNDEFINED,
                f"{who} call{'s' if len(tasks) == 1 else ''} agent.{member}: {mend(member, spec)}",
                "without it the task fails at reset with ManiSkill's NotImplementedError or "
                "AttributeError",
            )
