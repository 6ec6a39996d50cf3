"""Located MJCF parsing that mirrors ManiSkill's MJCF loader (mani_skill/utils/building/
_mjcf_loader.py, ManiSkill 3.0.1), with lxml only.

What that loader turns into the robot articulation, and hence what this module reports:

* ``<include file=...>`` elements directly under ``<mujoco>`` are read relative to the file and
  their children appended after the main file's (not recursively). ``find`` then takes the first
  ``<compiler>`` and the first ``<worldbody>``.
* ``<compiler angle=...>``: ranges are in degrees unless ``angle`` is set to anything but
  "degree" (ManiSkill's default is degrees, like MuJoCo's); hinge ranges are converted to
  radians, slide ranges are kept.
* Every direct ``<body>`` of ``<worldbody>`` that has a ``<joint>`` somewhere below it (or a
  ``<freejoint>`` of its own) becomes an articulation; the robot is the first one. Its root is a
  link named ``dummy_root_{i}``, ``i`` the body's index among ``<worldbody>``'s bodies; it is free
  when the body has a ``<freejoint>``, fixed otherwise. A body holding nothing but one child body
  is skipped in favour of that child.
* A body with no ``<joint>`` hangs on a fixed joint named "". A body with ``n`` joints becomes a
  chain of ``n`` links: ``{body}_dummy_0`` ... ``{body}_dummy_{n-2}`` and finally ``{body}``,
  joint ``k`` moving link ``k``. ``<freejoint>`` below the root is ignored.
* Joint attributes merge the active defaults, then the joint's ``class``, then its own
  attributes. A body's ``childclass`` matching ``motor`` (ManiSkill's ignore list, a regex
  prefix match) drops the body and everything below it.
* hinge -> revolute (continuous when not limited), slide -> prismatic; ``limited="auto"``
  means "has a range". Ball and free joints make ManiSkill's loader fail.
* PhysX then orders the links breadth-first, exactly as for URDF (see urdf.py).

ManiSkill's link and joint names are the builder names above (``Articulation`` strips its
``scene-0-{uid}_`` prefix), so these are the names a spec must use.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from lxml import etree

from robospec.description.facts import (
    ACTIVE_JOINT_TYPES,
    Joint,
    JointType,
    Link,
    RobotDescription,
)
from robospec.description.mjcf_constraints import (
    closures,
    joint_couplings,
    mocap_welds,
    robot_names,
)
from robospec.description.mjcf_control import file_actuators, file_keyframes
from robospec.description.mjcf_frames import Unparsable, body_pose
from robospec.description.mjcf_gaps import loader_gaps
from robospec.description.mjcf_geoms import filtered_pairs
from robospec.description.mjcf_loaded import (
    Defaults,
    LoadedBody,
    LoadedMjcf,
    is_ignored_class,
    loader_classes,
    merge,
)
from robospec.description.mjcf_mujoco import Includes, read_classes
from robospec.description.mjcf_structure import unread_includes
from robospec.description.urdf import (
    at,
    bfs_order,
    did_you_mean,
    line_of,
    parse_root,
    parse_xml,
    read_file_bytes,
)
from robospec.diagnostics import Diagnostic, Location, error, note, warning
from robospec.diagnostics.codes import DESCRIPTION_NOT_FOUND, INVALID_STRUCTURE, MJCF_DEGREES
from robospec.geometry import IDENTITY_POSE

ReadFile = Callable[[str], bytes]


@dataclass
class _Node:
    """One link ManiSkill creates, with the joint that attaches it to its parent."""

    name: str
    line: int
    parent: str | None
    joint: Joint | None  # None for the dummy root
    shaped: bool = False  # it carries its body's geoms (Link.shaped)


@dataclass
class _State:
    path: str
    use_degrees: bool
    classes: dict[str, Defaults]
    class_lines: dict[str, int]
    diagnostics: list[Diagnostic]
    file_of: dict[etree._Element, str] = field(default_factory=dict)
    nodes: list[_Node] = field(default_factory=list)
    children: dict[str, list[str]] = field(default_factory=dict)
    link_lines: dict[str, tuple[str, int]] = field(default_factory=dict)
    # (parent body's link, body's link) per body, in parse order: the loader's group-2 bits
    body_pairs: list[tuple[str, str]] = field(default_factory=list)
    # the robot's bodies as the loader parses them (depth first)
    robot: list[LoadedBody] = field(default_factory=list)

    def where(self, element: etree._Element) -> Location:
        return at(self.file_of.get(element.getroottree().getroot(), self.path), element)


@dataclass(frozen=True)
class _Compiler:
    """What the loader reads of the first ``<compiler>`` (its defaults where there is none)."""

    use_degrees: bool
    eulerseq: str


@dataclass(frozen=True)
class _Robot:
    """The articulation the loader takes as the robot, as parsed into ``_State``."""

    element: etree._Element  # its <body> under <worldbody>
    body: etree._Element  # the body its root link stands for: element, or the one it wraps
    root_name: str  # its dummy root link
    floating: bool  # the body has a <freejoint>


@dataclass(frozen=True)
class _Ordered:
    """The robot's links and joints in qpos order (PhysX's breadth-first one)."""

    order: list[str]  # the link names
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]  # the named ones
    unnamed: tuple[Joint, ...]  # the nameless fixed joints of bodies without joints
    active: tuple[str, ...]


def parse_mjcf(
    text: str | bytes, path: str, read_file: ReadFile | None = None
) -> tuple[RobotDescription | None, list[Diagnostic]]:
    """Parse an MJCF into the :class:`RobotDescription` of the articulation ManiSkill builds.

    ``path`` locates diagnostics and resolves ``<include>`` files (read with ``read_file``,
    default: from disk). Never raises on bad input; the description is None when no
    articulation can be made out or any error was found.

    ``links`` are ManiSkill's links in qpos order (dummy root and dummy links included);
    ``joints`` are the named joints in the same order: the nameless fixed joints ManiSkill makes
    for bodies without joints are left out, since no spec can name them; they are
    ``unnamed_joints`` (the kinematic tree needs them).

    What ManiSkill's loader drops or reads differently is reported at the element
    (:mod:`robospec.description.mjcf_gaps`): such errors leave the description in place, since
    its names are right; only structure errors make it None.
    """
    read = read_file or read_file_bytes
    root, diagnostics = parse_root(text, path, "mujoco")
    if root is None:
        return None, diagnostics
    # the loader's parse order: includes, <compiler>, defaults, <worldbody>, the articulation
    top, file_of = _top_elements(root, path, read, diagnostics)
    if any(d.is_error for d in diagnostics):
        return None, diagnostics

    compiler_element = next((el for el in top if el.tag == "compiler"), None)
    compiler = _read_compiler(compiler_element)
    state = _State(path, compiler.use_degrees, {}, {}, diagnostics, file_of)
    if compiler_element is None or compiler_element.get("angle") is None:
        diagnostics.extend(_degrees_note(top, compiler_element, root, state))
    classes, class_lines = loader_classes(el for el in top if el.tag == "default")
    state.classes.update(classes)
    state.class_lines.update(class_lines)

    worldbody = next((el for el in top if el.tag == "worldbody"), None)
    if worldbody is None:
        diagnostics.append(error(at(path, root), INVALID_STRUCTURE, "the model has no <worldbody>"))
        return None, diagnostics

    includes = Includes(path, read, file_of)
    articulated = _articulations(root, worldbody, includes, state)
    if not articulated:
        return None, diagnostics
    robot = _parse_robot(*articulated[0], state)
    if any(d.is_error for d in diagnostics):
        return None, diagnostics

    loaded = LoadedMjcf(
        path=path,
        top=top,
        classes=state.classes,
        degrees=compiler.use_degrees,
        eulerseq=compiler.eulerseq,
        worldbody=worldbody,
        robot_element=robot.element,
        robot=state.robot,
        root_link=robot.root_name,
        where=state.where,
        includes=includes,
        mujoco_classes=read_classes(top, includes),
    )
    diagnostics.extend(loader_gaps(loaded))
    return _description(loaded, state, robot, compiler), diagnostics


def _top_elements(
    root: etree._Element, path: str, read: ReadFile, diagnostics: list[Diagnostic]
) -> tuple[list[etree._Element], dict[etree._Element, str]]:
    """``<mujoco>``'s child elements, those of its ``<include>`` files appended after the main
    file's (as the loader reads them), and the file each read root element came from."""
    file_of: dict[etree._Element, str] = {root: path}
    top: list[etree._Element] = [child for child in root if isinstance(child.tag, str)]
    for include in root.findall("include"):
        included = _read_include(include, path, read, diagnostics)
        if included is not None:
            file_of[included[0]] = included[1]
            top.extend(child for child in included[0] if isinstance(child.tag, str))
            _check_nested_includes(included[0], included[1], path, diagnostics)
    return top, file_of


