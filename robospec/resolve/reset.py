"""The episode reset: which keyframe the agent's ``reset()`` restores, and where the noise goes.

A robot ManiSkill's scene builders do not know is never reset between episodes by the tasks
(``BaseEnv.reset`` calls ``agent.reset()`` with no joint positions, which keeps them where they
are), so robospec's agent resets itself: to the spec's ``reset.keyframe``, by default the first
keyframe. A spec that ``extends`` a class keeps the class's reset unless it declares its own.
"""

from __future__ import annotations

from robospec.diagnostics.codes import UNKNOWN_KEYFRAME
from robospec.resolve.context import ResolveContext
from robospec.resolve.resolved import ResolvedKeyframe, ResolvedReset
from robospec.resolve.selection import select_joints


def resolve_reset(
    context: ResolveContext, keyframes: tuple[ResolvedKeyframe, ...]
) -> ResolvedReset | None:
    spec = context.spec
    rule = spec.reset
    declared = "reset" in spec.model_fields_set
    if spec.extends is not None and not declared:
        return None
    by_name = {frame.name: frame for frame in keyframes}
    if rule.keyframe is not None and rule.keyframe not in by_name:
        context.err(
            ("reset", "keyframe"),
            UNKNOWN_KEYFRAME,
            f"unknown keyframe '{rule.keyframe}'",
            f"name one of: {', '.join(by_name)}" if by_name else "define it under `keyframes`",
        )
        return None
    name = rule.keyframe or next(iter(by_name), None)
    if name is None:
        return None
    frame = by_name[name]
    if frame.qpos is None:
        # no positions to reset to (RS326 when named), or not one per joint (RS303)
        return None
    active = context.description.active_joint_names
    if rule.noise_joints is None:
        columns = tuple(range(len(frame.qpos)))
    else:
        order = {joint: i for i, joint in enumerate(active)}
        selected = select_joints(context, rule.noise_joints, ("reset", "noise_joints"))
        columns = tuple(sorted(order[j] for j in selected if j in order))
    return ResolvedReset(
        keyframe=name,
        qpos_noise=rule.qpos_noise,
        noise_columns=columns,
        dof=len(frame.qpos),
        with_qvel=frame.qvel is not None,
    )
