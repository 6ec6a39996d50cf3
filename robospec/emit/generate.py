"""Stage 5: a resolved robot → the source of a Python module defining its agent class.

Code is built as ``ast`` nodes by small ``generate_*`` functions and laid out by
:mod:`robospec.emit.pretty`. Text from a spec only ever enters as an ``ast.Constant``; the one
identifier taken from a spec (the class name, and controller names used as variable names) is
checked with :func:`safe_identifier` first. The same function serves ``robospec build`` and
import-time registration, so the two cannot drift apart.
"""

from __future__ import annotations

import ast
import keyword
import os
import re
from pathlib import Path
from typing import Any

from robospec.emit import members as helpers
from robospec.emit.pretty import format_module
from robospec.resolve.resolved import FileRef, ResolvedCamera, ResolvedKeyframe, ResolvedRobot

CONFIG_CLASSES = {
    "pd_joint_pos": "PDJointPosControllerConfig",
    "pd_joint_pos_mimic": "PDJointPosMimicControllerConfig",
    "pd_joint_vel": "PDJointVelControllerConfig",
    "pd_joint_pos_vel": "PDJointPosVelControllerConfig",
    "pd_ee_pos": "PDEEPosControllerConfig",
    "pd_ee_pose": "PDEEPoseControllerConfig",
    "pd_base_vel": "PDBaseVelControllerConfig",
    "pd_base_forward_vel": "PDBaseForwardVelControllerConfig",
    "passive": "PassiveControllerConfig",
}
# names the generated module defines or imports: a controller variable must not shadow them
RESERVED_NAMES = frozenset(
    {
        "self",
        "os",
        "np",
        "sapien",
        "PACKAGE_ASSET_DIR",
        "ASSET_DIR",
        "BaseAgent",
        "Keyframe",
        "deepcopy_dict",
        "register_agent",
        "CameraConfig",
        "Pose",
        "link_name",
        "HERE",
        "torch",
        "common",
        "vectorize_pose",
        "importlib",
        "inspect",
        "AgentBase",
        *CONFIG_CLASSES.values(),
    }
)


class UnsafeIdentifier(ValueError):
    pass


def safe_identifier(name: str) -> str:
    if not name.isidentifier() or keyword.iskeyword(name) or not name.isascii():
        raise UnsafeIdentifier(f"{name!r} is not a valid Python identifier")
    return name


def emit_module(robot: ResolvedRobot, module_dir: Path, description_file: str | None = None) -> str:
    """The module's source. ``module_dir`` is where it will live: files on disk are named
    relative to it. ``description_file`` names the generated URDF (xacro) beside the module."""
    context = _Context(robot, module_dir, description_file)
    module = ast.Module(
        body=[*generate_header(robot, context), generate_class(robot, context)], type_ignores=[]
    )
    ast.fix_missing_locations(module)
    source = format_module(module)
    compile(source, f"<robospec:{robot.uid}>", "exec")  # never write a module that cannot load
    return source


class _Context:
    def __init__(self, robot: ResolvedRobot, module_dir: Path, description_file: str | None):
        self.robot = robot
        self.module_dir = module_dir
        self.description_file = description_file
        self.asset_folders: set[str] = set()
        self.uses_here = False
        self.imports = helpers.Imports()
        # the spec as the generated module's docstrings name it: relative to the module, so that
        # the output is the same whatever folder (or absolute path) the build was started with;
        # just its file name when that path climbs out of the module's folder, where it would
        # spell this machine's folders ("../../../home/me/specs/x.yaml")
        relative = Path(os.path.relpath(robot.spec_path, module_dir)).as_posix()
        self.spec_label = Path(robot.spec_path).name if relative.startswith("../") else relative

    def path_expr(self, ref: FileRef, *, is_description: bool = False) -> ast.expr:
        if ref.kind in ("maniskill_assets", "maniskill_data") and ref.generated_text is None:
            folder = "PACKAGE_ASSET_DIR" if ref.kind == "maniskill_assets" else "ASSET_DIR"
            self.asset_folders.add(folder)
            return ast.JoinedStr(
                [ast.FormattedValue(_name(folder), -1, None), ast.Constant("/" + ref.relative)]
            )
        self.uses_here = True
        if is_description and ref.generated_text is not None and self.description_file:
            relative = self.description_file
        else:
            relative = Path(os.path.relpath(ref.absolute, self.module_dir)).as_posix()
        return _call("os.path.join", [_name("HERE"), ast.Constant(relative)])