def _read_compiler(compiler: etree._Element | None) -> _Compiler:
    if compiler is None:
        return _Compiler(use_degrees=True, eulerseq="xyz")
    return _Compiler(
        use_degrees=compiler.get("angle", "degree").lower() == "degree",
        eulerseq=compiler.get("eulerseq", "xyz"),
    )


def _articulations(
    root: etree._Element, worldbody: etree._Element, includes: Includes, state: _State
) -> list[tuple[int, etree._Element]]:
    """The bodies of ``<worldbody>`` that become articulations, with their index among its
    bodies: the first is the robot. Empty (an error said) when there is none; a warning for
    each other one."""
    diagnostics = state.diagnostics
    bodies = worldbody.findall("body")
    articulated = [(i, body) for i, body in enumerate(bodies) if _is_articulation(body)]
    diagnostics.extend(
        unread_includes(root, includes, state.where, articulated[0][1] if articulated else None)
    )
    if not articulated:
        diagnostics.append(
            error(
                state.where(worldbody),
                INVALID_STRUCTURE,
                "no <body> under <worldbody> has a joint; ManiSkill loads the first body tree "
                "with a joint as the robot",
            )
        )
        return []
    chosen_joints = _joint_count(articulated[0][1])
    for _, other in articulated[1:]:
        message = (
            f"body '{other.get('name', '')}' is a second articulation; ManiSkill loads only "
            "the first body tree with joints as the robot"
        )
        hint = None
        if _joint_count(other) > chosen_joints:
            # more joints than the one ManiSkill takes: likely the robot, behind an object
            message += (
                f", body '{articulated[0][1].get('name', '')}' ({chosen_joints} joint(s)), "
                f"and this one has {_joint_count(other)}"
            )
            hint = "if this is the robot, move it before the other bodies in <worldbody>"
        diagnostics.append(warning(state.where(other), INVALID_STRUCTURE, message, hint))
    return articulated


