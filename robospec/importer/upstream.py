"""Mistakes in the agent class being imported, found by general rules (never by uid).

- RS405: a controller field value its config class does not accept (e.g. an EE ``frame`` that
  is not one of the frames) — ManiSkill crashes when the mode is selected: the mode is left out.
- RS406: a link name the robot description does not have — in ``urdf_config`` (ManiSkill
  silently ignores it: the rule is left out), as a controller's ``ee_link`` / ``root_link_name``
  (the mode is left out) or as a camera mount (the camera is left out).
- RS407: ``normalize_action`` over joints without limits (bounds taken from the joint limits):
  the normalized action is NaN. Reproduced, with a warning.
- RS408: an end-effector stiffness below 1 that equals one of the position/rotation bounds:
  the config's arguments were passed by position and landed in the wrong fields. Reproduced,
  with a warning.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.diagnostics.codes import (
    UPSTREAM_CONFIG_REJECTED,
    UPSTREAM_JOINT_DRIVEN_TWICE,
    UPSTREAM_KEYFRAME_MISFIT,
    UPSTREAM_POSITIONAL_GAINS,
    UPSTREAM_UNBOUNDED_NORMALIZATION,
    UPSTREAM_UNKNOWN_LINK,
)
from robospec.importer.controllers import written_fields
from robospec.importer.records import (
    ALL_JOINTS,
    AgentRecord,
    ControllerRecord,
    JointFacts,
    SourceRef,
)
from robospec.model.thresholds import LIMIT_TOLERANCE, MIN_EE_STIFFNESS

LINK_FIELDS = ("ee_link", "root_link_name")
BOUND_FIELDS = ("pos_lower", "pos_upper", "rot_lower", "rot_upper")


@dataclass
class Findings:
    diagnostics: list[Diagnostic] = field(default_factory=list)
    dropped_modes: dict[str, str] = field(default_factory=dict)  # mode → why
    dropped_rules: dict[str, str] = field(default_factory=dict)  # link rule → why
    dropped_cameras: dict[str, str] = field(default_factory=dict)  # camera uid → why
    dropped_keyframes: dict[str, str] = field(default_factory=dict)  # keyframe → why
    # (controller record key, field) → a comment for the line it is written on
    field_notes: dict[tuple[str, str], str] = field(default_factory=dict)


def _at(ref: SourceRef) -> Location:
    return Location(ref.file, ref.line, ref.column)


def find_upstream_mistakes(record: AgentRecord, path_text: Callable[[str], str | None]) -> Findings:
    found = Findings()
    controllers_at = record.controllers_at or record.source
    links = set(record.link_names) if record.link_names is not None else None
    limits = {j.name: j for j in record.active_joints} if record.active_joints else None
    _controller_mistakes(record, path_text, controllers_at, links, limits, found)
    _keyframes(record, found)
    _driven_twice(record, controllers_at, found)
    if links is not None:
        _unknown_rule_and_mount_links(record, links, found)
    return found


def _controllers_and_their_modes(
    record: AgentRecord,
) -> dict[str, tuple[ControllerRecord, list[str]]]:
    """Each distinct controller (by key), with the modes that use it."""
    modes_of: dict[str, list[str]] = {}
    distinct: dict[str, ControllerRecord] = {}
    for mode in record.modes:
        for _, controller in mode.entries:
            modes_of.setdefault(controller.key, []).append(mode.name)
            distinct.setdefault(controller.key, controller)
    return {key: (controller, modes_of[key]) for key, controller in distinct.items()}


def _controller_mistakes(
    record: AgentRecord,
    path_text: Callable[[str], str | None],
    controllers_at: SourceRef,
    links: set[str] | None,
    limits: dict[str, JointFacts] | None,
    found: Findings,
) -> None:
    """RS405 and RS406 for each controller (its modes are left out), then the warnings that
    several controllers share, once for all their modes."""
    pending: dict[tuple[str, str], tuple[list[str], str, str]] = {}
    for controller, modes in _controllers_and_their_modes(record).values():
        where = ", ".join(modes)
        problem = _rejected_field(controller, path_text)
        if problem is not None:
            name, value, reason = problem
            found.diagnostics.append(
                error(
                    _at(
                        record.locate(value, controllers_at)
                        if isinstance(value, str)
                        else controllers_at
                    ),
                    UPSTREAM_CONFIG_REJECTED,
                    f"{_config_name(controller)} {name}={value!r} is not accepted ({reason}); "
                    f"ManiSkill fails when the mode is selected, so mode(s) {where} are left out",
                )
            )
            for mode_name in modes:
                found.dropped_modes.setdefault(mode_name, f"{name}={value!r} is not a valid {name}")
            continue
        for name in LINK_FIELDS:
            value = controller.get(name)
            if links is not None and isinstance(value, str) and value not in links:
                found.diagnostics.append(
                    error(
                        _at(record.locate(value, controllers_at)),
                        UPSTREAM_UNKNOWN_LINK,
                        f"{name} {value!r} is no link of the robot description; ManiSkill fails "
                        f"when the mode is selected, so mode(s) {where} are left out",
                        _did_you_mean(value, links),
                    )
                )
                for mode_name in modes:
                    found.dropped_modes.setdefault(mode_name, f"{name} {value!r} is no link")
        _unbounded_normalize(controller, modes, limits, pending)
        _positional_gains(controller, modes, pending, found)
    for (code, _detail), (modes, message, hint) in pending.items():
        where = ", ".join(modes)
        found.diagnostics.append(
            warning(_at(controllers_at), code, f"mode(s) {where}: {message}", hint)
        )


def _unknown_rule_and_mount_links(record: AgentRecord, links: set[str], found: Findings) -> None:
    """RS406 for a urdf_config rule (left out) or a camera mount (the camera left out) naming
    a link the description does not have."""
    at = record.urdf_config_at or record.source
    for link, _ in record.link_rules:
        if link not in links:
            found.diagnostics.append(
                error(
                    _at(record.locate(link, at)),
                    UPSTREAM_UNKNOWN_LINK,
                    f"urdf_config names link {link!r}, which the robot description does not "
                    "have; ManiSkill ignores it silently, and the spec leaves the rule out",
                    _did_you_mean(link, links),
                )
            )
            found.dropped_rules[link] = "no such link"
    for camera in record.cameras:
        if camera.mount is not None and camera.mount not in links:
            found.diagnostics.append(
                error(
                    _at(record.locate(camera.mount)),
                    UPSTREAM_UNKNOWN_LINK,
                    f"camera {camera.uid!r} is mounted on {camera.mount!r}, which is no link "
                    "of the robot description; the camera is left out",
                    _did_you_mean(camera.mount, links),
                )
            )
            found.dropped_cameras[camera.uid] = f"mount {camera.mount!r} is no link"


def _driven_twice(record: AgentRecord, at: SourceRef, found: Findings) -> None:
    """RS415: one mode whose controllers share a joint (both write its drive target; the
    action has the joint twice). The spec keeps it; `robospec validate` reports it."""
    by_joints: dict[str, list[str]] = {}
    for mode in record.modes:
        if mode.name in found.dropped_modes:
            continue
        owner: dict[str, str] = {}
        for key, controller in mode.entries:
            for joint in controller.joints:
                if joint in owner and joint != ALL_JOINTS:
                    detail = f"{joint} ({owner[joint]} and {key})"
                    by_joints.setdefault(detail, []).append(mode.name)
                owner.setdefault(joint, str(key))
    for detail, modes in by_joints.items():
        found.diagnostics.append(
            warning(
                _at(at),
                UPSTREAM_JOINT_DRIVEN_TWICE,
                f"mode(s) {', '.join(modes)} drive joint {detail} with two controllers",
                "drive each joint from one controller upstream; the spec keeps it as it is and "
                "`robospec validate` reports it",
            )
        )


def _keyframes(record: AgentRecord, found: Findings) -> None:
    """RS414: a keyframe with the wrong number of values (ManiSkill fails when it is used:
    left out), or with values outside the joint limits (kept as upstream has it; `robospec
    validate` reports them)."""
    if record.active_joints is not None:
        joints = record.active_joints
        counted = "active joints"
    else:  # not installed: the joints the controllers name, unless some take "all of them"
        named = [j for m in record.modes for _, c in m.entries for j in c.joints]
        if not named or ALL_JOINTS in named:
            return
        joints = tuple(JointFacts(name, None, None) for name in dict.fromkeys(named))
        counted = "joints the controllers drive"
    for frame in record.keyframes:
        at = _at(record.locate(frame.name, record.source))
        for name in ("qpos", "qvel"):
            values = getattr(frame, name)
            if values is None:
                continue
            if len(values) != len(joints) or any(isinstance(v, tuple) for v in values):
                found.diagnostics.append(
                    error(
                        at,
                        UPSTREAM_KEYFRAME_MISFIT,
                        f"keyframe {frame.name!r} has {len(values)} {name} values for "
                        f"{len(joints)} {counted}; ManiSkill fails when it is used, so it is "
                        "left out",
                    )
                )
                found.dropped_keyframes[frame.name] = f"{len(values)} {name} values"
                break
            if name != "qpos":
                continue
            outside = [
                f"{joint.name}={value!r} (limits [{joint.lower}, {joint.upper}])"
                for joint, value in zip(joints, values, strict=True)
                if (joint.lower is not None and value < joint.lower - LIMIT_TOLERANCE)
                or (joint.upper is not None and value > joint.upper + LIMIT_TOLERANCE)
            ]
            if outside:
                found.diagnostics.append(
                    warning(
                        at,
                        UPSTREAM_KEYFRAME_MISFIT,
                        f"keyframe {frame.name!r} sets joints outside their limits: "
                        + ", ".join(outside),
                        "the spec keeps upstream's values; `robospec validate` reports them "
                        "until they are fixed",
                    )
                )


def _config_name(controller: ControllerRecord) -> str:
    return controller.kind.config_class


def _did_you_mean(name: str, candidates: set[str]) -> str | None:
    from robospec.diagnostics.suggest import did_you_mean

    return did_you_mean(name, sorted(candidates))


def _rejected_field(
    controller: ControllerRecord, path_text: Callable[[str], str | None]
) -> tuple[str, Any, str] | None:
    """The first field the spec model (which mirrors ManiSkill's field types) rejects."""
    from pydantic import TypeAdapter, ValidationError

    from robospec.model.controllers import ControllerConfig

    data = written_fields(controller, list(controller.joints), path_text)
    try:
        TypeAdapter(ControllerConfig).validate_python(data)
    except ValidationError as exc:
        first = exc.errors(include_url=False)[0]
        loc = [p for p in first["loc"] if isinstance(p, str) and p != controller.type]
        name = loc[0] if loc else "?"
        return name, data.get(name), first["msg"]
    return None


def _note(
    pending: dict[tuple[str, str], tuple[list[str], str, str]],
    code: str,
    modes: list[str],
    message: str,
    hint: str,
) -> None:
    entry = pending.setdefault((code, message), ([], message, hint))
    entry[0].extend(m for m in modes if m not in entry[0])


def _unbounded_normalize(
    controller: ControllerRecord,
    modes: list[str],
    limits: dict[str, Any] | None,
    pending: dict[tuple[str, str], tuple[list[str], str, str]],
) -> None:
    if limits is None or not controller.kind.joint_position_targets:
        return
    if not controller.get("normalize_action"):
        return
    unbounded: list[str] = []
    for side in ("lower", "upper"):
        if controller.get(side) is not None:
            continue
        for joint in controller.joints:
            facts = limits.get(joint)
            bound = getattr(facts, side, None) if facts is not None else None
            if facts is not None and (bound is None or math.isinf(bound)):
                if joint not in unbounded:
                    unbounded.append(joint)
    if unbounded and controller.joints != (ALL_JOINTS,):
        _note(
            pending,
            UPSTREAM_UNBOUNDED_NORMALIZATION,
            modes,
            f"{_config_name(controller)} normalizes actions to the joint limits, but "
            f"{', '.join(unbounded)} have none: the actions become NaN",
            "give lower/upper bounds, or normalize_action: false; the spec reproduces "
            "upstream as it is",
        )


def _positional_gains(
    controller: ControllerRecord,
    modes: list[str],
    pending: dict[tuple[str, str], tuple[list[str], str, str]],
    found: Findings,
) -> None:
    if not controller.kind.end_effector:
        return
    stiffness = controller.get("stiffness")
    if not isinstance(stiffness, (int, float)) or isinstance(stiffness, bool):
        return
    if not 0 < stiffness < MIN_EE_STIFFNESS:
        return
    for name in BOUND_FIELDS:
        bound = controller.get(name)
        if isinstance(bound, (int, float)) and float(bound) == float(stiffness):
            _note(
                pending,
                UPSTREAM_POSITIONAL_GAINS,
                modes,
                f"{_config_name(controller)} stiffness is {stiffness!r}, the same as {name}: "
                "the arguments look passed by position and shifted (after pos_upper come "
                "stiffness, damping, force_limit, friction)",
                "pass them by keyword upstream; the spec reproduces the numbers as they are",
            )
            found.field_notes[(controller.key, "stiffness")] = (
                f"as upstream: equals {name}, arguments passed by position"
            )
            return