# -- values ------------------------------------------------------------------------------------


def _name(dotted: str) -> ast.expr:
    head, *rest = dotted.split(".")
    node: ast.expr = ast.Name(head, ast.Load())
    for attr in rest:
        node = ast.Attribute(node, attr, ast.Load())
    return node


def _call(func: str, args: list[ast.expr] | None = None, **kwargs: ast.expr) -> ast.Call:
    return ast.Call(_name(func), args or [], [ast.keyword(k, v) for k, v in kwargs.items()])


def const(value: Any, context: _Context | None = None) -> ast.expr:
    """A Python value as an expression of constants only."""
    if isinstance(value, FileRef):
        assert context is not None
        if value == context.robot.description:
            return _name("self.urdf_path")  # as ManiSkill's agents hand their URDF to IK
        return context.path_expr(value)
    if value is None or isinstance(value, (bool, int, str)):
        return ast.Constant(value)
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise ValueError("non-finite numbers never reach the emitter")
        return ast.Constant(value) if value >= 0 else ast.UnaryOp(ast.USub(), ast.Constant(-value))
    if isinstance(value, (list, tuple)):
        return ast.List([const(v, context) for v in value], ast.Load())
    if isinstance(value, dict):
        return ast.Dict([const(str(k)) for k in value], [const(v, context) for v in value.values()])
    raise TypeError(f"cannot emit {type(value).__name__}")


def _assign(target: str, value: ast.expr) -> ast.Assign:
    return ast.Assign([ast.Name(target, ast.Store())], value)


# -- module ------------------------------------------------------------------------------------


def generate_header(robot: ResolvedRobot, context: _Context) -> list[ast.stmt]:
    # the class body is generated first so we know which imports it needs
    context.class_node = _class_body(robot, context)  # type: ignore[attr-defined]
    doc = (
        f"{robot.uid}: a ManiSkill agent generated by robospec from {context.spec_label}.\n\n"
        "Do not edit: change the spec and run `robospec build` again.\n"
    )
    imports = context.imports
    base = helpers.python_ref_expr(robot.base, imports) if robot.base is not None else None
    body: list[ast.stmt] = [ast.Expr(ast.Constant(doc))]
    if imports.importlib:
        body.append(ast.Import([ast.alias("importlib")]))
    if imports.inspect:
        body.append(ast.Import([ast.alias("inspect")]))
    if context.uses_here:
        body.append(ast.Import([ast.alias("os")]))
    body.append(ast.Import([ast.alias("numpy", "np")]))
    body.append(ast.Import([ast.alias("sapien")]))
    if imports.torch:
        body.append(ast.Import([ast.alias("torch")]))
    if context.asset_folders:
        names = [ast.alias(n) for n in sorted(context.asset_folders)]
        body.append(ast.ImportFrom("mani_skill", names, 0))
    body.append(
        ast.ImportFrom(
            "mani_skill.agents.base_agent", [ast.alias("BaseAgent"), ast.alias("Keyframe")], 0
        )
    )
    if "controllers" in robot.declared:
        config_classes = sorted({CONFIG_CLASSES[c.type] for c in robot.controllers})
        body.append(
            ast.ImportFrom(
                "mani_skill.agents.controllers",
                [ast.alias(n) for n in [*config_classes, "deepcopy_dict"]],
                0,
            )
        )
    body.append(ast.ImportFrom("mani_skill.agents.registration", [ast.alias("register_agent")], 0))
    if robot.cameras and "cameras" in robot.declared:
        body.append(ast.ImportFrom("mani_skill.sensors.camera", [ast.alias("CameraConfig")], 0))
    if imports.common:
        body.append(ast.ImportFrom("mani_skill.utils", [ast.alias("common")], 0))
    pose_names = [
        name
        for name, used in (
            ("Pose", imports.pose or (robot.cameras and "cameras" in robot.declared)),
            ("vectorize_pose", imports.vectorize_pose),
        )
        if used
    ]
    if pose_names:
        body.append(
            ast.ImportFrom("mani_skill.utils.structs.pose", [ast.alias(n) for n in pose_names], 0)
        )
    if base is not None:
        body.append(_assign("AgentBase", base))
    if context.uses_here:
        body.append(
            _assign(
                "HERE", _call("os.path.dirname", [_call("os.path.abspath", [_name("__file__")])])
            )
        )
    return body


