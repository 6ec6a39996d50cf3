"""The ``_controller_configs`` property and the class attributes its configs share.

As ManiSkill's own agents do, the joints a spec group names become ``<group>_joint_names``,
and a gain that several controllers of one group share is named once, ``<group>_<gain>``
(``arm_stiffness = 1e3``), each config reading ``self.arm_stiffness``.
"""

from __future__ import annotations

import ast
import keyword
import re
from collections import Counter
from dataclasses import dataclass

from robospec.emit.values import (
    NO_TYPE_PARAMS,
    FileExpression,
    assign,
    call,
    const,
    name,
    value_key,
)
from robospec.model.controller_kinds import GAINS
from robospec.resolve.resolved import ResolvedController, ResolvedRobot


@dataclass(frozen=True)
class ClassAttributes:
    """What the configs read from ``self``: ``{group: attribute}`` for joint lists and
    ``{(group, gain): (attribute, value)}`` for shared gains."""

    joint_names: dict[str, str]
    gains: dict[tuple[str, str], tuple[str, object]]

    def statements(self, robot: ResolvedRobot) -> list[list[ast.stmt]]:
        """The attribute assignments, in paragraphs: the joint lists, then each group's gains."""
        paragraphs: list[list[ast.stmt]] = []
        joints: list[ast.stmt] = []
        for group, attribute in self.joint_names.items():
            controller = next(c for c in robot.controllers if c.joints_group == group)
            joints.append(assign(attribute, const(list(controller.joint_names))))
        paragraphs.append(joints)
        by_group: dict[str, list[ast.stmt]] = {}
        for (group, _), (attribute, value) in self.gains.items():
            by_group.setdefault(group, []).append(assign(attribute, const(value)))
        paragraphs.extend(by_group.values())
        return [paragraph for paragraph in paragraphs if paragraph]


def python_name(text: str) -> str | None:
    """``text`` as part of an attribute name (non-word characters become ``_``), or None."""
    candidate = re.sub(r"\W", "_", text)
    if not candidate.isidentifier() or not candidate.isascii() or keyword.iskeyword(candidate):
        return None
    return candidate


def class_attributes(robot: ResolvedRobot, taken: set[str]) -> ClassAttributes:
    """Names for the joint lists and shared gains, none of them in ``taken`` (which grows).

    A gain is named when at least two controllers of one group set it to the same value (the
    value most of them share, if they differ). Not for a robot that extends a Python class:
    the base class may use such names for its own values."""
    joint_names: dict[str, str] = {}
    for controller in robot.controllers:
        group = controller.joints_group
        base = python_name(group) if group is not None else None
        if group is None or group in joint_names or base is None:
            continue
        joint_names[group] = _free(base + "_joint_names", taken)
    gains: dict[tuple[str, str], tuple[str, object]] = {}
    if robot.base is None:
        for (group, gain), value in _shared_gains(robot.controllers).items():
            base = python_name(group)
            if base is not None:
                gains[(group, gain)] = (_free(f"{base}_{gain}", taken), value)
    return ClassAttributes(joint_names, gains)


def _shared_gains(controllers: tuple[ResolvedController, ...]) -> dict[tuple[str, str], object]:
    counts: dict[tuple[str, str], Counter[tuple[type, str]]] = {}
    values: dict[tuple[type, str], object] = {}
    for controller in controllers:
        if controller.joints_group is None:
            continue
        for key, value in controller.kwargs:
            if key in GAINS and isinstance(value, (int, float)) and not isinstance(value, bool):
                values.setdefault(value_key(value), value)
                slot = (controller.joints_group, key)
                counts.setdefault(slot, Counter())[value_key(value)] += 1
    shared: dict[tuple[str, str], object] = {}
    for slot, counter in counts.items():
        most, count = counter.most_common(1)[0]  # ties: the first value seen
        if count >= 2:
            shared[slot] = values[most]
    # grouped as ManiSkill writes them: a group's gains together, in GAINS order
    groups = list(dict.fromkeys(group for group, _ in shared))
    return {(g, gain): shared[(g, gain)] for g in groups for gain in GAINS if (g, gain) in shared}


def _free(candidate: str, taken: set[str]) -> str:
    while candidate in taken:
        candidate += "_"
    taken.add(candidate)
    return candidate


# names pycodestyle calls ambiguous (E741): too easily read as 1 and 0
AMBIGUOUS = frozenset({"l", "I", "O"})


def variable_names(robot: ResolvedRobot, reserved: frozenset[str]) -> dict[str, str]:
    """A local variable per controller, named after it where that is a free identifier."""
    names: dict[str, str] = {}
    for index, controller in enumerate(robot.controllers):
        base = re.sub(r"\W", "_", controller.name)
        if not base.isidentifier() or keyword.iskeyword(base) or base in reserved | AMBIGUOUS:
            base = f"{base}_config" if base.isidentifier() else f"controller_{index}"
        while base in names.values():
            base += "_"
        names[controller.name] = base
    return names


def generate_controller_configs(
    robot: ResolvedRobot,
    attributes: ClassAttributes,
    variables: dict[str, str],
    files: FileExpression,
) -> ast.FunctionDef:
    used = {name for mode in robot.modes for _, name in (mode.groups or ())}
    used |= {mode.controller for mode in robot.modes if mode.controller is not None}
    body: list[ast.stmt] = []
    for controller in robot.controllers:
        if controller.name not in used:
            continue  # defined in the spec, used by no mode: a config nothing reads
        kwargs = {key: const(value, files) for key, value in controller.kwargs}
        group = controller.joints_group
        if group in attributes.joint_names:
            kwargs["joint_names"] = name("self." + attributes.joint_names[group])
        for key, value in controller.kwargs:
            shared = attributes.gains.get((group or "", key))
            if shared is not None and value_key(value) == value_key(shared[1]):
                kwargs[key] = name("self." + shared[0])
        body.append(
            assign(variables[controller.name], call(controller.kind.config_class, **kwargs))
        )
    modes: list[ast.expr] = []
    for mode in robot.modes:
        if mode.groups is None:
            modes.append(name(variables[mode.controller or ""]))
            continue
        keys: list[ast.expr | None] = [ast.Constant(group) for group, _ in mode.groups]
        values: list[ast.expr] = [name(variables[controller]) for _, controller in mode.groups]
        if mode.balance_passive_force is not None:
            keys.append(ast.Constant("balance_passive_force"))
            values.append(ast.Constant(mode.balance_passive_force))
        modes.append(ast.Dict(keys, values))
    table = ast.Dict([ast.Constant(m.name) for m in robot.modes], modes)
    # ManiSkill pops balance_passive_force out of these dicts: hand it fresh copies every time
    body.append(ast.Return(call("deepcopy_dict", [table])))
    return property_method("_controller_configs", body)


def property_method(method_name: str, body: list[ast.stmt]) -> ast.FunctionDef:
    arguments = ast.arguments([], [ast.arg("self")], None, [], [], None, [])
    return ast.FunctionDef(
        method_name, arguments, body, [ast.Name("property", ast.Load())], None, **NO_TYPE_PARAMS
    )