def _parse_robot(index: int, robot_element: etree._Element, state: _State) -> _Robot:
    """Parse the robot's body tree (the ``index``-th body of ``<worldbody>``) into ``state``,
    below its dummy root link."""
    root_name = f"dummy_root_{index}"
    state.nodes.append(_Node(root_name, line_of(robot_element), None, None))
    state.children[root_name] = []
    state.link_lines[root_name] = (state.path, line_of(robot_element))
    body = robot_element
    # ManiSkill skips a wrapper body that holds exactly one body and no geom or joint (its
    # root link then stands where the wrapper would).
    tags = [child.tag for child in body if isinstance(child.tag, str)]
    if tags.count("body") == 1 and "geom" not in tags and "joint" not in tags:
        body = next(body.iterchildren("body"))  # the one counted
    root_defaults = state.classes.get("__root__", {})
    _parse_body(body, root_name, None, root_defaults, state)
    floating = robot_element.find("freejoint") is not None
    return _Robot(robot_element, body, root_name, floating)


def _qpos_order(root_name: str, state: _State) -> _Ordered:
    """The parsed links and joints in the order PhysX gives them (breadth first)."""
    order = bfs_order(root_name, state.children)
    by_name = {node.name: node for node in state.nodes}
    joints: list[Joint] = []
    unnamed: list[Joint] = []
    active: list[str] = []
    for name in order[1:]:
        joint = by_name[name].joint
        if joint is None:
            continue
        if joint.type == "fixed" and not joint.name:
            unnamed.append(joint)
            continue
        joints.append(joint)
        if joint.type in ACTIVE_JOINT_TYPES:
            active.append(joint.name)
    links = tuple(Link(name, by_name[name].line, by_name[name].shaped) for name in order)
    return _Ordered(order, links, tuple(joints), tuple(unnamed), tuple(active))


