"""The spec models, frozen: record classes and pydantic-core schemas. GENERATED, do not edit.

Written by ``python -m robospec.model.freeze --write`` from the pydantic models in
robospec.model; tests/test_frozen_model.py fails when it is out of date. See
robospec/model/freeze.py for why it exists.
"""
# ruff: noqa: E501

from __future__ import annotations

import functools
from typing import Any

from robospec.model import rules
from robospec.model.record import FieldSpec, Record

PYDANTIC_CORE_VERSION = '2.50.4'
"""The pydantic-core the schemas were frozen with (another one rebuilds them: model.core)."""



class Pose(Record):
    """A pose: a position `p` and an orientation, given either as a wxyz quaternion `q` or as roll-pitch-yaw angles `rpy` (neither: no rotation)."""

    __slots__ = ()
    model_fields = {'p': FieldSpec(False), 'q': FieldSpec(False), 'rpy': FieldSpec(False)}



class AllBut(Record):
    """Every active joint except the ones selected: `{all_but: gripper}`."""

    __slots__ = ()
    model_fields = {'all_but': FieldSpec(True)}



class AllLinksBut(AllBut):
    """Every link except the ones selected: `{all_but: base_link}`."""

    __slots__ = ()
    model_fields = {'all_but': FieldSpec(True)}



class _Controller(Record):
    """_Controller"""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True)}



class _Drive(_Controller):
    """_Drive"""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False)}



class PassiveConfig(_Drive):
    """A passive controller (`passive`): it takes no action and leaves its joints to physics, with the given damping and friction (e.g. the wheels of a caster)."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'type': FieldSpec(True)}



class PDJointVelConfig(_Drive):
    """Joint velocity targets (`pd_joint_vel`): each action is a target velocity per joint."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'type': FieldSpec(True), 'lower': FieldSpec(True), 'upper': FieldSpec(True), 'normalize_action': FieldSpec(False), 'drive_mode': FieldSpec(False)}



class PDBaseVelConfig(PDJointVelConfig):
    """Mobile-base velocity in the world frame (`pd_base_vel`): x, y and yaw velocity targets for the base's three joints."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'type': FieldSpec(True), 'lower': FieldSpec(True), 'upper': FieldSpec(True), 'normalize_action': FieldSpec(False), 'drive_mode': FieldSpec(False)}



class PDBaseForwardVelConfig(PDJointVelConfig):
    """Mobile-base forward and turning velocity, ego-centric (`pd_base_forward_vel`): a 2-D action (forward speed, turn rate) for the base's x, y and yaw joints."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'type': FieldSpec(True), 'lower': FieldSpec(True), 'upper': FieldSpec(True), 'normalize_action': FieldSpec(False), 'drive_mode': FieldSpec(False)}



class PDJointPosConfig(_Drive):
    """Joint position targets (`pd_joint_pos`): absolute positions, or changes to them with `use_delta`."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'type': FieldSpec(True), 'lower': FieldSpec(True), 'upper': FieldSpec(True), 'stiffness': FieldSpec(True), 'use_delta': FieldSpec(False), 'use_target': FieldSpec(False), 'interpolate': FieldSpec(False), 'normalize_action': FieldSpec(False), 'drive_mode': FieldSpec(False)}



class MimicTarget(Record):
    """The joint a mimicking joint follows, with a scale and an offset: q = q_joint * multiplier + offset."""

    __slots__ = ()
    model_fields = {'joint': FieldSpec(True), 'multiplier': FieldSpec(False), 'offset': FieldSpec(False)}



class PDJointPosMimicConfig(PDJointPosConfig):
    """Joint positions where some joints follow others (`pd_joint_pos_mimic`): only the controlling joints take actions, e.g. one action for a two-finger gripper."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'type': FieldSpec(True), 'lower': FieldSpec(True), 'upper': FieldSpec(True), 'stiffness': FieldSpec(True), 'use_delta': FieldSpec(False), 'use_target': FieldSpec(False), 'interpolate': FieldSpec(False), 'normalize_action': FieldSpec(False), 'drive_mode': FieldSpec(False), 'mimic': FieldSpec(False)}



class PDJointPosVelConfig(PDJointPosConfig):
    """Joint position and velocity targets (`pd_joint_pos_vel`): each action holds a position target and then a velocity target per joint."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'type': FieldSpec(True), 'lower': FieldSpec(True), 'upper': FieldSpec(True), 'stiffness': FieldSpec(True), 'use_delta': FieldSpec(False), 'use_target': FieldSpec(False), 'interpolate': FieldSpec(False), 'normalize_action': FieldSpec(False), 'drive_mode': FieldSpec(False), 'vel_lower': FieldSpec(False), 'vel_upper': FieldSpec(False)}



class DeltaSolver(Record):
    """How inverse kinematics turns an end-effector change into joint changes."""

    __slots__ = ()
    model_fields = {'type': FieldSpec(False), 'alpha': FieldSpec(False)}



class PDEEPosConfig(_Controller):
    """End-effector position through inverse kinematics (`pd_ee_pos`): actions move a link in x, y, z and the arm's joints follow."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'type': FieldSpec(True), 'pos_lower': FieldSpec(True), 'pos_upper': FieldSpec(True), 'stiffness': FieldSpec(True), 'damping': FieldSpec(True), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'ee_link': FieldSpec(True), 'urdf_path': FieldSpec(False), 'frame': FieldSpec(False), 'root_link_name': FieldSpec(False), 'use_delta': FieldSpec(False), 'use_target': FieldSpec(False), 'interpolate': FieldSpec(False), 'normalize_action': FieldSpec(False), 'delta_solver_config': FieldSpec(False), 'drive_mode': FieldSpec(False)}



class PDEEPoseConfig(PDEEPosConfig):
    """End-effector position and orientation through inverse kinematics (`pd_ee_pose`): actions move and turn a link and the arm's joints follow."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'type': FieldSpec(True), 'pos_lower': FieldSpec(True), 'pos_upper': FieldSpec(True), 'stiffness': FieldSpec(False), 'damping': FieldSpec(False), 'force_limit': FieldSpec(False), 'friction': FieldSpec(False), 'ee_link': FieldSpec(True), 'urdf_path': FieldSpec(False), 'frame': FieldSpec(False), 'root_link_name': FieldSpec(False), 'use_delta': FieldSpec(False), 'use_target': FieldSpec(False), 'interpolate': FieldSpec(False), 'normalize_action': FieldSpec(False), 'delta_solver_config': FieldSpec(False), 'drive_mode': FieldSpec(False), 'rot_lower': FieldSpec(False), 'rot_upper': FieldSpec(False)}



class Tcp(Record):
    """The tool centre point: `self.tcp` and the `tcp_pos`/`tcp_pose` properties."""

    __slots__ = ()
    model_fields = {'link': FieldSpec(False), 'midpoint': FieldSpec(False), 'orientation': FieldSpec(False)}



class Finger(Record):
    """One finger of a two-finger grasp check."""

    __slots__ = ()
    model_fields = {'link': FieldSpec(True), 'opening': FieldSpec(True)}



class Grasping(Record):
    """A two-finger grasp check `is_grasping(object, min_force, max_angle)`: both fingers touch the object with at least `min_force` newtons, each contact force within `max_angle` degrees of the finger's opening direction."""

    __slots__ = ()
    model_fields = {'fingers': FieldSpec(True), 'min_force': FieldSpec(False), 'max_angle': FieldSpec(False)}



class StaticJoints(Record):
    """A second set of joints for `is_static`, with its own threshold (`base_threshold`)."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'threshold': FieldSpec(True)}



class IsStatic(Record):
    """`is_static(threshold)`: every selected joint's velocity is within `threshold`."""

    __slots__ = ()
    model_fields = {'joints': FieldSpec(True), 'threshold': FieldSpec(False), 'base': FieldSpec(False), 'absolute': FieldSpec(False)}



class HeightBand(Record):
    """A band of root-link heights over the ground, in metres."""

    __slots__ = ()
    model_fields = {'above': FieldSpec(False), 'below': FieldSpec(False)}



