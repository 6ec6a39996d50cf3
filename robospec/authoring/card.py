"""``robospec doc``: a Markdown robot card, a pure function of the compiled spec.

Sections: the robot (uid, class, description file), the parts mounted on it, the kinematic
tree as a Mermaid ``graph TD`` (links as nodes, joints as labelled edges, active joints drawn
thick), the active joints, the action layout of each control mode (:mod:`.layout`), the
keyframes, the cameras and the spec's ``simulation`` settings (where it has any), and the
success of each task whose demonstrations ``robospec solve`` recorded (``doc --demos DIR``:
the episodes' own record, ManiSkill's trajectory ``.json``, never a number typed in). With
pictures (``doc --images``, :mod:`robospec.pictures`) the card leads with the robot, shows it
from each view at each keyframe, and each camera's view below the cameras' table.
No path of the machine appears (files are shown as the spec names them) and numbers are
formatted the same way every time, so the card is byte-identical for the same spec.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from robospec.authoring.layout import ActionRow, mode_layout
from robospec.description import RobotDescription
from robospec.kinematics.tree import KinematicTree
from robospec.resolve.resolved import FileRef, ResolvedRobot
from robospec.resolve.root_pose import root_body_pose

_MERMAID_ESCAPES = {"&": "#amp;", '"': "#quot;", "<": "#lt;", ">": "#gt;", "|": "#124;"}


def number(value: float | None) -> str:
    if value is None:
        return "—"
    if math.isinf(value):
        return "∞" if value > 0 else "-∞"
    return f"{value:.6g}"


def cell(text: str) -> str:
    """Text safe inside a Markdown table cell (inline code keeps names like a_b_c intact)."""
    return text.replace("|", "\\|")


def code(text: str) -> str:
    return f"`{cell(text)}`"


def mermaid_label(text: str) -> str:
    return "".join(_MERMAID_ESCAPES.get(ch, ch) for ch in text)


def node_ids(links: list[str]) -> dict[str, str]:
    """A Mermaid-safe id per link: its name reduced to [A-Za-z0-9_], made unique by index."""
    ids: dict[str, str] = {}
    used: set[str] = set()
    for index, link in enumerate(links):
        base = "l_" + (re.sub(r"[^A-Za-z0-9_]", "_", link) or str(index))
        candidate = base
        while candidate in used:
            candidate = f"{base}_{index}"
        used.add(candidate)
        ids[link] = candidate
    return ids


def description_text(ref: FileRef) -> str:
    return ref.placeholder_text or ref.relative + " (relative to the spec)"


@dataclass(frozen=True)
class SolvedTask:
    """A task's episodes as ``robospec solve`` recorded them for this robot: how many the task
    judged a success, and the record's path from the card's folder."""

    task: str
    episodes: int
    successes: int
    link: str


@dataclass(frozen=True)
class CardPicture:
    """A picture of ``doc --images``: what it shows, and its path from the card's folder."""

    kind: str  # "robot", "collision" (the same view, collision shapes), "camera", "table"
    keyframe: str
    name: str  # the view's name, or the camera's uid
    link: str


def robot_card(
    robot: ResolvedRobot,
    description: RobotDescription,
    spec_link: str,
    plots: Sequence[tuple[str, str]] = (),
    pictures: Sequence[CardPicture] = (),
    solved: Sequence[SolvedTask] = (),
) -> str:
    """The card; ``spec_link`` is the spec's path relative to the card's folder, ``plots``
    each controller's step-response picture (``check --plot``, ``tune --plot``) as
    ``(controller, path relative to the card's folder)``, ``pictures`` those of
    ``doc --images``, ``solved`` the tasks ``robospec solve`` recorded (``doc --demos``)."""
    lines = [f"# {robot.uid}", ""]
    lead = next((p for p in pictures if p.kind == "robot"), None)
    if lead is not None:  # as model cards do: first, what the robot looks like
        lines += [f"![{robot.uid} at keyframe {lead.keyframe}](<{lead.link}>)", ""]
    lines += _summary(robot, description, spec_link)
    lines += _parts(robot)
    lines += _pictures(pictures)
    lines += _tree(description)
    lines += _joints(description)
    lines += _actions(robot, description)
    lines += _keyframes(robot, description)
    lines += _cameras(robot, pictures)
    lines += _simulation(robot)
    lines += _tasks(solved)
    lines += _plots(plots)
    while lines and lines[-1] == "":
        lines.pop()
    return "\n".join(lines) + "\n"


def _simulation(robot: ResolvedRobot) -> list[str]:
    """The spec's ``simulation`` section, where it has one: what the agent changes in how its
    shapes collide, and the sim config it recommends."""
    sim = robot.simulation
    if sim.empty:
        return []
    lines = ["## Simulation", ""]
    if sim.profile is not None:
        lines += [
            f"Written by `robospec optimize --profile {sim.profile}`: the robot collides "
            "differently from its description, for speed.",
            "",
        ]
    lines += ["| setting | value |", "| --- | --- |"]
    if sim.category is not None:
        lines.append(f"| category | {sim.category} |")
    if sim.contact_offset is not None:
        lines.append(
            f"| contact offset of the robot's shapes | {number(sim.contact_offset)} m "
            "(ManiSkill's scenes: 0.02 m) |"
        )
    for key, value in sim.sim_config.get("scene_config", {}).items():
        lines.append(f"| {key.replace('_', ' ')} | {value} |")
    if sim.sim_config:
        lines += [
            "",
            "Pass the recommended sim config to `gym.make(..., sim_config=sim_config_for(uid))`.",
        ]
    return [*lines, ""]