def _description(
    loaded: LoadedMjcf, state: _State, robot: _Robot, compiler: _Compiler
) -> RobotDescription:
    """The description of the parsed robot, with what the file says of its control, keyframes,
    couplings, closures and contacts."""
    ordered = _qpos_order(robot.root_name, state)
    actuators = file_actuators(loaded)
    try:
        root_pose = body_pose(robot.element.attrib, compiler.use_degrees, compiler.eulerseq)
    except Unparsable:
        root_pose = IDENTITY_POSE  # the orientation report says what is wrong with it
    names = robot_names(loaded)
    return RobotDescription(
        kind="mjcf",
        path=state.path,
        links=ordered.links,
        joints=ordered.joints,
        active_joint_names=ordered.active,
        root_link=robot.root_name,
        floating_root=robot.floating,
        loader_collision_bits=_loader_collision_bits(loaded.top, state, ordered.order),
        unnamed_joints=ordered.unnamed,
        root_body_pose=root_pose,
        root_body_offset=root_pose if robot.body is robot.element else IDENTITY_POSE,
        keyframes=file_keyframes(loaded, ordered.active, root_pose),
        actuators=actuators,
        couplings=joint_couplings(
            loaded,
            names,
            {j.name: (j.lower, j.upper) for j in ordered.joints},
            frozenset(a.joint for a in actuators if a.joint is not None),
        ),
        closures=closures(loaded, names),
        mocap_welds=mocap_welds(loaded, names),
        filtered_pairs=filtered_pairs(loaded),
    )


def _loader_collision_bits(
    top: list[etree._Element], state: _State, links: list[str]
) -> tuple[tuple[int, tuple[str, ...]], ...]:
    """The group-2 bits ManiSkill's loader sets: bit ``k`` on the ``k``-th body and its parent
    body; bit 1 on every link too when ``<option><flag contact="disable"/>`` turns contacts off
    (any value but "enable" does)."""
    bits: dict[int, set[str]] = {k: set(pair) for k, pair in enumerate(state.body_pairs)}
    option = next((el for el in top if el.tag == "option"), None)
    flags = option.findall("flag") if option is not None else []
    contact = True
    for flag in flags:
        if "contact" in flag.attrib:
            contact = flag.get("contact") == "enable"
    if not contact:
        bits.setdefault(1, set()).update(links)
    order = {name: i for i, name in enumerate(links)}
    return tuple(
        (k, tuple(sorted(names, key=lambda n: order.get(n, len(order)))))
        for k, names in sorted(bits.items())
    )


def _read_include(
    include: etree._Element, path: str, read: ReadFile, diagnostics: list[Diagnostic]
) -> tuple[etree._Element, str] | None:
    file = include.get("file")
    if not file:
        diagnostics.append(error(at(path, include), INVALID_STRUCTURE, "<include> without file="))
        return None
    full = os.path.join(os.path.dirname(path), file)
    try:
        data = read(full)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        diagnostics.append(
            error(
                at(path, include),
                DESCRIPTION_NOT_FOUND,
                f"cannot read included file '{file}': {reason}",
            )
        )
        return None
    included, included_diagnostics = parse_xml(data, full)
    diagnostics.extend(included_diagnostics)
    return (included, full) if included is not None else None


def _check_nested_includes(
    included: etree._Element, file: str, model: str, diagnostics: list[Diagnostic]
) -> None:
    """ManiSkill's loader reads ``<include>`` one level deep (as we do), so one inside an
    included file is dropped without a word: an error when it names the model or the file
    itself again (a cycle MuJoCo refuses), else a warning that its contents are not loaded."""
    for nested in included.findall("include"):
        target = nested.get("file") or ""
        full = os.path.join(os.path.dirname(model), target)
        if os.path.realpath(full) in (os.path.realpath(model), os.path.realpath(file)):
            diagnostics.append(
                error(
                    at(file, nested),
                    INVALID_STRUCTURE,
                    f"include cycle: '{os.path.basename(file)}' includes '{target}', "
                    "which is already being read",
                )
            )
        else:
            diagnostics.append(
                warning(
                    at(file, nested),
                    INVALID_STRUCTURE,
                    f'<include file="{target}"> inside an included file is not read by '
                    "ManiSkill's MJCF loader: its contents are not part of the robot",
                    "include it from the main model file instead",
                )
            )


