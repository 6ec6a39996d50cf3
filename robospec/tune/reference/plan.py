"""Which joints a reference fit drives and whose gains it fits, decided from the compiled spec
before anything is simulated: every joint the reference names must be one of the robot's, and
driven by a joint-position controller of one control mode (the first mode that drives them
all; with ``--controller``, through those controllers). Problems are RS644 and RS645, at the
reference's column for the joint."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import REFERENCE_JOINT_NOT_POSITION_DRIVEN, REFERENCE_UNKNOWN_JOINT
from robospec.resolve.resolved import ResolvedRobot


@dataclass(frozen=True)
class Plan:
    mode: str
    joints: tuple[str, ...]  # the reference's, in its order
    controllers: tuple[str, ...]  # each joint's controller in the spec
    groups: tuple[str, ...]  # each joint's group in the mode (its controller's name when none)


def driving(robot: ResolvedRobot) -> dict[str, dict[str, tuple[str, str]]]:
    """Per mode: joint -> (group, controller) for joints a position controller drives (one
    whose drives take joint-position targets, with stiffness and damping)."""
    types = {c.name: c for c in robot.controllers}
    out: dict[str, dict[str, tuple[str, str]]] = {}
    for mode in robot.modes:
        pairs = list(mode.groups) if mode.groups else [(mode.name, mode.controller or mode.name)]
        found: dict[str, tuple[str, str]] = {}
        for group, name in pairs:
            controller = types.get(name)
            if controller is None or not controller.kind.joint_position_targets:
                continue
            for joint in controller.joint_names:
                found.setdefault(joint, (group, name))
        out[mode.name] = found
    return out


def plan(
    robot: ResolvedRobot,
    active_joints: Sequence[str],
    joints: Sequence[str],
    where: Callable[[str], Location],
    controllers: Sequence[str] = (),
) -> tuple[Plan | None, list[Diagnostic]]:
    """The mode and controllers for the reference's ``joints``; ``where(joint)`` locates a
    joint's column for diagnostics."""
    problems = []
    for joint in joints:
        if joint not in active_joints:
            from robospec.diagnostics.suggest import did_you_mean

            hint = did_you_mean(joint, active_joints)
            problems.append(
                error(
                    where(joint),
                    REFERENCE_UNKNOWN_JOINT,
                    f"reference joint '{joint}' is not a moving joint of '{robot.uid}'",
                    hint or f"its joints: {', '.join(active_joints)}",
                )
            )
    if problems:
        return None, problems
    wanted = set(controllers)
    best: tuple[int, str] | None = None  # (joints driven, mode)
    by_mode = driving(robot)
    for mode, found in by_mode.items():
        usable = {j: pair for j, pair in found.items() if not wanted or pair[1] in wanted}
        count = sum(joint in usable for joint in joints)
        if count == len(joints):
            group_of = [usable[j] for j in joints]
            return Plan(
                mode,
                tuple(joints),
                tuple(c for _, c in group_of),
                tuple(g for g, _ in group_of),
            ), []
        if best is None or count > best[0]:
            best = (count, mode)
    chosen = by_mode.get(best[1], {}) if best is not None else {}
    through = f" through --controller {', '.join(controllers)}" if controllers else ""
    for joint in joints:
        pair = chosen.get(joint)
        if pair is not None and (not wanted or pair[1] in wanted):
            continue
        problems.append(
            error(
                where(joint),
                REFERENCE_JOINT_NOT_POSITION_DRIVEN,
                f"no control mode of '{robot.uid}' drives reference joint '{joint}' with a "
                f"joint-position controller{through} together with the reference's other joints",
                "a reference fit needs stiffness and damping to fit: drive the joint with a "
                "pd_joint_pos controller, or leave its columns out of the reference",
            )
        )
    return None, problems
