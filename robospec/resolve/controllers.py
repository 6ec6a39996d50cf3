"""Controllers: each spec controller becomes one ManiSkill controller config's arguments.

Joint selections become ``joint_names``; per-joint values given by name become lists in the
controller's joint order; links, files and mimic maps are bound to the description.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from robospec.diagnostics.codes import INVALID_VALUE, UNKNOWN_JOINT
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath
from robospec.model.controller_kinds import FIELD_ORDER, controller_kind
from robospec.model.frozen import MimicTarget
from robospec.resolve.context import ResolveContext
from robospec.resolve.description_files import file_ref
from robospec.resolve.resolved import FileRef, ResolvedController
from robospec.resolve.selection import bound_joints, link, select_joints


def resolve_controller(
    context: ResolveContext, name: str, config: Any, description_ref: FileRef
) -> ResolvedController:
    path: KeyPath = ("controllers", name)
    joints = select_joints(context, config.joints, (*path, "joints"))
    # a joint name that did not bind leaves the list short: "not driven" would only repeat it
    whole = bound_joints(context, (*path, "joints")) is not None
    kind = controller_kind(config.type)
    kwargs: list[tuple[str, Any]] = [("joint_names", joints)]
    required = {n for n, f in type(config).model_fields.items() if f.is_required()}
    for field_name in type(config).model_fields:
        if field_name in ("type", "joints"):
            continue
        if field_name not in config.model_fields_set and field_name not in required:
            continue
        value = getattr(config, field_name)
        field_path = (*path, field_name)
        if axes := kind.axes_bounded_by(field_name):  # one value per axis, not per joint
            value = per_joint_values(context, value, axes, field_path)
        elif field_name in kind.per_joint:
            value = per_joint_values(context, value, joints, field_path, whole=whole)
        elif field_name == "mimic":
            value = mimic_map(context, value, joints, field_path)
        elif field_name in ("ee_link", "root_link_name") and value is not None:
            link(context, value, field_path)
        elif field_name == "urdf_path" and value is not None:
            value = file_ref(context, value, field_path)
        elif field_name == "delta_solver_config" and value is not None:
            value = value.model_dump()
        kwargs.append((field_name, value))
    if kind.end_effector and "urdf_path" not in config.model_fields_set:
        # ManiSkill's own agents pass their URDF to the IK controller; so do we
        kwargs.append(("urdf_path", description_ref))
    kwargs.sort(key=lambda item: FIELD_ORDER.index(item[0]))
    group = (
        config.joints
        if isinstance(config.joints, str) and config.joints in context.spec.groups
        else None
    )
    return ResolvedController(name, config.type, tuple(kwargs), joints_group=group)


def per_joint_values(
    context: ResolveContext,
    value: Any,
    joints: Sequence[str],
    path: KeyPath,
    *,
    whole: bool = True,
) -> Any:
    """A scalar stays a scalar; a list must have one value per joint; a mapping by
    joint or group name becomes a list in the controller's joint order. ``whole``: whether
    ``joints`` is every joint the controller names (else it is short of the ones that did not
    bind, and a joint missing from it is no mistake of the mapping's)."""
    if isinstance(value, list):
        if len(value) != len(joints):
            context.err(
                path,
                INVALID_VALUE,
                f"expected {len(joints)} values (one per joint), got {len(value)}",
            )
        return list(value)
    if not isinstance(value, dict):
        return value
    by_joint: dict[str, Any] = {}
    for key, item in value.items():
        for joint in select_joints(context, key, (*path, key)):
            if joint not in joints and whole:
                context.err(
                    (*path, key), UNKNOWN_JOINT, f"joint '{joint}' is not driven by this controller"
                )
            by_joint[joint] = item
    missing = [j for j in joints if j not in by_joint]
    # a name that did not bind is reported already: the joints it meant are not "missing" too
    if missing and all(bound_joints(context, (*path, key)) is not None for key in value):
        context.err(path, INVALID_VALUE, "no value for joint(s) " + ", ".join(missing))
    return [by_joint.get(j) for j in joints]


def mimic_map(
    context: ResolveContext, value: dict[str, Any], joints: Sequence[str], path: KeyPath
) -> dict[str, dict[str, Any]]:
    """ManiSkill's ``mimic`` argument: follower -> {"joint": leader, multiplier?, offset?}."""
    result: dict[str, dict[str, Any]] = {}
    for follower, target in value.items():
        leader = target if isinstance(target, str) else target.joint
        entry: dict[str, Any] = {"joint": leader}
        if isinstance(target, MimicTarget):
            entry.update(
                {
                    k: getattr(target, k)
                    for k in ("multiplier", "offset")
                    if k in target.model_fields_set
                }
            )
        for joint in (follower, leader):
            if joint not in joints and context.description.joint(joint) is None:
                context.err(
                    (*path, follower),
                    UNKNOWN_JOINT,
                    f"unknown joint '{joint}'",
                    did_you_mean(joint, joints),
                )
        result[follower] = entry
    return result