def _joint_count(body: etree._Element) -> int:
    return sum(1 for _ in body.iter("joint", "freejoint"))


def _is_articulation(body: etree._Element) -> bool:
    """ManiSkill's test: a <freejoint> on the body, or a <joint> anywhere in its tree."""
    return body.find("freejoint") is not None or next(body.iter("joint"), None) is not None


def _class_table(name: str, element: etree._Element, state: _State) -> Defaults | None:
    table = state.classes.get(name)
    if table is None:
        state.diagnostics.append(
            error(
                state.where(element),
                INVALID_STRUCTURE,
                f"unknown default class '{name}'",
                did_you_mean(name, [c for c in state.classes if c != "__root__"]),
            )
        )
    return table


def _parse_body(
    body: etree._Element,
    parent: str,
    parent_body: LoadedBody | None,
    incoming: Defaults,
    state: _State,
) -> None:
    childclass = body.get("childclass")
    defaults = incoming
    if childclass is not None:
        if is_ignored_class(childclass):
            return  # ManiSkill drops the body and its subtree
        table = _class_table(childclass, body, state)
        if table is None:
            return
        defaults = merge(incoming, table)

    body_attrib = merge(defaults.get("body", {}), dict(body.attrib))
    name = body_attrib.get("name")
    if not name:
        state.diagnostics.append(
            error(
                state.where(body),
                INVALID_STRUCTURE,
                "body without a name; ManiSkill's MJCF loader needs one for every body",
            )
        )
        return

    joint_elements = body.findall("joint")
    link_parent = parent
    if not joint_elements:
        # the loader attaches the body with a fixed joint it leaves nameless
        fixed = Joint(name="", type="fixed", parent=parent, child=name, line=line_of(body))
        _add_link(name, body, link_parent, fixed, state, shaped=body.find("geom") is not None)
        link_parent = name
    for i, joint_element in enumerate(joint_elements):
        link_name = name if i == len(joint_elements) - 1 else f"{name}_dummy_{i}"
        attributes = _joint_attributes(joint_element, defaults, state)
        if attributes is None:
            return
        joint = _make_joint(joint_element, attributes, link_parent, link_name, state)
        shaped = link_name == name and body.find("geom") is not None  # a dummy has none
        _add_link(link_name, body, link_parent, joint, state, shaped)
        link_parent = link_name

    record = LoadedBody(
        element=body,
        link=name,
        parent_link=parent,
        parent=parent_body,
        defaults=defaults,
        joints=tuple(joint_elements),
        bit=len(state.body_pairs),
    )
    state.robot.append(record)
    # ManiSkill keeps a body from colliding with its parent body (dummy links in between) by
    # giving both the next bit of collision group 2, before it parses the children
    state.body_pairs.append((parent, link_parent))
    for child in body.findall("body"):
        _parse_body(child, link_parent, record, defaults, state)


def _add_link(
    name: str,
    body: etree._Element,
    parent: str,
    joint: Joint | None,
    state: _State,
    shaped: bool = False,
) -> None:
    where = state.where(body)
    if name in state.link_lines:
        first_file, first_line = state.link_lines[name]
        first = f"line {first_line}" if first_file == where.file else f"{first_file}:{first_line}"
        state.diagnostics.append(
            error(
                where,
                INVALID_STRUCTURE,
                f"duplicate link name '{name}' (first made at {first}); ManiSkill names a "
                "body's links after the body, with '_dummy_<k>' for its extra joints",
            )
        )
        return
    state.link_lines[name] = (where.file, where.line)
    state.nodes.append(_Node(name, where.line, parent, joint, shaped))
    state.children.setdefault(parent, []).append(name)
    state.children.setdefault(name, [])