def generate_class(robot: ResolvedRobot, context: _Context) -> ast.ClassDef:
    decorator_args: dict[str, ast.expr] = {}
    if robot.download_ids:
        decorator_args["asset_download_ids"] = const(list(robot.download_ids))
    if robot.override:
        decorator_args["override"] = ast.Constant(True)
    return ast.ClassDef(
        name=safe_identifier(robot.class_name),
        bases=[_name("AgentBase" if robot.base is not None else "BaseAgent")],
        keywords=[],
        body=context.class_node,  # type: ignore[attr-defined]
        decorator_list=[_call("register_agent", **decorator_args)],
        type_params=[],
    )


def _class_body(robot: ResolvedRobot, context: _Context) -> list[ast.stmt]:
    doc = f"Agent '{robot.uid}', compiled from {context.spec_label}."
    declared = robot.declared
    body: list[ast.stmt] = [ast.Expr(ast.Constant(doc)), _assign("uid", ast.Constant(robot.uid))]
    if "description" in declared:
        path_attr = "mjcf_path" if robot.description_kind == "mjcf" else "urdf_path"
        body.append(_assign(path_attr, context.path_expr(robot.description, is_description=True)))
    if "loader" in declared:
        body.append(_assign("fix_root_link", ast.Constant(robot.fix_root_link)))
        body.append(
            _assign("load_multiple_collisions", ast.Constant(robot.load_multiple_collisions))
        )
        body.append(_assign("disable_self_collisions", ast.Constant(robot.disable_self_collisions)))
    if robot.urdf_config and "urdf_config" in declared:
        body.append(_assign("urdf_config", const(robot.urdf_config)))
    if "keyframes" in declared:
        body.append(_assign("keyframes", generate_keyframes(robot.keyframes)))
    if "controllers" in declared:
        for group, attribute in _group_attributes(robot).items():
            joints = next(c.joint_names for c in robot.controllers if c.joints_group == group)
            body.append(_assign(attribute, const(list(joints))))
        body.append(generate_controller_configs(robot, context))
    if robot.cameras and "cameras" in declared:
        body.append(generate_sensor_configs(robot.cameras))
    body.extend(generate_members(robot, context.imports))
    return body


def generate_members(robot: ResolvedRobot, imports: helpers.Imports) -> list[ast.stmt]:
    """Hooks and task-facing helpers, after the data ManiSkill reads."""
    body: list[ast.stmt] = []
    loading = helpers.generate_after_loading_articulation(robot, imports)
    if loading is not None:
        body.append(loading)
    after_init = generate_after_init(robot, imports)
    if after_init is not None:
        body.append(after_init)
    body.extend(helpers.generate_tcp_members(robot, imports))
    body.extend(helpers.generate_grasping(check, robot, imports) for check in robot.grasping)
    if robot.is_static is not None:
        body.append(helpers.generate_is_static(robot.is_static, imports))
    if robot.is_standing is not None:
        body.append(helpers.generate_is_standing(robot.is_standing, imports))
    if robot.is_fallen is not None:
        body.append(helpers.generate_is_fallen(robot.is_fallen, imports))
    body.extend(helpers.generate_link_state(state, robot, imports) for state in robot.link_states)
    proprioception = helpers.generate_proprioception(robot)
    if proprioception is not None:
        body.append(proprioception)
    for name, ref in robot.hooks.methods:
        body.append(_assign(safe_identifier(name), helpers.python_ref_expr(ref, imports)))
    return body


def generate_keyframes(keyframes: tuple[ResolvedKeyframe, ...]) -> ast.expr:
    values: list[ast.expr] = []
    for frame in keyframes:
        kwargs: dict[str, ast.expr] = {"pose": _pose("sapien.Pose", frame.p, frame.q)}
        if frame.qpos is not None:
            kwargs["qpos"] = _call("np.array", [const(list(frame.qpos))])
        if frame.qvel is not None:
            kwargs["qvel"] = _call("np.array", [const(list(frame.qvel))])
        values.append(_call("Keyframe", **kwargs))
    return ast.Dict([ast.Constant(f.name) for f in keyframes], values)


def _pose(factory: str, p: tuple[float, ...], q: tuple[float, ...]) -> ast.Call:
    return _call(factory, p=const(list(p)), q=const(list(q)))


def _variable_names(robot: ResolvedRobot) -> dict[str, str]:
    names: dict[str, str] = {}
    for index, controller in enumerate(robot.controllers):
        base = re.sub(r"\W", "_", controller.name)
        if not base.isidentifier() or keyword.iskeyword(base) or base in RESERVED_NAMES:
            base = f"{base}_config" if base.isidentifier() else f"controller_{index}"
        while base in names.values():
            base += "_"
        names[controller.name] = safe_identifier(base)
    return names


