"""Stage 4: semantic checks over a resolved robot. One module per rule, each a function
``check(context) -> Iterable[Diagnostic]`` with its code and, in its docstring, a passing and a
failing example.

Two kinds, run at two moments:

- :data:`BINDING_CHECKS` judge how the spec uses the description — a keyframe one value short,
  a joint listed twice, a fixed joint selected. They read the bindings resolve recorded and
  skip any selection that did not bind, so they run even when resolve reported errors: every
  independent mistake is reported at once, and none twice.
- :data:`ROBOT_CHECKS` judge the robot as a whole — every active joint driven in every mode,
  bits ManiSkill reserves. A robot with unresolved names has holes these would misread, so
  they run only on a robot without errors.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from robospec.checks import (
    base_controller_joints,
    camera_fov_or_intrinsic,
    collision_bits,
    controller_gains,
    ee_controller_urdf,
    inactive_joints,
    joint_listed_twice,
    joint_set_twice,
    keyframe_length,
    keyframe_limits,
    link_rule_material,
    member_names,
    member_references,
    mimic_joints,
    mimic_map,
    mjcf_link_rules,
    mode_coverage,
    never_collide_bits,
    never_collide_entries,
    never_collide_no_free_bit,
    never_collide_self,
    physical_ranges,
    reset_keyframe,
    task_members,
    unbounded_normalization,
)
from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic

Check = Callable[[CheckContext], Iterable[Diagnostic]]

BINDING_CHECKS: tuple[Check, ...] = (
    keyframe_length.check,  # RS303
    keyframe_limits.check,  # RS304
    mimic_map.check,  # RS305
    joint_listed_twice.check,  # RS310
    inactive_joints.check,  # RS311
    link_rule_material.check,  # RS312
    joint_set_twice.check,  # RS313
    camera_fov_or_intrinsic.check,  # RS314
    base_controller_joints.check,  # RS315
    member_references.check,  # RS316
    member_names.check,  # RS317
    task_members.check,  # RS330, RS331, RS332
    never_collide_entries.check,  # RS320
    never_collide_no_free_bit.check,  # RS323
    mjcf_link_rules.check,  # RS324
    ee_controller_urdf.check,  # RS325
    reset_keyframe.check,  # RS326
)

ROBOT_CHECKS: tuple[Check, ...] = (
    mode_coverage.check,  # RS301, RS302
    mimic_joints.check,  # RS309
    collision_bits.check,  # RS307
    controller_gains.check,  # RS318
    physical_ranges.check,  # RS106
    unbounded_normalization.check,  # RS319
    never_collide_bits.check,  # RS321
    never_collide_self.check,  # RS322
)


def run_checks(checks: Iterable[Check], context: CheckContext) -> list[Diagnostic]:
    return [d for check in checks for d in check(context)]


__all__ = ["BINDING_CHECKS", "ROBOT_CHECKS", "CheckContext", "run_checks"]