def _joint_attributes(
    element: etree._Element, defaults: Defaults, state: _State
) -> dict[str, Any] | None:
    layers: list[Mapping[str, Any]] = []
    if "joint" in defaults:
        layers.append(defaults["joint"])
    joint_class = element.get("class")
    if joint_class is not None:
        table = _class_table(joint_class, element, state)
        if table is None:
            return None
        if "joint" not in table:
            # ManiSkill indexes the class's joint defaults directly and fails with KeyError.
            state.diagnostics.append(
                error(
                    state.where(element),
                    INVALID_STRUCTURE,
                    f"default class '{joint_class}' sets no joint attributes; ManiSkill's MJCF "
                    "loader fails on a joint that names it",
                )
            )
            return None
        layers.append(table["joint"])
    layers.append(dict(element.attrib))
    return merge({}, *layers)


def _make_joint(
    element: etree._Element,
    attributes: Mapping[str, Any],
    parent: str,
    child: str,
    state: _State,
) -> Joint | None:
    name = str(attributes.get("name", ""))
    where = state.where(element)
    mj_type = str(attributes.get("type", "hinge"))
    if mj_type not in ("hinge", "slide"):
        state.diagnostics.append(
            error(
                where,
                INVALID_STRUCTURE,
                f"joint '{name}' has type '{mj_type}'; ManiSkill's MJCF loader only loads hinge "
                "and slide joints (and a <freejoint/> on the root body)",
                "a floating root: `description: {mend: {freejoint: root}}` writes it as the "
                "<freejoint/> ManiSkill reads"
                if mj_type == "free"
                else None,
            )
        )
        return None
    if not name:
        state.diagnostics.append(
            warning(
                where,
                INVALID_STRUCTURE,
                f"{mj_type} joint without a name; ManiSkill names it '' and a spec cannot "
                "refer to it",
            )
        )

    limited_attr = str(attributes.get("limited", "auto"))
    limited = "range" in attributes if limited_attr == "auto" else limited_attr == "true"
    lower: float | None = None
    upper: float | None = None
    if limited:
        raw = str(attributes.get("range", "0 0"))
        try:
            values = [float(part) for part in raw.split()]
        except ValueError:
            values = []
        if len(values) != 2 or not all(math.isfinite(v) for v in values):
            state.diagnostics.append(
                error(where, INVALID_STRUCTURE, f"joint '{name}': range=\"{raw}\" is not 2 numbers")
            )
        elif values[0] > values[1]:
            state.diagnostics.append(
                error(
                    where,
                    INVALID_STRUCTURE,
                    f"joint '{name}': range=\"{raw}\" has its lower bound above its upper bound",
                )
            )
        else:
            if mj_type == "hinge" and state.use_degrees:
                values = [math.radians(v) for v in values]
            lower, upper = values

    joint_type: JointType
    if mj_type == "hinge":
        joint_type = "revolute" if limited else "continuous"
    else:
        joint_type = "prismatic"
    return Joint(
        name=name,
        type=joint_type,
        parent=parent,
        child=child,
        line=where.line,
        lower=lower,
        upper=upper,
    )


def _degrees_note(
    top: list[etree._Element],
    compiler: etree._Element | None,
    root: etree._Element,
    state: _State,
) -> list[Diagnostic]:
    """RS086: no ``<compiler angle=...>``, so MJCF's default holds and every angle the model
    gives (``euler``, ``axisangle``, a hinge's ``range``) is in degrees. MuJoCo and ManiSkill
    agree on it; a model written in radians without saying so is turned by a factor of 57.3,
    without a word from either. Said whatever else the model says."""
    angles = [
        el
        for branch in top
        for el in branch.iter()
        if isinstance(el.tag, str)
        and (
            el.get("euler") is not None
            or el.get("axisangle") is not None
            or (
                el.tag == "joint"
                and el.get("range") is not None
                and el.get("type", "hinge") == "hinge"
            )
        )
    ]
    if not angles:
        return []
    where = state.where(compiler) if compiler is not None else at(state.path, root)
    first = state.where(angles[0])
    return [
        note(
            where,
            MJCF_DEGREES,
            f"no <compiler angle=...>: MJCF's default holds, and the model's {len(angles)} "
            f"angle(s) (euler=, axisangle=, hinge range=; the first at line {first.line}) are "
            "read as degrees by MuJoCo and ManiSkill alike",
            'if they are radians, say <compiler angle="radian"/>; if degrees, say '
            '<compiler angle="degree"/> to silence this note',
        )
    ]