class IsStanding(Record):
    """`is_standing(ground_height=0)`: the root is within a height band over the ground and, with `upright_within`, tilted less than that many radians from upright."""

    __slots__ = ()
    model_fields = {'height': FieldSpec(True), 'upright_within': FieldSpec(False)}



class ContactRule(Record):
    """Links whose contact with anything means the robot has fallen."""

    __slots__ = ()
    model_fields = {'links': FieldSpec(True), 'force_above': FieldSpec(True)}



class IsFallen(Record):
    """`is_fallen()`: the root is low (`height`) or links touch something (`contact`)."""

    __slots__ = ()
    model_fields = {'height': FieldSpec(False), 'contact': FieldSpec(False)}



class LinkState(Record):
    """A property reading links' poses (7 numbers: p, q) or linear velocities (3 numbers)."""

    __slots__ = ()
    model_fields = {'link': FieldSpec(False), 'links': FieldSpec(False), 'quantity': FieldSpec(False), 'stack_dim': FieldSpec(False), 'method': FieldSpec(False)}



class AxisLimit(Record):
    """Translation limits of a drive per axis: [lower, upper] in metres; an axis left out moves freely."""

    __slots__ = ()
    model_fields = {'x': FieldSpec(False), 'y': FieldSpec(False), 'z': FieldSpec(False)}



class Drive(Record):
    """A closed kinematic loop: a SAPIEN drive between two links (as the Robotiq gripper needs), created after the articulation loads, with its x/y/z motion limited."""

    __slots__ = ()
    model_fields = {'parent': FieldSpec(True), 'parent_pose': FieldSpec(False), 'child': FieldSpec(True), 'child_pose': FieldSpec(False), 'limit': FieldSpec(False)}



class Hooks(Record):
    """Python for what no declaration covers, named as `module:function`."""

    __slots__ = ()
    model_fields = {'after_loading_articulation': FieldSpec(False), 'after_init': FieldSpec(False), 'methods': FieldSpec(False)}



class KeyframeHold(Record):
    """Hold each keyframe with a joint-position mode and measure how far the robot drifts."""

    __slots__ = ()
    model_fields = {'steps': FieldSpec(False), 'max_joint_drift': FieldSpec(False), 'max_root_drift': FieldSpec(False), 'mode': FieldSpec(False), 'pin_root': FieldSpec(False)}



class RandomActions(Record):
    """Send bounded random actions in every control mode; nothing may explode."""

    __slots__ = ()
    model_fields = {'steps': FieldSpec(False), 'seed': FieldSpec(False), 'joint_limit_tolerance': FieldSpec(False), 'max_joint_speed': FieldSpec(False), 'max_root_speed': FieldSpec(False)}



class StepLimits(Record):
    """How one controller's step response is judged; every field defaults to the spec-wide ``step_response`` value."""

    __slots__ = ()
    model_fields = {'duration': FieldSpec(False), 'max_rise_time': FieldSpec(False), 'max_overshoot': FieldSpec(False), 'max_steady_state_error': FieldSpec(False)}



class StepResponse(Record, rules.StepResponseBehaviour):
    """Command a small step to every position- or velocity-controlled group and time the response of each of its joints."""

    __slots__ = ()
    model_fields = {'step': FieldSpec(False), 'prismatic_step': FieldSpec(False), 'duration': FieldSpec(False), 'max_rise_time': FieldSpec(False), 'max_overshoot': FieldSpec(False), 'max_steady_state_error': FieldSpec(False), 'settling_band': FieldSpec(False), 'controllers': FieldSpec(False)}



class SelfContact(Record):
    """At each keyframe, links of the robot that touch each other."""

    __slots__ = ()
    model_fields = {'min_depth': FieldSpec(False)}



class Checks(Record):
    """Thresholds of ``robospec check`` for this robot."""

    __slots__ = ()
    model_fields = {'keyframe_hold': FieldSpec(False), 'random_actions': FieldSpec(False), 'step_response': FieldSpec(False), 'self_contact': FieldSpec(False)}



class Description(Record, rules.DescriptionBehaviour):
    """The robot description file: exactly one of `urdf`, `mjcf` or `xacro`. Relative paths are taken against the spec file's folder; `{maniskill_assets}` stands for ManiSkill's bundled asset folder."""

    __slots__ = ()
    model_fields = {'urdf': FieldSpec(False), 'mjcf': FieldSpec(False), 'xacro': FieldSpec(False), 'args': FieldSpec(False), 'download': FieldSpec(False)}



class Loader(Record):
    """How ManiSkill loads the articulation (BaseAgent class attributes)."""

    __slots__ = ()
    model_fields = {'fix_root_link': FieldSpec(False), 'load_multiple_collisions': FieldSpec(False), 'disable_self_collisions': FieldSpec(False)}



class Material(Record):
    """A physical material: PhysX friction and restitution, given to links by `links` rules."""

    __slots__ = ()
    model_fields = {'static_friction': FieldSpec(True), 'dynamic_friction': FieldSpec(True), 'restitution': FieldSpec(False)}



class LinkRule(Record):
    """Physical properties for the links a name or glob matches."""

    __slots__ = ()
    model_fields = {'material': FieldSpec(False), 'patch_radius': FieldSpec(False), 'min_patch_radius': FieldSpec(False), 'density': FieldSpec(False)}



class Keyframe(Record):
    """A named robot state: root pose, joint positions and velocities."""

    __slots__ = ()
    model_fields = {'pose': FieldSpec(False), 'qpos': FieldSpec(False), 'qvel': FieldSpec(False)}



class Camera(Record):
    """A camera mounted on a link."""

    __slots__ = ()
    model_fields = {'mount': FieldSpec(True), 'pose': FieldSpec(False), 'width': FieldSpec(True), 'height': FieldSpec(True), 'fov': FieldSpec(False), 'intrinsic': FieldSpec(False), 'near': FieldSpec(False), 'far': FieldSpec(False), 'shader_pack': FieldSpec(False)}



class CollisionRule(Record):
    """Set one collision-group bit on some links (`link.set_collision_group_bit`), e.g. so a mobile base does not collide with the ground."""

    __slots__ = ()
    model_fields = {'links': FieldSpec(True), 'group': FieldSpec(True), 'bit': FieldSpec(True), 'value': FieldSpec(False)}



class Spec(Record):
    """A robot for ManiSkill, version 1: a robospec spec compiles to a registered ManiSkill agent (a `BaseAgent` subclass)."""

    __slots__ = ()
    model_fields = {'robospec': FieldSpec(True), 'uid': FieldSpec(True), 'override': FieldSpec(False), 'extends': FieldSpec(False), 'class_name': FieldSpec(False), 'description': FieldSpec(False), 'loader': FieldSpec(False), 'materials': FieldSpec(False), 'links': FieldSpec(False), 'groups': FieldSpec(False), 'passive_joints': FieldSpec(False), 'keyframes': FieldSpec(False), 'controllers': FieldSpec(False), 'control_modes': FieldSpec(False), 'cameras': FieldSpec(False), 'collision_rules': FieldSpec(False), 'never_collide': FieldSpec(False), 'scene_collision_bits': FieldSpec(False), 'tcp': FieldSpec(False), 'named_links': FieldSpec(False), 'grasping': FieldSpec(False), 'is_static': FieldSpec(False), 'is_standing': FieldSpec(False), 'is_fallen': FieldSpec(False), 'link_states': FieldSpec(False), 'proprioception': FieldSpec(False), 'disable_gravity': FieldSpec(False), 'drives': FieldSpec(False), 'hooks': FieldSpec(False), 'checks': FieldSpec(False)}