def _tasks(solved: Sequence[SolvedTask]) -> list[str]:
    """How often ManiSkill's solution of each task succeeded with this robot, as recorded."""
    if not solved:
        return []
    lines = [
        "## Tasks",
        "",
        "ManiSkill's own motion-planning solution of each task, run with this robot by "
        '`robospec solve`; success as the task judges it (`info["success"]`), read from the '
        "episodes' record.",
        "",
        "| task | episodes | successes | success rate | record |",
        "| --- | ---: | ---: | ---: | --- |",
    ]
    for task in solved:
        rate = task.successes / task.episodes if task.episodes else 0.0
        lines.append(
            f"| {code(task.task)} | {task.episodes} | {task.successes} | {rate:.0%} | "
            f"[{cell(task.link.rsplit('/', 1)[-1])}](<{task.link}>) |"
        )
    return [*lines, ""]


def _plots(plots: Sequence[tuple[str, str]]) -> list[str]:
    if not plots:
        return []
    lines = ["## Step responses", ""]
    lines += [
        "Each controller's joints after a small step of their drive targets "
        "(`robospec check --plot`, `robospec tune --plot`).",
        "",
    ]
    for controller, link in plots:
        lines += [f"### {code(controller)}", "", f"![{controller} step response]({link})", ""]
    return lines


def _summary(robot: ResolvedRobot, description: RobotDescription, spec_link: str) -> list[str]:
    default = robot.modes[0].name if robot.modes else "—"
    return [
        "| | |",
        "| --- | --- |",
        f"| uid | {code(robot.uid)} |",
        f"| class | {code(robot.class_name)} |",
        f"| spec | [{code(spec_link)}](<{spec_link}>) |",
        f"| description | {robot.description_kind}: {code(description_text(robot.description))} |",
        f"| root link | {code(description.root_link)}"
        + (" (fixed)" if robot.fix_root_link else " (free)")
        + " |",
        f"| active joints | {len(description.active_joint_names)} |",
        f"| control modes | {len(robot.modes)} (default {code(default)}) |",
        "",
    ]