def _group_attributes(robot: ResolvedRobot) -> dict[str, str]:
    """Groups that controllers use whole become ``<group>_joint_names`` class attributes."""
    attributes: dict[str, str] = {}
    for controller in robot.controllers:
        group = controller.joints_group
        if group is None or group in attributes:
            continue
        attribute = re.sub(r"\W", "_", group) + "_joint_names"
        if attribute.isidentifier() and attribute.isascii():
            attributes[group] = safe_identifier(attribute)
    return attributes


def generate_controller_configs(robot: ResolvedRobot, context: _Context) -> ast.FunctionDef:
    variables = _variable_names(robot)
    attributes = _group_attributes(robot)
    body: list[ast.stmt] = []
    for controller in robot.controllers:
        kwargs = {key: const(value, context) for key, value in controller.kwargs}
        if controller.joints_group in attributes:
            kwargs["joint_names"] = _name("self." + attributes[controller.joints_group])
        body.append(
            _assign(variables[controller.name], _call(CONFIG_CLASSES[controller.type], **kwargs))
        )
    modes: list[ast.expr] = []
    for mode in robot.modes:
        if mode.groups is None:
            modes.append(_name(variables[mode.controller or ""]))
            continue
        keys: list[ast.expr | None] = [ast.Constant(group) for group, _ in mode.groups]
        values: list[ast.expr] = [_name(variables[name]) for _, name in mode.groups]
        if mode.balance_passive_force is not None:
            keys.append(ast.Constant("balance_passive_force"))
            values.append(ast.Constant(mode.balance_passive_force))
        modes.append(ast.Dict(keys, values))
    table = ast.Dict([ast.Constant(m.name) for m in robot.modes], modes)
    # ManiSkill pops balance_passive_force out of these dicts: hand it fresh copies every time
    body.append(ast.Return(_call("deepcopy_dict", [table])))
    return _property("_controller_configs", body)


def generate_sensor_configs(cameras: tuple[ResolvedCamera, ...]) -> ast.FunctionDef:
    configs: list[ast.expr] = []
    for camera in cameras:
        kwargs: dict[str, ast.expr] = {
            "uid": ast.Constant(camera.uid),
            "pose": _call("Pose.create_from_pq", [const(list(camera.p)), const(list(camera.q))]),
            "width": ast.Constant(camera.width),
            "height": ast.Constant(camera.height),
        }
        if camera.fov is not None:
            kwargs["fov"] = const(camera.fov)
        if camera.intrinsic is not None:
            kwargs["intrinsic"] = _call("np.array", [const([list(r) for r in camera.intrinsic])])
        kwargs["near"] = const(camera.near)
        kwargs["far"] = const(camera.far)
        kwargs["entity_uid"] = ast.Constant(camera.mount)
        if camera.shader_pack != "minimal":
            kwargs["shader_pack"] = ast.Constant(camera.shader_pack)
        configs.append(_call("CameraConfig", **kwargs))
    return _property("_sensor_configs", [ast.Return(ast.List(configs, ast.Load()))])


def generate_after_init(robot: ResolvedRobot, imports: helpers.Imports) -> ast.FunctionDef | None:
    body: list[ast.stmt] = helpers.generate_after_init_helpers(robot)
    for rule in robot.collision_rules:
        link = ast.Subscript(_name("self.robot.links_map"), _name("link_name"), ast.Load())
        call = ast.Call(
            ast.Attribute(link, "set_collision_group_bit", ast.Load()),
            [],
            [
                ast.keyword("group", ast.Constant(rule.group)),
                ast.keyword("bit_idx", ast.Constant(rule.bit)),
                ast.keyword("bit", ast.Constant(rule.value)),
            ],
        )
        body.append(
            ast.For(
                ast.Name("link_name", ast.Store()), const(list(rule.links)), [ast.Expr(call)], []
            )
        )
    if robot.hooks.after_init is not None:
        hook = helpers.python_ref_expr(robot.hooks.after_init, imports)
        body.append(ast.Expr(ast.Call(hook, [_name("self")], [])))
    if not body:
        return None
    if robot.base is not None:
        body[:0] = helpers.template("super()._after_init()")
    return helpers.method("_after_init", body)


def _property(name: str, body: list[ast.stmt]) -> ast.FunctionDef:
    return helpers.as_property(helpers.method(name, body))
