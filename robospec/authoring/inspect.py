"""``robospec inspect``: what a robot description holds, as text or JSON.

The report is plain data (:func:`inspect_report`) rendered two ways; JSON writes an unbounded
limit as ``null`` (strict JSON has no infinity).
"""

from __future__ import annotations

import json
from typing import Any

from robospec.authoring.description_file import DescriptionFile
from robospec.description import Joint
from robospec.kinematics.tree import KinematicTree


def mimic_text(joint: Joint) -> str:
    assert joint.mimic is not None
    m = joint.mimic
    return f"{joint.name} mimics {m.joint} ×{m.multiplier:g} + {m.offset:g}"


def inspect_report(source: DescriptionFile) -> dict[str, Any]:
    from robospec.authoring.mounting import mounting_frames

    description = source.description
    # the URDF written from MuJoCo's model rates no joint (effort="0" velocity="0": new reads
    # the ratings from the MJCF's own actuators), so its zeros are shown as no rating
    rated = source.loader != "mujoco"
    return {
        "file": str(source.path),
        "kind": source.kind,
        # an MJCF's reading, as the spec's description.loader says it: "mujoco" (MuJoCo's
        # compiled model, what new writes) or "maniskill" (ManiSkill's own MJCF loader)
        "loader": (source.loader or "maniskill") if source.kind == "mjcf" else None,
        "robot": source.robot_name,
        "root_link": description.root_link,
        "floating_root": description.floating_root,
        "active_joints": [
            {
                "index": index,
                "name": joint.name,
                "type": joint.type,
                "lower": joint.lower,
                "upper": joint.upper,
                "velocity": joint.velocity if rated else None,
                "effort": joint.effort if rated else None,
                "mimic": None
                if joint.mimic is None
                else {
                    "joint": joint.mimic.joint,
                    "multiplier": joint.mimic.multiplier,
                    "offset": joint.mimic.offset,
                },
            }
            for index, joint in enumerate(description.active_joints)
        ],
        "mimic": [mimic_text(j) for j in description.joints if j.mimic is not None],
        "tree": [
            {
                "depth": row.depth,
                "link": row.link,
                # "" for the nameless fixed joint ManiSkill makes for an MJCF body without one
                "joint": row.joint.name if row.joint else None,
                "joint_type": row.joint.type if row.joint else None,
            }
            for row in KinematicTree(description).rows()
        ],
        # where a part can be mounted (parts: {NAME: {at, pose}}), and where this robot mounts
        "mounting_frames": [
            {"at": f.at, "pose": f.pose_yaml(), "role": f.role, "why": f.why}
            for f in mounting_frames(source)
        ],
    }


def render_json(report: dict[str, Any]) -> str:
    return json.dumps(report, indent=2, ensure_ascii=False) + "\n"


_NUMERIC = (0, 3, 4, 5, 6)  # right-aligned columns


def _number(value: float | None, unbounded: str = "-") -> str:
    return unbounded if value is None else f"{value:.6g}"


def render_text(report: dict[str, Any]) -> str:
    joints = report["active_joints"]
    loader = f", loader: {report['loader']}" if report.get("loader") else ""
    head = f"{report['file']} ({report['kind']}{loader})"
    if report["robot"]:
        head += f": robot '{report['robot']}'"
    root = report["root_link"] + (" (floating)" if report["floating_root"] else "")
    lines = [f"{head}, root link {root}, {len(joints)} active joint(s)", ""]
    if joints:
        table = [("#", "joint", "type", "lower", "upper", "velocity", "effort")]
        for j in joints:
            unbounded = "-inf" if j["type"] == "continuous" else "-"
            table.append(
                (
                    str(j["index"]),
                    j["name"],
                    j["type"],
                    _number(j["lower"], unbounded),
                    _number(j["upper"], unbounded.lstrip("-")),
                    _number(j["velocity"]),
                    _number(j["effort"]),
                )
            )
        widths = [max(len(row[i]) for row in table) for i in range(len(table[0]))]
        lines.append("active joints (qpos order):")
        for row in table:
            cells = [
                cell.rjust(width) if i in _NUMERIC else cell.ljust(width)
                for i, (cell, width) in enumerate(zip(row, widths, strict=True))
            ]
            lines.append("  " + "  ".join(cells).rstrip())
        lines.append("")
    lines.append("mimic relations:" if report["mimic"] else "mimic relations: none")
    lines += [f"  {text}" for text in report["mimic"]]
    lines += ["", "kinematic tree (link  <- joint, type):"]
    for row in report["tree"]:
        indent = "  " * (row["depth"] + 1)
        if row["joint"] is None:
            via = ""
        elif row["joint"]:
            via = f"  <- {row['joint']} ({row['joint_type']})"
        else:
            via = f"  <- ({row['joint_type']}, unnamed)"
        lines.append(f"{indent}{row['link']}{via}")
    frames = report.get("mounting_frames", [])
    if frames:
        lines += ["", "mounting frames (parts: {NAME: {at: LINK, pose: ...}}):"]
        for frame in frames:
            pose = f", pose {_pose_text(frame['pose'])}" if frame["pose"] else ""
            role = "mount a part at" if frame["role"] == "flange" else "mounted as a part by"
            lines.append(f"  {role} {frame['at']}{pose}: {frame['why']}")
    return "\n".join(lines) + "\n"


def _pose_text(pose: dict[str, list[float]]) -> str:
    return (
        "{" + ", ".join(f"{k}: [{', '.join(f'{v:g}' for v in vs)}]" for k, vs in pose.items()) + "}"
    )