def _parts(robot: ResolvedRobot) -> list[str]:
    """The robots mounted on this one (``parts:``): where, how, and what was renamed."""
    if not robot.parts:
        return []
    lines = [
        "## Parts",
        "",
        "Robots mounted on this one; the description above is robospec's combination of them.",
        "",
        "| part | from | at | pose (p; q) | joint | root | prefixed | frames left out |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for part in robot.parts:
        pose = f"{_vector(part.p)}; {_vector(part.q)}"
        renamed = ", ".join(f"{code(old)} → {code(new)}" for _, old, new in part.renamed) or "—"
        folded = ", ".join(code(name) for name in part.folded) or "—"
        joint = code(part.joint) if part.joint else "(welded body)"
        lines.append(
            f"| {code(part.name)} | {part.kind} {code(part.source)} | {code(part.at)} | {pose} | "
            f"{joint} | {code(part.root)} | {renamed} | {folded} |"
        )
    return [*lines, ""]


def _tree(description: RobotDescription) -> list[str]:
    rows = KinematicTree(description).rows()
    ids = node_ids([row.link for row in rows])
    lines = [
        "## Kinematic tree",
        "",
        "Links are boxes; joints are edges, thick (`==>`) for active joints.",
        "",
        "```mermaid",
        "graph TD",
    ]
    for row in rows:
        lines.append(f'  {ids[row.link]}["{mermaid_label(row.link)}"]')
    for row in rows:
        joint = row.joint
        if joint is None:
            continue
        arrow = "==>" if joint.is_active else "-->"
        label = mermaid_label(f"{joint.name} ({joint.type})" if joint.name else joint.type)
        lines.append(f'  {ids[joint.parent]} {arrow}|"{label}"| {ids[row.link]}')
    return [*lines, "```", ""]


def _joints(description: RobotDescription) -> list[str]:
    lines = [
        "## Active joints",
        "",
        "| qpos | joint | type | lower | upper | mimics |",
        "| ---: | --- | --- | ---: | ---: | --- |",
    ]
    for index, joint in enumerate(description.active_joints):
        lower, upper = joint.lower, joint.upper
        if joint.type == "continuous":
            lower, upper = -math.inf, math.inf
        mimic = ""
        if joint.mimic is not None:
            m = joint.mimic
            mimic = f"{code(m.joint)} ×{number(m.multiplier)} + {number(m.offset)}"
        lines.append(
            f"| {index} | {code(joint.name)} | {joint.type} | {number(lower)} | "
            f"{number(upper)} | {mimic} |"
        )
    return [*lines, ""]


def _actions(robot: ResolvedRobot, description: RobotDescription) -> list[str]:
    lines = [
        "## Action layout",
        "",
        "Per control mode (the first is the default). A normalized action is in [-1, 1]; "
        "low and high are then what -1 and 1 mean.",
        "",
    ]
    for mode in robot.modes:
        rows = mode_layout(robot, description, mode)
        lines += [f"### {mode.name} ({len(rows)} dims)", ""]
        if not rows:
            lines += ["No action dimensions.", ""]
            continue
        lines += [
            "| index | group | controller | target | low | high | normalized |",
            "| ---: | --- | --- | --- | ---: | ---: | --- |",
        ]
        lines += [_action_row(row) for row in rows]
        lines.append("")
    return lines


def _action_row(row: ActionRow) -> str:
    return (
        f"| {row.index} | {code(row.group)} | {code(row.controller)} ({row.type}) | "
        f"{code(row.target)} | {number(row.low)} | {number(row.high)} | "
        f"{'yes' if row.normalized else 'no'} |"
    )


def _keyframes(robot: ResolvedRobot, description: RobotDescription) -> list[str]:
    lines = ["## Keyframes", ""]
    if not robot.keyframes:
        return [*lines, "None.", ""]
    names = [k.name for k in robot.keyframes]
    # the poses as the spec means them (an MJCF robot's: its root body's, see resolve.root_pose)
    poses = [root_body_pose(description, (k.p, k.q)) for k in robot.keyframes]
    lines += [
        "| joint | " + " | ".join(code(n) for n in names) + " |",
        "| --- |" + " ---: |" * len(names),
    ]
    lines.append("| pose p | " + " | ".join(_vector(p) for p, _ in poses) + " |")
    lines.append("| pose q (wxyz) | " + " | ".join(_vector(q) for _, q in poses) + " |")
    for index, joint in enumerate(robot.active_joints):
        values = [
            number(k.qpos[index]) if k.qpos is not None and index < len(k.qpos) else "—"
            for k in robot.keyframes
        ]
        lines.append(f"| {code(joint)} | " + " | ".join(values) + " |")
    return [*lines, ""]


def _vector(values: tuple[float, ...]) -> str:
    return "[" + ", ".join(number(v) for v in values) + "]"


def _pictures(pictures: Sequence[CardPicture]) -> list[str]:
    robot = [p for p in pictures if p.kind in ("robot", "collision")]
    if not robot:
        return []
    lines = [
        "## Pictures",
        "",
        "The robot at each keyframe (`robospec doc --images`; drawn by MuJoCo from the "
        "description, as ManiSkill loads it).",
        "",
    ]
    for keyframe in dict.fromkeys(p.keyframe for p in robot):
        lines += [f"### {code(keyframe)}", ""]
        for kind in ("robot", "collision"):
            row = [p for p in robot if p.keyframe == keyframe and p.kind == kind]
            if row:
                what = "" if kind == "robot" else " (collision shapes)"
                lines.append(" ".join(f"![{keyframe}: {p.name}{what}](<{p.link}>)" for p in row))
                lines.append("")
    return lines


def _camera_pictures(pictures: Sequence[CardPicture], uid: str) -> list[str]:
    views = [p for p in pictures if p.kind in ("camera", "table") and p.name == uid]
    if not views:
        return []
    lines = [
        f"### {code(uid)}",
        "",
        "| keyframe | the robot alone | at a table, with a cube |",
        "| --- | --- | --- |",
    ]
    for keyframe in dict.fromkeys(p.keyframe for p in views):
        cells = []
        for kind in ("camera", "table"):
            found = [p for p in views if p.keyframe == keyframe and p.kind == kind]
            cells.append(f"![{uid} at {keyframe}](<{found[0].link}>)" if found else "—")
        lines.append(f"| {code(keyframe)} | " + " | ".join(cells) + " |")
    return [*lines, ""]


def _cameras(robot: ResolvedRobot, pictures: Sequence[CardPicture] = ()) -> list[str]:
    lines = ["## Cameras", ""]
    if not robot.cameras:
        return [*lines, "None.", ""]
    lines += [
        "| uid | mount | p | q (wxyz) | resolution | fov (rad) | near | far |",
        "| --- | --- | --- | --- | --- | ---: | ---: | ---: |",
    ]
    for camera in robot.cameras:
        fov = number(camera.fov) if camera.fov is not None else "intrinsic"
        lines.append(
            f"| {code(camera.uid)} | {code(camera.mount)} | {_vector(camera.p)} | "
            f"{_vector(camera.q)} | {camera.width}×{camera.height} | {fov} | "
            f"{number(camera.near)} | {number(camera.far)} |"
        )
    lines.append("")
    if any(p.kind in ("camera", "table") for p in pictures):
        lines += [
            "What each camera sees from its mount at each keyframe, with its own size, field "
            "of view, near and far.",
            "",
        ]
        for camera in robot.cameras:
            lines += _camera_pictures(pictures, camera.uid)
    return lines