# Shared parts of the schemas below, each written once.
_S0 = {'type': 'no-info', 'function': rules._to_number}
_S1 = {'type': 'function-before', 'function': _S0, 'schema': {'type': 'float'}}
_S2 = {'type': 'list', 'items_schema': _S1, 'min_length': 3, 'max_length': 3}
_S3 = {'type': 'default', 'schema': _S2, 'default_factory': rules.origin, 'default_factory_takes_data': False}
_S4 = {'type': 'model-field', 'schema': _S3}
_S5 = {'type': 'list', 'items_schema': _S1, 'min_length': 4, 'max_length': 4}
_S6 = {'type': 'nullable', 'schema': _S5}
_S7 = {'type': 'default', 'schema': _S6, 'default': None}
_S8 = {'type': 'model-field', 'schema': _S7}
_S9 = {'type': 'nullable', 'schema': _S2}
_S10 = {'type': 'default', 'schema': _S9, 'default': None}
_S11 = {'type': 'model-field', 'schema': _S10}
_S12 = {'p': _S4, 'q': _S8, 'rpy': _S11}
_S13 = {'type': 'model-fields', 'fields': _S12, 'model_name': 'Pose', 'computed_fields': []}
_S14 = {'extra_fields_behavior': 'forbid', 'title': 'Pose'}
_S15 = {'type': 'model', 'cls': Pose, 'schema': _S13, 'custom_init': False, 'root_model': False, 'config': _S14, 'ref': 'robospec.model.common.Pose'}
_S16 = {'type': 'list', 'items_schema': {'type': 'str'}}
_S17 = [{'type': 'str'}, _S16]
_S18 = {'type': 'union', 'choices': _S17}
_S19 = {'type': 'model-field', 'schema': _S18}
_S20 = {'all_but': _S19}
_S21 = {'type': 'model-fields', 'fields': _S20, 'model_name': 'AllBut', 'computed_fields': []}
_S22 = {'extra_fields_behavior': 'forbid', 'title': 'AllBut'}
_S23 = {'type': 'model', 'cls': AllBut, 'schema': _S21, 'custom_init': False, 'root_model': False, 'config': _S22, 'ref': 'robospec.model.common.AllBut'}
_S24 = {'type': 'model-fields', 'fields': _S20, 'model_name': 'AllLinksBut', 'computed_fields': []}
_S25 = {'extra_fields_behavior': 'forbid', 'title': 'AllLinksBut'}
_S26 = {'type': 'model', 'cls': AllLinksBut, 'schema': _S24, 'custom_init': False, 'root_model': False, 'config': _S25, 'ref': 'robospec.model.common.AllLinksBut'}
_S27 = {'type': 'dict', 'keys_schema': {'type': 'str'}, 'values_schema': _S1}
_S28 = {'type': 'list', 'items_schema': _S1}
_S29 = [_S27, _S1, _S28]
_S30 = {'type': 'union', 'choices': _S29}
_S31 = {'type': 'model-field', 'schema': _S30}
_S32 = {'type': 'default', 'schema': _S30, 'default': 10000000000.0}
_S33 = {'type': 'model-field', 'schema': _S32}
_S34 = {'type': 'default', 'schema': _S30, 'default': 0.0}
_S35 = {'type': 'model-field', 'schema': _S34}
_S36 = {'type': 'literal', 'expected': ['passive']}
_S37 = {'type': 'model-field', 'schema': _S36}
_S38 = {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'type': _S37}
_S39 = {'type': 'model-fields', 'fields': _S38, 'model_name': 'PassiveConfig', 'computed_fields': []}
_S40 = {'extra_fields_behavior': 'forbid', 'title': 'PassiveConfig'}
_S41 = {'type': 'model', 'cls': PassiveConfig, 'schema': _S39, 'custom_init': False, 'root_model': False, 'config': _S40, 'ref': 'robospec.model.controllers.PassiveConfig'}
_S42 = {'type': 'literal', 'expected': ['pd_joint_vel']}
_S43 = {'type': 'model-field', 'schema': _S42}
_S44 = {'type': 'nullable', 'schema': _S30}
_S45 = {'type': 'model-field', 'schema': _S44}
_S46 = {'type': 'default', 'schema': {'type': 'bool'}, 'default': True}
_S47 = {'type': 'model-field', 'schema': _S46}
_S48 = {'type': 'literal', 'expected': ['force', 'acceleration']}
_S49 = {'type': 'list', 'items_schema': _S48}
_S50 = [_S48, _S49]
_S51 = {'type': 'union', 'choices': _S50}
_S52 = {'type': 'default', 'schema': _S51, 'default': 'force'}
_S53 = {'type': 'model-field', 'schema': _S52}
_S54 = {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'type': _S43, 'lower': _S45, 'upper': _S45, 'normalize_action': _S47, 'drive_mode': _S53}
_S55 = {'type': 'model-fields', 'fields': _S54, 'model_name': 'PDJointVelConfig', 'computed_fields': []}
_S56 = {'extra_fields_behavior': 'forbid', 'title': 'PDJointVelConfig'}
_S57 = {'type': 'model', 'cls': PDJointVelConfig, 'schema': _S55, 'custom_init': False, 'root_model': False, 'config': _S56, 'ref': 'robospec.model.controllers.PDJointVelConfig'}
_S58 = {'type': 'literal', 'expected': ['pd_base_vel']}
_S59 = {'type': 'model-field', 'schema': _S58}
_S60 = {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'type': _S59, 'lower': _S45, 'upper': _S45, 'normalize_action': _S47, 'drive_mode': _S53}
_S61 = {'type': 'model-fields', 'fields': _S60, 'model_name': 'PDBaseVelConfig', 'computed_fields': []}
_S62 = {'extra_fields_behavior': 'forbid', 'title': 'PDBaseVelConfig'}
_S63 = {'type': 'model', 'cls': PDBaseVelConfig, 'schema': _S61, 'custom_init': False, 'root_model': False, 'config': _S62, 'ref': 'robospec.model.controllers.PDBaseVelConfig'}
_S64 = {'type': 'literal', 'expected': ['pd_base_forward_vel']}
_S65 = {'type': 'model-field', 'schema': _S64}
_S66 = {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'type': _S65, 'lower': _S45, 'upper': _S45, 'normalize_action': _S47, 'drive_mode': _S53}
_S67 = {'type': 'model-fields', 'fields': _S66, 'model_name': 'PDBaseForwardVelConfig', 'computed_fields': []}
_S68 = {'extra_fields_behavior': 'forbid', 'title': 'PDBaseForwardVelConfig'}
_S69 = {'type': 'model', 'cls': PDBaseForwardVelConfig, 'schema': _S67, 'custom_init': False, 'root_model': False, 'config': _S68, 'ref': 'robospec.model.controllers.PDBaseForwardVelConfig'}
_S70 = {'type': 'literal', 'expected': ['pd_joint_pos']}
_S71 = {'type': 'model-field', 'schema': _S70}
_S72 = {'type': 'default', 'schema': {'type': 'bool'}, 'default': False}
_S73 = {'type': 'model-field', 'schema': _S72}
_S74 = {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'type': _S71, 'lower': _S45, 'upper': _S45, 'stiffness': _S31, 'use_delta': _S73, 'use_target': _S73, 'interpolate': _S73, 'normalize_action': _S47, 'drive_mode': _S53}
_S75 = {'type': 'model-fields', 'fields': _S74, 'model_name': 'PDJointPosConfig', 'computed_fields': []}
_S76 = {'extra_fields_behavior': 'forbid', 'title': 'PDJointPosConfig'}
_S77 = {'type': 'model', 'cls': PDJointPosConfig, 'schema': _S75, 'custom_init': False, 'root_model': False, 'config': _S76, 'ref': 'robospec.model.controllers.PDJointPosConfig'}
_S78 = {'type': 'model-field', 'schema': {'type': 'str'}}
_S79 = {'type': 'default', 'schema': _S1, 'default': 1.0}
_S80 = {'type': 'model-field', 'schema': _S79}
_S81 = {'type': 'default', 'schema': _S1, 'default': 0.0}
_S82 = {'type': 'model-field', 'schema': _S81}
_S83 = {'joint': _S78, 'multiplier': _S80, 'offset': _S82}
_S84 = {'type': 'model-fields', 'fields': _S83, 'model_name': 'MimicTarget', 'computed_fields': []}
_S85 = {'extra_fields_behavior': 'forbid', 'title': 'MimicTarget'}
_S86 = {'type': 'model', 'cls': MimicTarget, 'schema': _S84, 'custom_init': False, 'root_model': False, 'config': _S85, 'ref': 'robospec.model.controllers.MimicTarget'}
_S87 = {'type': 'literal', 'expected': ['pd_joint_pos_mimic']}
_S88 = {'type': 'model-field', 'schema': _S87}
_S89 = [{'type': 'str'}, _S86]
_S90 = {'type': 'union', 'choices': _S89}
_S91 = {'type': 'dict', 'keys_schema': {'type': 'str'}, 'values_schema': _S90}
_S92 = {'type': 'default', 'schema': _S91, 'default_factory': dict, 'default_factory_takes_data': False}
_S93 = {'type': 'model-field', 'schema': _S92}
_S94 = {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'type': _S88, 'lower': _S45, 'upper': _S45, 'stiffness': _S31, 'use_delta': _S73, 'use_target': _S73, 'interpolate': _S73, 'normalize_action': _S47, 'drive_mode': _S53, 'mimic': _S93}
_S95 = {'type': 'model-fields', 'fields': _S94, 'model_name': 'PDJointPosMimicConfig', 'computed_fields': []}
_S96 = {'extra_fields_behavior': 'forbid', 'title': 'PDJointPosMimicConfig'}
_S97 = {'type': 'model', 'cls': PDJointPosMimicConfig, 'schema': _S95, 'custom_init': False, 'root_model': False, 'config': _S96, 'ref': 'robospec.model.controllers.PDJointPosMimicConfig'}
_S98 = {'type': 'literal', 'expected': ['pd_joint_pos_vel']}
_S99 = {'type': 'model-field', 'schema': _S98}
_S100 = {'type': 'default', 'schema': _S44, 'default': -1.0}
_S101 = {'type': 'model-field', 'schema': _S100}
_S102 = {'type': 'default', 'schema': _S44, 'default': 1.0}
_S103 = {'type': 'model-field', 'schema': _S102}
_S104 = {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'type': _S99, 'lower': _S45, 'upper': _S45, 'stiffness': _S31, 'use_delta': _S73, 'use_target': _S73, 'interpolate': _S73, 'normalize_action': _S47, 'drive_mode': _S53, 'vel_lower': _S101, 'vel_upper': _S103}
_S105 = {'type': 'model-fields', 'fields': _S104, 'model_name': 'PDJointPosVelConfig', 'computed_fields': []}
_S106 = {'extra_fields_behavior': 'forbid', 'title': 'PDJointPosVelConfig'}
_S107 = {'type': 'model', 'cls': PDJointPosVelConfig, 'schema': _S105, 'custom_init': False, 'root_model': False, 'config': _S106, 'ref': 'robospec.model.controllers.PDJointPosVelConfig'}
_S108 = ['levenberg_marquardt', 'pseudo_inverse']
_S109 = {'type': 'literal', 'expected': _S108}
_S110 = {'type': 'default', 'schema': _S109, 'default': 'levenberg_marquardt'}
_S111 = {'type': 'model-field', 'schema': _S110}
_S112 = {'type': _S111, 'alpha': _S80}
_S113 = {'type': 'model-fields', 'fields': _S112, 'model_name': 'DeltaSolver', 'computed_fields': []}
_S114 = {'extra_fields_behavior': 'forbid', 'title': 'DeltaSolver'}
_S115 = {'type': 'model', 'cls': DeltaSolver, 'schema': _S113, 'custom_init': False, 'root_model': False, 'config': _S114, 'ref': 'robospec.model.controllers.DeltaSolver'}
_S116 = {'type': 'literal', 'expected': ['pd_ee_pos']}
_S117 = {'type': 'model-field', 'schema': _S116}
_S118 = [_S1, _S28]
_S119 = {'type': 'union', 'choices': _S118}
_S120 = {'type': 'model-field', 'schema': _S119}
_S121 = {'type': 'nullable', 'schema': {'type': 'str'}}
_S122 = {'type': 'default', 'schema': _S121, 'default': None}
_S123 = {'type': 'model-field', 'schema': _S122}
_S124 = ['body_translation', 'root_translation']
_S125 = {'type': 'literal', 'expected': _S124}
_S126 = {'type': 'default', 'schema': _S125, 'default': 'root_translation'}
_S127 = {'type': 'model-field', 'schema': _S126}
_S128 = {'type': 'nullable', 'schema': _S115}
_S129 = {'type': 'default', 'schema': _S128, 'default': None}
_S130 = {'type': 'model-field', 'schema': _S129}
_S131 = {'joints': _S19, 'type': _S117, 'pos_lower': _S120, 'pos_upper': _S120, 'stiffness': _S31, 'damping': _S31, 'force_limit': _S33, 'friction': _S35, 'ee_link': _S78, 'urdf_path': _S123, 'frame': _S127, 'root_link_name': _S123, 'use_delta': _S47, 'use_target': _S73, 'interpolate': _S73, 'normalize_action': _S47, 'delta_solver_config': _S130, 'drive_mode': _S53}
_S132 = {'type': 'model-fields', 'fields': _S131, 'model_name': 'PDEEPosConfig', 'computed_fields': []}
_S133 = {'extra_fields_behavior': 'forbid', 'title': 'PDEEPosConfig'}
_S134 = {'type': 'model', 'cls': PDEEPosConfig, 'schema': _S132, 'custom_init': False, 'root_model': False, 'config': _S133, 'ref': 'robospec.model.controllers.PDEEPosConfig'}
_S135 = {'type': 'literal', 'expected': ['pd_ee_pose']}
_S136 = {'type': 'model-field', 'schema': _S135}
_S137 = {'type': 'default', 'schema': _S44, 'default': None}
_S138 = {'type': 'model-field', 'schema': _S137}
_S139 = ['body_translation:root_aligned_body_rotation', 'root_translation:root_aligned_body_rotation', 'body_translation:body_aligned_body_rotation', 'root_translation:body_aligned_body_rotation']
_S140 = {'type': 'literal', 'expected': _S139}
_S141 = {'type': 'default', 'schema': _S140, 'default': 'root_translation:root_aligned_body_rotation'}
_S142 = {'type': 'model-field', 'schema': _S141}
_S143 = {'type': 'default', 'schema': _S119, 'default': -6.283185307179586}
_S144 = {'type': 'model-field', 'schema': _S143}
_S145 = {'type': 'default', 'schema': _S119, 'default': 6.283185307179586}
_S146 = {'type': 'model-field', 'schema': _S145}
_S147 = {'joints': _S19, 'type': _S136, 'pos_lower': _S120, 'pos_upper': _S120, 'stiffness': _S138, 'damping': _S138, 'force_limit': _S33, 'friction': _S35, 'ee_link': _S78, 'urdf_path': _S123, 'frame': _S142, 'root_link_name': _S123, 'use_delta': _S47, 'use_target': _S73, 'interpolate': _S73, 'normalize_action': _S47, 'delta_solver_config': _S130, 'drive_mode': _S53, 'rot_lower': _S144, 'rot_upper': _S146}
_S148 = {'type': 'model-fields', 'fields': _S147, 'model_name': 'PDEEPoseConfig', 'computed_fields': []}
_S149 = {'extra_fields_behavior': 'forbid', 'title': 'PDEEPoseConfig'}
_S150 = {'type': 'model', 'cls': PDEEPoseConfig, 'schema': _S148, 'custom_init': False, 'root_model': False, 'config': _S149, 'ref': 'robospec.model.controllers.PDEEPoseConfig'}
_S151 = {'type': 'no-info', 'function': rules.tcp_complete}
_S152 = {'type': 'list', 'items_schema': {'type': 'str'}, 'min_length': 2, 'max_length': 2}
_S153 = {'type': 'nullable', 'schema': _S152}
_S154 = {'type': 'default', 'schema': _S153, 'default': None}
_S155 = {'type': 'model-field', 'schema': _S154}
_S156 = {'type': 'literal', 'expected': ['midpoint']}
_S157 = [_S156, {'type': 'str'}]
_S158 = {'type': 'union', 'choices': _S157}
_S159 = {'type': 'nullable', 'schema': _S158}
_S160 = {'type': 'default', 'schema': _S159, 'default': None}
_S161 = {'type': 'model-field', 'schema': _S160}
_S162 = {'link': _S123, 'midpoint': _S155, 'orientation': _S161}
_S163 = {'type': 'model-fields', 'fields': _S162, 'model_name': 'Tcp', 'computed_fields': []}
_S164 = {'extra_fields_behavior': 'forbid', 'title': 'Tcp'}
_S165 = {'type': 'model', 'cls': Tcp, 'schema': _S163, 'custom_init': False, 'root_model': False, 'config': _S164}
_S166 = {'type': 'function-after', 'function': _S151, 'schema': _S165, 'ref': 'robospec.model.members.Tcp'}
_S167 = {'type': 'literal', 'expected': ['+x', '-x', '+y', '-y', '+z', '-z']}
_S168 = {'type': 'model-field', 'schema': _S167}
_S169 = {'link': _S78, 'opening': _S168}
_S170 = {'type': 'model-fields', 'fields': _S169, 'model_name': 'Finger', 'computed_fields': []}
_S171 = {'extra_fields_behavior': 'forbid', 'title': 'Finger'}
_S172 = {'type': 'model', 'cls': Finger, 'schema': _S170, 'custom_init': False, 'root_model': False, 'config': _S171, 'ref': 'robospec.model.members.Finger'}
_S173 = {'type': 'list', 'items_schema': _S172, 'min_length': 2, 'max_length': 2}
_S174 = {'type': 'model-field', 'schema': _S173}
_S175 = {'type': 'default', 'schema': _S1, 'default': 0.5}
_S176 = {'type': 'model-field', 'schema': _S175}
_S177 = {'type': 'default', 'schema': _S1, 'default': 85.0}
_S178 = {'type': 'model-field', 'schema': _S177}
_S179 = {'fingers': _S174, 'min_force': _S176, 'max_angle': _S178}
_S180 = {'type': 'model-fields', 'fields': _S179, 'model_name': 'Grasping', 'computed_fields': []}
_S181 = {'extra_fields_behavior': 'forbid', 'title': 'Grasping'}
_S182 = {'type': 'model', 'cls': Grasping, 'schema': _S180, 'custom_init': False, 'root_model': False, 'config': _S181, 'ref': 'robospec.model.members.Grasping'}
_S183 = [{'type': 'str'}, _S16, _S23]
_S184 = {'type': 'union', 'choices': _S183}
_S185 = {'type': 'model-field', 'schema': _S184}
_S186 = {'type': 'model-field', 'schema': _S1}
_S187 = {'joints': _S185, 'threshold': _S186}
_S188 = {'type': 'model-fields', 'fields': _S187, 'model_name': 'StaticJoints', 'computed_fields': []}
_S189 = {'extra_fields_behavior': 'forbid', 'title': 'StaticJoints'}
_S190 = {'type': 'model', 'cls': StaticJoints, 'schema': _S188, 'custom_init': False, 'root_model': False, 'config': _S189, 'ref': 'robospec.model.members.StaticJoints'}
_S191 = {'type': 'default', 'schema': _S1, 'default': 0.2}
_S192 = {'type': 'model-field', 'schema': _S191}
_S193 = {'type': 'nullable', 'schema': _S190}
_S194 = {'type': 'default', 'schema': _S193, 'default': None}
_S195 = {'type': 'model-field', 'schema': _S194}
_S196 = {'joints': _S185, 'threshold': _S192, 'base': _S195, 'absolute': _S47}
_S197 = {'type': 'model-fields', 'fields': _S196, 'model_name': 'IsStatic', 'computed_fields': []}
_S198 = {'extra_fields_behavior': 'forbid', 'title': 'IsStatic'}
_S199 = {'type': 'model', 'cls': IsStatic, 'schema': _S197, 'custom_init': False, 'root_model': False, 'config': _S198, 'ref': 'robospec.model.members.IsStatic'}
_S200 = {'type': 'no-info', 'function': rules.some_bound}
_S201 = {'type': 'nullable', 'schema': _S1}
_S202 = {'type': 'default', 'schema': _S201, 'default': None}
_S203 = {'type': 'model-field', 'schema': _S202}
_S204 = {'above': _S203, 'below': _S203}
_S205 = {'type': 'model-fields', 'fields': _S204, 'model_name': 'HeightBand', 'computed_fields': []}
_S206 = {'extra_fields_behavior': 'forbid', 'title': 'HeightBand'}
_S207 = {'type': 'model', 'cls': HeightBand, 'schema': _S205, 'custom_init': False, 'root_model': False, 'config': _S206}
_S208 = {'type': 'function-after', 'function': _S200, 'schema': _S207, 'ref': 'robospec.model.members.HeightBand'}
_S209 = {'type': 'model-field', 'schema': _S208}
_S210 = {'height': _S209, 'upright_within': _S203}
_S211 = {'type': 'model-fields', 'fields': _S210, 'model_name': 'IsStanding', 'computed_fields': []}
_S212 = {'extra_fields_behavior': 'forbid', 'title': 'IsStanding'}
_S213 = {'type': 'model', 'cls': IsStanding, 'schema': _S211, 'custom_init': False, 'root_model': False, 'config': _S212, 'ref': 'robospec.model.members.IsStanding'}
_S214 = {'type': 'list', 'items_schema': {'type': 'str'}, 'min_length': 1}
_S215 = {'type': 'model-field', 'schema': _S214}
_S216 = {'links': _S215, 'force_above': _S186}
_S217 = {'type': 'model-fields', 'fields': _S216, 'model_name': 'ContactRule', 'computed_fields': []}
_S218 = {'extra_fields_behavior': 'forbid', 'title': 'ContactRule'}
_S219 = {'type': 'model', 'cls': ContactRule, 'schema': _S217, 'custom_init': False, 'root_model': False, 'config': _S218, 'ref': 'robospec.model.members.ContactRule'}
_S220 = {'type': 'no-info', 'function': rules.height_or_contact}
_S221 = {'type': 'nullable', 'schema': _S208}
_S222 = {'type': 'default', 'schema': _S221, 'default': None}
_S223 = {'type': 'model-field', 'schema': _S222}
_S224 = {'type': 'nullable', 'schema': _S219}
_S225 = {'type': 'default', 'schema': _S224, 'default': None}
_S226 = {'type': 'model-field', 'schema': _S225}
_S227 = {'height': _S223, 'contact': _S226}
_S228 = {'type': 'model-fields', 'fields': _S227, 'model_name': 'IsFallen', 'computed_fields': []}
_S229 = {'extra_fields_behavior': 'forbid', 'title': 'IsFallen'}
_S230 = {'type': 'model', 'cls': IsFallen, 'schema': _S228, 'custom_init': False, 'root_model': False, 'config': _S229}
_S231 = {'type': 'function-after', 'function': _S220, 'schema': _S230, 'ref': 'robospec.model.members.IsFallen'}
_S232 = {'type': 'no-info', 'function': rules.link_or_links}
_S233 = [_S16, {'type': 'str'}]
_S234 = {'type': 'union', 'choices': _S233}
_S235 = {'type': 'nullable', 'schema': _S234}
_S236 = {'type': 'default', 'schema': _S235, 'default': None}
_S237 = {'type': 'model-field', 'schema': _S236}
_S238 = {'type': 'literal', 'expected': ['pose', 'linear_velocity']}
_S239 = {'type': 'default', 'schema': _S238, 'default': 'pose'}
_S240 = {'type': 'model-field', 'schema': _S239}
_S241 = {'type': 'literal', 'expected': [-1, -2]}
_S242 = {'type': 'default', 'schema': _S241, 'default': -2}
_S243 = {'type': 'model-field', 'schema': _S242}
_S244 = {'link': _S123, 'links': _S237, 'quantity': _S240, 'stack_dim': _S243, 'method': _S73}
_S245 = {'type': 'model-fields', 'fields': _S244, 'model_name': 'LinkState', 'computed_fields': []}
_S246 = {'extra_fields_behavior': 'forbid', 'title': 'LinkState'}
_S247 = {'type': 'model', 'cls': LinkState, 'schema': _S245, 'custom_init': False, 'root_model': False, 'config': _S246}
_S248 = {'type': 'function-after', 'function': _S232, 'schema': _S247, 'ref': 'robospec.model.members.LinkState'}
_S249 = {'type': 'list', 'items_schema': _S1, 'min_length': 2, 'max_length': 2}
_S250 = {'type': 'nullable', 'schema': _S249}
_S251 = {'type': 'default', 'schema': _S250, 'default': None}
_S252 = {'type': 'model-field', 'schema': _S251}
_S253 = {'x': _S252, 'y': _S252, 'z': _S252}
_S254 = {'type': 'model-fields', 'fields': _S253, 'model_name': 'AxisLimit', 'computed_fields': []}
_S255 = {'extra_fields_behavior': 'forbid', 'title': 'AxisLimit'}
_S256 = {'type': 'model', 'cls': AxisLimit, 'schema': _S254, 'custom_init': False, 'root_model': False, 'config': _S255, 'ref': 'robospec.model.members.AxisLimit'}
_S257 = {'type': 'definition-ref', 'schema_ref': 'robospec.model.common.Pose'}
_S258 = {'type': 'default', 'schema': _S257, 'default_factory': Pose, 'default_factory_takes_data': False}
_S259 = {'type': 'model-field', 'schema': _S258}
_S260 = {'x': [0.0, 0.0], 'y': [0.0, 0.0], 'z': [0.0, 0.0]}
_S261 = {'type': 'default', 'schema': _S256, 'validate_default': True, 'default': _S260}
_S262 = {'type': 'model-field', 'schema': _S261}
_S263 = {'parent': _S78, 'parent_pose': _S259, 'child': _S78, 'child_pose': _S259, 'limit': _S262}
_S264 = {'type': 'model-fields', 'fields': _S263, 'model_name': 'Drive', 'computed_fields': []}
_S265 = {'extra_fields_behavior': 'forbid', 'title': 'Drive'}
_S266 = {'type': 'model', 'cls': Drive, 'schema': _S264, 'custom_init': False, 'root_model': False, 'config': _S265, 'ref': 'robospec.model.members.Drive'}
_S267 = {'type': 'str', 'pattern': '^[A-Za-z_][A-Za-z0-9_]*(\\.[A-Za-z_][A-Za-z0-9_]*)*:[A-Za-z_][A-Za-z0-9_]*(\\.[A-Za-z_][A-Za-z0-9_]*)*$'}
_S268 = {'type': 'nullable', 'schema': _S267}
_S269 = {'type': 'default', 'schema': _S268, 'default': None}
_S270 = {'type': 'model-field', 'schema': _S269}
_S271 = {'type': 'no-info', 'function': rules._not_a_keyword}
_S272 = {'type': 'str', 'pattern': '^[A-Za-z_][A-Za-z0-9_]{0,63}$'}
_S273 = {'type': 'function-after', 'function': _S271, 'schema': _S272}
_S274 = {'type': 'dict', 'keys_schema': _S273, 'values_schema': _S267}
_S275 = {'type': 'default', 'schema': _S274, 'default_factory': dict, 'default_factory_takes_data': False}
_S276 = {'type': 'model-field', 'schema': _S275}
_S277 = {'after_loading_articulation': _S270, 'after_init': _S270, 'methods': _S276}
_S278 = {'type': 'model-fields', 'fields': _S277, 'model_name': 'Hooks', 'computed_fields': []}
_S279 = {'extra_fields_behavior': 'forbid', 'title': 'Hooks'}
_S280 = {'type': 'model', 'cls': Hooks, 'schema': _S278, 'custom_init': False, 'root_model': False, 'config': _S279, 'ref': 'robospec.model.members.Hooks'}
_S281 = {'type': 'default', 'schema': {'type': 'int', 'ge': 1, 'le': 100000}, 'default': 50}
_S282 = {'type': 'model-field', 'schema': _S281}
_S283 = {'type': 'no-info', 'function': functools.partial(rules.greater_than, gt=0)}
_S284 = {'type': 'function-after', 'function': _S283, 'schema': _S1}
_S285 = {'type': 'default', 'schema': _S284, 'default': 0.05}
_S286 = {'type': 'model-field', 'schema': _S285}
_S287 = {'steps': _S282, 'max_joint_drift': _S286, 'max_root_drift': _S286, 'mode': _S123, 'pin_root': _S73}
_S288 = {'type': 'model-fields', 'fields': _S287, 'model_name': 'KeyframeHold', 'computed_fields': []}
_S289 = {'extra_fields_behavior': 'forbid', 'title': 'KeyframeHold'}
_S290 = {'type': 'model', 'cls': KeyframeHold, 'schema': _S288, 'custom_init': False, 'root_model': False, 'config': _S289, 'ref': 'robospec.model.check_settings.KeyframeHold'}
_S291 = {'type': 'default', 'schema': {'type': 'int', 'ge': 1, 'le': 100000}, 'default': 60}
_S292 = {'type': 'model-field', 'schema': _S291}
_S293 = {'type': 'default', 'schema': {'type': 'int'}, 'default': 0}
_S294 = {'type': 'model-field', 'schema': _S293}
_S295 = {'type': 'no-info', 'function': functools.partial(rules.greater_than_or_equal, ge=0)}
_S296 = {'type': 'function-after', 'function': _S295, 'schema': _S1}
_S297 = {'type': 'default', 'schema': _S296, 'default': 0.1}
_S298 = {'type': 'model-field', 'schema': _S297}
_S299 = {'type': 'default', 'schema': _S284, 'default': 200.0}
_S300 = {'type': 'model-field', 'schema': _S299}
_S301 = {'type': 'default', 'schema': _S284, 'default': 20.0}
_S302 = {'type': 'model-field', 'schema': _S301}
_S303 = {'steps': _S292, 'seed': _S294, 'joint_limit_tolerance': _S298, 'max_joint_speed': _S300, 'max_root_speed': _S302}
_S304 = {'type': 'model-fields', 'fields': _S303, 'model_name': 'RandomActions', 'computed_fields': []}
_S305 = {'extra_fields_behavior': 'forbid', 'title': 'RandomActions'}
_S306 = {'type': 'model', 'cls': RandomActions, 'schema': _S304, 'custom_init': False, 'root_model': False, 'config': _S305, 'ref': 'robospec.model.check_settings.RandomActions'}
_S307 = {'type': 'nullable', 'schema': _S284}
_S308 = {'type': 'default', 'schema': _S307, 'default': None}
_S309 = {'type': 'model-field', 'schema': _S308}
_S310 = {'type': 'nullable', 'schema': _S296}
_S311 = {'type': 'default', 'schema': _S310, 'default': None}
_S312 = {'type': 'model-field', 'schema': _S311}
_S313 = {'duration': _S309, 'max_rise_time': _S309, 'max_overshoot': _S312, 'max_steady_state_error': _S312}
_S314 = {'type': 'model-fields', 'fields': _S313, 'model_name': 'StepLimits', 'computed_fields': []}
_S315 = {'extra_fields_behavior': 'forbid', 'title': 'StepLimits'}
_S316 = {'type': 'model', 'cls': StepLimits, 'schema': _S314, 'custom_init': False, 'root_model': False, 'config': _S315, 'ref': 'robospec.model.check_settings.StepLimits'}
_S317 = {'type': 'default', 'schema': _S284, 'default': 0.1}
_S318 = {'type': 'model-field', 'schema': _S317}
_S319 = {'type': 'default', 'schema': _S284, 'default': 0.01}
_S320 = {'type': 'model-field', 'schema': _S319}
_S321 = {'type': 'default', 'schema': _S284, 'default': 1.0}
_S322 = {'type': 'model-field', 'schema': _S321}
_S323 = {'type': 'default', 'schema': _S284, 'default': 0.5}
_S324 = {'type': 'model-field', 'schema': _S323}
_S325 = {'type': 'default', 'schema': _S296, 'default': 0.5}
_S326 = {'type': 'model-field', 'schema': _S325}
_S327 = {'type': 'default', 'schema': _S296, 'default': 0.2}
_S328 = {'type': 'model-field', 'schema': _S327}
_S329 = {'type': 'dict', 'keys_schema': {'type': 'str'}, 'values_schema': _S316}
_S330 = {'type': 'default', 'schema': _S329, 'default_factory': dict, 'default_factory_takes_data': False}
_S331 = {'type': 'model-field', 'schema': _S330}
_S332 = {'step': _S318, 'prismatic_step': _S320, 'duration': _S322, 'max_rise_time': _S324, 'max_overshoot': _S326, 'max_steady_state_error': _S328, 'settling_band': _S298, 'controllers': _S331}
_S333 = {'type': 'model-fields', 'fields': _S332, 'model_name': 'StepResponse', 'computed_fields': []}
_S334 = {'extra_fields_behavior': 'forbid', 'title': 'StepResponse'}
_S335 = {'type': 'model', 'cls': StepResponse, 'schema': _S333, 'custom_init': False, 'root_model': False, 'config': _S334, 'ref': 'robospec.model.check_settings.StepResponse'}
_S336 = {'type': 'default', 'schema': _S296, 'default': 0.001}
_S337 = {'type': 'model-field', 'schema': _S336}
_S338 = {'min_depth': _S337}
_S339 = {'type': 'model-fields', 'fields': _S338, 'model_name': 'SelfContact', 'computed_fields': []}
_S340 = {'extra_fields_behavior': 'forbid', 'title': 'SelfContact'}
_S341 = {'type': 'model', 'cls': SelfContact, 'schema': _S339, 'custom_init': False, 'root_model': False, 'config': _S340, 'ref': 'robospec.model.check_settings.SelfContact'}
_S342 = {'type': 'default', 'schema': _S290, 'default_factory': KeyframeHold, 'default_factory_takes_data': False}
_S343 = {'type': 'model-field', 'schema': _S342}
_S344 = {'type': 'default', 'schema': _S306, 'default_factory': RandomActions, 'default_factory_takes_data': False}
_S345 = {'type': 'model-field', 'schema': _S344}
_S346 = {'type': 'default', 'schema': _S335, 'default_factory': StepResponse, 'default_factory_takes_data': False}
_S347 = {'type': 'model-field', 'schema': _S346}
_S348 = {'type': 'default', 'schema': _S341, 'default_factory': SelfContact, 'default_factory_takes_data': False}
_S349 = {'type': 'model-field', 'schema': _S348}
_S350 = {'keyframe_hold': _S343, 'random_actions': _S345, 'step_response': _S347, 'self_contact': _S349}
_S351 = {'type': 'model-fields', 'fields': _S350, 'model_name': 'Checks', 'computed_fields': []}
_S352 = {'extra_fields_behavior': 'forbid', 'title': 'Checks'}
_S353 = {'type': 'model', 'cls': Checks, 'schema': _S351, 'custom_init': False, 'root_model': False, 'config': _S352, 'ref': 'robospec.model.check_settings.Checks'}
_S354 = {'type': 'no-info', 'function': rules.one_description}
_S355 = [{'type': 'str'}, {'type': 'int'}, {'type': 'float'}, {'type': 'bool'}]
_S356 = {'type': 'union', 'choices': _S355}
_S357 = {'type': 'dict', 'keys_schema': {'type': 'str'}, 'values_schema': _S356}
_S358 = {'type': 'default', 'schema': _S357, 'default_factory': dict, 'default_factory_takes_data': False}
_S359 = {'type': 'model-field', 'schema': _S358}
_S360 = {'type': 'str', 'pattern': '^[A-Za-z0-9_][A-Za-z0-9_.\\-]{0,63}$'}
_S361 = {'type': 'list', 'items_schema': _S360}
_S362 = {'type': 'default', 'schema': _S361, 'default_factory': list, 'default_factory_takes_data': False}
_S363 = {'type': 'model-field', 'schema': _S362}
_S364 = {'urdf': _S123, 'mjcf': _S123, 'xacro': _S123, 'args': _S359, 'download': _S363}
_S365 = {'type': 'model-fields', 'fields': _S364, 'model_name': 'Description', 'computed_fields': []}
_S366 = {'extra_fields_behavior': 'forbid', 'title': 'Description'}
_S367 = {'type': 'model', 'cls': Description, 'schema': _S365, 'custom_init': False, 'root_model': False, 'config': _S366}
_S368 = {'type': 'function-after', 'function': _S354, 'schema': _S367, 'ref': 'robospec.model.spec.Description'}
_S369 = {'fix_root_link': _S47, 'load_multiple_collisions': _S73, 'disable_self_collisions': _S73}
_S370 = {'type': 'model-fields', 'fields': _S369, 'model_name': 'Loader', 'computed_fields': []}
_S371 = {'extra_fields_behavior': 'forbid', 'title': 'Loader'}
_S372 = {'type': 'model', 'cls': Loader, 'schema': _S370, 'custom_init': False, 'root_model': False, 'config': _S371, 'ref': 'robospec.model.spec.Loader'}
_S373 = {'static_friction': _S186, 'dynamic_friction': _S186, 'restitution': _S82}
_S374 = {'type': 'model-fields', 'fields': _S373, 'model_name': 'Material', 'computed_fields': []}
_S375 = {'extra_fields_behavior': 'forbid', 'title': 'Material'}
_S376 = {'type': 'model', 'cls': Material, 'schema': _S374, 'custom_init': False, 'root_model': False, 'config': _S375, 'ref': 'robospec.model.spec.Material'}
_S377 = {'material': _S123, 'patch_radius': _S203, 'min_patch_radius': _S203, 'density': _S203}
_S378 = {'type': 'model-fields', 'fields': _S377, 'model_name': 'LinkRule', 'computed_fields': []}
_S379 = {'extra_fields_behavior': 'forbid', 'title': 'LinkRule'}
_S380 = {'type': 'model', 'cls': LinkRule, 'schema': _S378, 'custom_init': False, 'root_model': False, 'config': _S379, 'ref': 'robospec.model.spec.LinkRule'}
_S381 = {'type': 'default', 'schema': _S15, 'default_factory': Pose, 'default_factory_takes_data': False}
_S382 = {'type': 'model-field', 'schema': _S381}
_S383 = {'type': 'dict', 'keys_schema': {'type': 'str'}, 'values_schema': _S119}
_S384 = [_S383, _S28]
_S385 = {'type': 'union', 'choices': _S384}
_S386 = {'type': 'nullable', 'schema': _S385}
_S387 = {'type': 'default', 'schema': _S386, 'default': None}
_S388 = {'type': 'model-field', 'schema': _S387}
_S389 = {'pose': _S382, 'qpos': _S388, 'qvel': _S388}
_S390 = {'type': 'model-fields', 'fields': _S389, 'model_name': 'Keyframe', 'computed_fields': []}
_S391 = {'extra_fields_behavior': 'forbid', 'title': 'Keyframe'}
_S392 = {'type': 'model', 'cls': Keyframe, 'schema': _S390, 'custom_init': False, 'root_model': False, 'config': _S391, 'ref': 'robospec.model.spec.Keyframe'}
_S393 = {'type': 'model-field', 'schema': {'type': 'int', 'gt': 0, 'le': 16384}}
_S394 = {'type': 'list', 'items_schema': _S2, 'min_length': 3, 'max_length': 3}
_S395 = {'type': 'nullable', 'schema': _S394}
_S396 = {'type': 'default', 'schema': _S395, 'default': None}
_S397 = {'type': 'model-field', 'schema': _S396}
_S398 = {'type': 'default', 'schema': _S1, 'default': 0.01}
_S399 = {'type': 'model-field', 'schema': _S398}
_S400 = {'type': 'default', 'schema': _S1, 'default': 100.0}
_S401 = {'type': 'model-field', 'schema': _S400}
_S402 = ['minimal', 'default', 'rt', 'rt-med', 'rt-fast']
_S403 = {'type': 'literal', 'expected': _S402}
_S404 = {'type': 'default', 'schema': _S403, 'default': 'minimal'}
_S405 = {'type': 'model-field', 'schema': _S404}
_S406 = {'mount': _S78, 'pose': _S382, 'width': _S393, 'height': _S393, 'fov': _S203, 'intrinsic': _S397, 'near': _S399, 'far': _S401, 'shader_pack': _S405}
_S407 = {'type': 'model-fields', 'fields': _S406, 'model_name': 'Camera', 'computed_fields': []}
_S408 = {'extra_fields_behavior': 'forbid', 'title': 'Camera'}
_S409 = {'type': 'model', 'cls': Camera, 'schema': _S407, 'custom_init': False, 'root_model': False, 'config': _S408, 'ref': 'robospec.model.spec.Camera'}
_S410 = {'type': 'model-field', 'schema': {'type': 'int', 'ge': 0, 'le': 3}}
_S411 = {'type': 'model-field', 'schema': {'type': 'int', 'ge': 0, 'le': 31}}
_S412 = {'type': 'default', 'schema': {'type': 'literal', 'expected': [0, 1]}, 'default': 1}
_S413 = {'type': 'model-field', 'schema': _S412}
_S414 = {'links': _S19, 'group': _S410, 'bit': _S411, 'value': _S413}
_S415 = {'type': 'model-fields', 'fields': _S414, 'model_name': 'CollisionRule', 'computed_fields': []}
_S416 = {'extra_fields_behavior': 'forbid', 'title': 'CollisionRule'}
_S417 = {'type': 'model', 'cls': CollisionRule, 'schema': _S415, 'custom_init': False, 'root_model': False, 'config': _S416, 'ref': 'robospec.model.spec.CollisionRule'}

# Each model's pydantic-core schema, by class name.
SCHEMAS: dict[str, Any] = {
    'Pose': _S15,
    'AllBut': _S23,
    'AllLinksBut': _S26,
    '_Controller': {'type': 'model', 'cls': _Controller, 'schema': {'type': 'model-fields', 'fields': {'joints': _S19}, 'model_name': '_Controller', 'computed_fields': []}, 'custom_init': False, 'root_model': False, 'config': {'extra_fields_behavior': 'forbid', 'title': '_Controller'}, 'ref': 'robospec.model.controllers._Controller'},
    '_Drive': {'type': 'model', 'cls': _Drive, 'schema': {'type': 'model-fields', 'fields': {'joints': _S19, 'damping': _S31, 'force_limit': _S33, 'friction': _S35}, 'model_name': '_Drive', 'computed_fields': []}, 'custom_init': False, 'root_model': False, 'config': {'extra_fields_behavior': 'forbid', 'title': '_Drive'}, 'ref': 'robospec.model.controllers._Drive'},
    'PassiveConfig': _S41,
    'PDJointVelConfig': _S57,
    'PDBaseVelConfig': _S63,
    'PDBaseForwardVelConfig': _S69,
    'PDJointPosConfig': _S77,
    'MimicTarget': _S86,
    'PDJointPosMimicConfig': _S97,
    'PDJointPosVelConfig': _S107,
    'DeltaSolver': _S115,
    'PDEEPosConfig': _S134,
    'PDEEPoseConfig': _S150,
    'Tcp': _S166,
    'Finger': _S172,
    'Grasping': _S182,
    'StaticJoints': _S190,
    'IsStatic': _S199,
    'HeightBand': _S208,
    'IsStanding': _S213,
    'ContactRule': _S219,
    'IsFallen': _S231,
    'LinkState': _S248,
    'AxisLimit': _S256,
    'Drive': {'type': 'definitions', 'schema': _S266, 'definitions': [_S15]},
    'Hooks': _S280,
    'KeyframeHold': _S290,
    'RandomActions': _S306,
    'StepLimits': _S316,
    'StepResponse': _S335,
    'SelfContact': _S341,
    'Checks': _S353,
    'Description': _S368,
    'Loader': _S372,
    'Material': _S376,
    'LinkRule': _S380,
    'Keyframe': _S392,
    'Camera': _S409,
    'CollisionRule': _S417,
    'Spec': {'type': 'definitions', 'schema': {'type': 'function-after', 'function': {'type': 'no-info', 'function': rules.description_or_base}, 'schema': {'type': 'model', 'cls': Spec, 'schema': {'type': 'model-fields', 'fields': {'robospec': {'type': 'model-field', 'schema': {'type': 'literal', 'expected': [1]}}, 'uid': {'type': 'model-field', 'schema': {'type': 'str', 'pattern': '^[A-Za-z0-9][A-Za-z0-9_.\\-]{0,63}$'}}, 'override': _S73, 'extends': _S270, 'class_name': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': _S273}, 'default': None}}, 'description': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': _S368}, 'default': None}}, 'loader': {'type': 'model-field', 'schema': {'type': 'default', 'schema': _S372, 'default_factory': Loader, 'default_factory_takes_data': False}}, 'materials': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S360, 'values_schema': {'type': 'definition-ref', 'schema_ref': 'robospec.model.spec.Material'}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'links': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': {'type': 'str'}, 'values_schema': {'type': 'definition-ref', 'schema_ref': 'robospec.model.spec.LinkRule'}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'groups': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S360, 'values_schema': _S184}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'passive_joints': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': _S18}, 'default': None}}, 'keyframes': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S360, 'values_schema': {'type': 'definition-ref', 'schema_ref': 'robospec.model.spec.Keyframe'}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'controllers': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S360, 'values_schema': {'type': 'tagged-union', 'choices': {'pd_joint_pos': _S77, 'pd_joint_pos_mimic': _S97, 'pd_joint_vel': _S57, 'pd_joint_pos_vel': _S107, 'pd_ee_pos': _S134, 'pd_ee_pose': _S150, 'pd_base_vel': _S63, 'pd_base_forward_vel': _S69, 'passive': _S41}, 'discriminator': 'type', 'strict': False, 'from_attributes': True}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'control_modes': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S360, 'values_schema': {'type': 'union', 'choices': [{'type': 'str'}, {'type': 'dict', 'keys_schema': {'type': 'str'}, 'values_schema': {'type': 'union', 'choices': [{'type': 'str'}, {'type': 'bool', 'strict': True}]}}]}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'cameras': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S360, 'values_schema': {'type': 'definition-ref', 'schema_ref': 'robospec.model.spec.Camera'}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'collision_rules': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'list', 'items_schema': _S417}, 'default_factory': list, 'default_factory_takes_data': False}}, 'never_collide': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'list', 'items_schema': _S18}, 'default_factory': list, 'default_factory_takes_data': False}}, 'scene_collision_bits': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'list', 'items_schema': {'type': 'int', 'ge': 0, 'le': 31}}, 'default_factory': list, 'default_factory_takes_data': False}}, 'tcp': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': {'type': 'union', 'choices': [{'type': 'str'}, _S166]}}, 'default': None}}, 'named_links': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S273, 'values_schema': _S18}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'grasping': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S273, 'values_schema': {'type': 'definition-ref', 'schema_ref': 'robospec.model.members.Grasping'}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'is_static': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': _S199}, 'default': None}}, 'is_standing': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': _S213}, 'default': None}}, 'is_fallen': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': _S231}, 'default': None}}, 'link_states': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'dict', 'keys_schema': _S273, 'values_schema': {'type': 'definition-ref', 'schema_ref': 'robospec.model.members.LinkState'}}, 'default_factory': dict, 'default_factory_takes_data': False}}, 'proprioception': {'type': 'model-field', 'schema': {'type': 'default', 'schema': _S16, 'default_factory': list, 'default_factory_takes_data': False}}, 'disable_gravity': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'nullable', 'schema': {'type': 'union', 'choices': [{'type': 'str'}, _S16, _S26]}}, 'default': None}}, 'drives': {'type': 'model-field', 'schema': {'type': 'default', 'schema': {'type': 'list', 'items_schema': _S266}, 'default_factory': list, 'default_factory_takes_data': False}}, 'hooks': {'type': 'model-field', 'schema': {'type': 'default', 'schema': _S280, 'default_factory': Hooks, 'default_factory_takes_data': False}}, 'checks': {'type': 'model-field', 'schema': {'type': 'default', 'schema': _S353, 'default_factory': Checks, 'default_factory_takes_data': False}}}, 'model_name': 'Spec', 'computed_fields': []}, 'custom_init': False, 'root_model': False, 'config': {'extra_fields_behavior': 'forbid', 'title': 'Spec'}}, 'ref': 'robospec.model.spec.Spec'}, 'definitions': [_S376, _S380, _S392, _S409, _S182, _S248, _S15]},
}
