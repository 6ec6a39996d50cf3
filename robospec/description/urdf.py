"""Located URDF parsing: the facts robospec needs, in SAPIEN's order, with source lines.

Only lxml is used (no yourdfpy/trimesh/SAPIEN): this runs on the fast validation path.

The order rule (verified against SAPIEN 3.0.3 for every URDF agent ManiSkill 3.0.1 bundles, see
tests/test_description_urdf.py): SAPIEN's URDF loader creates links depth-first from the root,
children in the order their joints appear in the file; PhysX then re-sorts the links of an
articulation breadth-first, keeping that creation order among siblings. ``robot.links``,
``robot.joints`` and ``robot.active_joints`` (hence qpos) follow that breadth-first order. So the
order is plain BFS from the root with siblings in joint declaration order — not DFS (panda's
fingertip pads come after both fingers; fetch's head and arm joints interleave).
"""

from __future__ import annotations

import dataclasses
import errno
import os
import re
import stat
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from lxml import etree

from robospec.description.facts import (
    ACTIVE_JOINT_TYPES,
    Joint,
    JointType,
    Link,
    Mimic,
    RobotDescription,
)
from robospec.description.inertia import check_inertials
from robospec.description.meshes import check_mesh_files
from robospec.description.sanity import check_sanity
from robospec.description.source_columns import element_at
from robospec.description.urdf_loader_rules import check_loader_rules
from robospec.description.urdf_values import read_floats
from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.diagnostics.codes import INVALID_STRUCTURE, MALFORMED_XML
from robospec.diagnostics.suggest import did_you_mean

# Joint types urchin (SAPIEN's URDF reader) accepts; anything else fails the load.
URDF_JOINT_TYPES: frozenset[str] = frozenset(
    {"revolute", "continuous", "prismatic", "fixed", "floating", "planar"}
)

# libxml2 appends ", line L, column C" to its messages; the location already says that.
_LXML_POSITION_SUFFIX = re.compile(r",\s*line \d+, column \d+\s*$")


# --------------------------------------------------------------------------------------------
# Helpers shared with the MJCF parser


def read_file_bytes(path: str) -> bytes:
    """A description file's bytes. Only a regular file is opened: reading a FIFO (or a device)
    named as a description would wait for a writer forever. Raises OSError as ``open`` does."""
    status = os.stat(path)
    if stat.S_ISDIR(status.st_mode):
        raise IsADirectoryError(errno.EISDIR, "it is a folder", path)
    if not stat.S_ISREG(status.st_mode):
        raise OSError(errno.EINVAL, "not a regular file", path)
    with open(path, "rb") as handle:
        return handle.read()


def line_of(element: etree._Element) -> int:
    """The 1-based source line of ``element`` (1 when lxml does not know it)."""
    line = element.sourceline
    return line if isinstance(line, int) and line > 0 else 1


def at(path: str, element: etree._Element | None) -> Location:
    if element is None:
        return Location(path, 1, 1)
    return element_at(path, element)


def parse_xml(text: str | bytes, path: str) -> tuple[etree._Element | None, list[Diagnostic]]:
    """Parse XML safely (no entity expansion, no network); a syntax error becomes RS051."""
    if isinstance(text, str):
        # A str has already been decoded: force UTF-8 for its bytes whatever the XML
        # declaration says (lxml refuses a str that carries an encoding declaration).
        data = text.encode("utf-8")
        encoding: str | None = "utf-8"
    else:
        data = text
        encoding = None
    parser = etree.XMLParser(
        resolve_entities=False,  # no billion-laughs, no reading files through entities
        no_network=True,
        load_dtd=False,
        remove_blank_text=False,
        encoding=encoding,
    )
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        line, column = exc.position if exc.position else (exc.lineno or 1, 1)
        message = _LXML_POSITION_SUFFIX.sub("", exc.msg or str(exc))
        location = Location(path, max(int(line or 1), 1), max(int(column or 1), 1))
        return None, [error(location, MALFORMED_XML, f"not well-formed XML: {message}")]
    return root, []


def parse_root(
    text: str | bytes, path: str, tag: str
) -> tuple[etree._Element | None, list[Diagnostic]]:
    """Parse the XML and insist on its root element (``robot`` for URDF, ``mujoco`` for MJCF)."""
    root, diagnostics = parse_xml(text, path)
    if root is not None and root.tag != tag:
        diagnostics.append(
            error(at(path, root), INVALID_STRUCTURE, f"root element is <{root.tag!s}>, not <{tag}>")
        )
        return None, diagnostics
    return root, diagnostics


def bfs_order(root: str, children: Mapping[str, Sequence[str]]) -> list[str]:
    """Links in PhysX's order: breadth-first from ``root``, siblings in creation order."""
    order = [root]
    queue = deque([root])
    while queue:
        for child in children.get(queue.popleft(), ()):
            order.append(child)
            queue.append(child)
    return order


# --------------------------------------------------------------------------------------------
# URDF


@dataclass
class _RawJoint:
    name: str
    type: str
    parent: str
    child: str
    element: etree._Element
    lower: float | None = None
    upper: float | None = None
    velocity: float | None = None
    effort: float | None = None
    mimic: Mimic | None = None
    mimic_element: etree._Element | None = None


def parse_urdf(
    text: str | bytes,
    path: str,
    *,
    look_for_files: bool = False,
    packages: Mapping[str, str] | None = None,
) -> tuple[RobotDescription | None, list[Diagnostic]]:
    """Parse a URDF into a :class:`RobotDescription` located in ``path``.

    Never raises on bad input. The description is None when the kinematic tree cannot be built
    (malformed XML, duplicate or missing names, unknown links, cycles, several roots); errors
    that leave the tree intact (bad limits, an unknown mimic target, joint types SAPIEN cannot
    load) come with a description so later checks still run. What SAPIEN's parser needs beyond
    the tree (robospec.description.urdf_loader_rules) and the inertials
    (robospec.description.inertia) are checked in every case.

    With ``look_for_files``, the meshes and textures the URDF names are looked for relative to
    ``path``'s folder, ``package://`` URIs with ``packages`` first
    (robospec.description.meshes), and the description's ``mesh_files`` say where.

    ``links`` are the links of the articulation ManiSkill loads, in SAPIEN's order; ``joints``
    hold one joint per link after the root, in the same order (fixed ones included).
    """
    root, diagnostics = parse_root(text, path, "robot")
    if root is None:
        return None, diagnostics
    description = _kinematic_tree(root, path, diagnostics)
    diagnostics[:] = _fold_joint_types(diagnostics)
    diagnostics.extend(check_loader_rules(root, path))
    diagnostics.extend(check_inertials(root, path))
    if look_for_files:
        mesh_files, mesh_diagnostics = check_mesh_files(root, path, packages)
        diagnostics.extend(mesh_diagnostics)
        diagnostics.extend(check_sanity(root, path, mesh_files, packages))
        if description is not None:
            description = dataclasses.replace(description, mesh_files=mesh_files)
    return description, diagnostics


def _kinematic_tree(
    root: etree._Element, path: str, diagnostics: list[Diagnostic]
) -> RobotDescription | None:
    """The articulation ManiSkill loads from the URDF ``root``; None when there is no tree."""
    links, links_fatal = _read_links(root, path, diagnostics)
    raw_joints, parent_joint, joints_fatal = _read_joints(root, links, path, diagnostics)
    _drop_unknown_mimics(raw_joints, path, diagnostics)
    if links_fatal or joints_fatal:
        return None
    if not links:
        diagnostics.append(error(at(path, root), INVALID_STRUCTURE, "the robot has no <link>"))
        return None
    base = _single_root(links, raw_joints, parent_joint, path, diagnostics)
    if base is None:
        return None
    return _articulation(path, links, raw_joints, parent_joint, base, diagnostics)


def _read_links(
    root: etree._Element, path: str, diagnostics: list[Diagnostic]
) -> tuple[dict[str, Link], bool]:
    """The named links, in declaration order, and whether one cannot take part in a tree."""
    fatal = False
    links: dict[str, Link] = {}
    for element in root.findall("link"):
        name = element.get("name")
        if not name:
            diagnostics.append(error(at(path, element), INVALID_STRUCTURE, "link without a name"))
            fatal = True
            continue
        if name in links:
            diagnostics.append(
                error(
                    at(path, element),
                    INVALID_STRUCTURE,
                    f"duplicate link name '{name}' (first defined on line {links[name].line})",
                )
            )
            fatal = True
            continue
        links[name] = Link(name, line_of(element), element.find("collision") is not None)
    return links, fatal


def _read_joints(
    root: etree._Element, links: Mapping[str, Link], path: str, diagnostics: list[Diagnostic]
) -> tuple[dict[str, _RawJoint], dict[str, _RawJoint], bool]:
    """The joints by name, the joint that attaches each child link, and whether one cannot
    take part in a tree (a link has one parent)."""
    fatal = False
    raw_joints: dict[str, _RawJoint] = {}
    parent_joint: dict[str, _RawJoint] = {}  # child link -> the joint that attaches it
    for element in root.findall("joint"):
        raw = _read_joint(element, links, raw_joints, path, diagnostics)
        if raw is None:
            fatal = True
            continue
        raw_joints[raw.name] = raw
        earlier = parent_joint.get(raw.child)
        if earlier is not None:
            diagnostics.append(
                error(
                    at(path, element),
                    INVALID_STRUCTURE,
                    f"link '{raw.child}' is the child of joint '{raw.name}' and of joint "
                    f"'{earlier.name}' (line {line_of(earlier.element)}); a link has one parent",
                )
            )
            fatal = True
            continue
        parent_joint[raw.child] = raw
    return raw_joints, parent_joint, fatal


def _drop_unknown_mimics(
    raw_joints: Mapping[str, _RawJoint], path: str, diagnostics: list[Diagnostic]
) -> None:
    """A ``<mimic>`` of itself or of a joint that does not exist is reported and left out."""
    for raw in raw_joints.values():
        if raw.mimic is None or raw.mimic_element is None:
            continue
        target = raw.mimic.joint
        if target == raw.name:
            diagnostics.append(
                error(
                    at(path, raw.mimic_element),
                    INVALID_STRUCTURE,
                    f"joint '{raw.name}' mimics itself",
                )
            )
            raw.mimic = None
        elif target not in raw_joints:
            diagnostics.append(
                error(
                    at(path, raw.mimic_element),
                    INVALID_STRUCTURE,
                    f"joint '{raw.name}' mimics unknown joint '{target}'",
                    did_you_mean(target, list(raw_joints)),
                )
            )
            raw.mimic = None


def _single_root(
    links: Mapping[str, Link],
    raw_joints: Mapping[str, _RawJoint],
    parent_joint: Mapping[str, _RawJoint],
    path: str,
    diagnostics: list[Diagnostic],
) -> str | None:
    """The one link that is no joint's child; None (diagnostics say why) for a cycle or
    several roots."""
    roots = [name for name in links if name not in parent_joint]
    children: dict[str, list[str]] = {name: [] for name in links}
    for raw in raw_joints.values():
        children[raw.parent].append(raw.child)

    fatal = False
    reachable: set[str] = set()
    for name in roots:
        reachable.update(bfs_order(name, children))
    if len(reachable) < len(links):
        _report_cycle(links, parent_joint, reachable, path, diagnostics)
        fatal = True
    if len(roots) > 1:
        listed = ", ".join(f"'{name}' (line {links[name].line})" for name in roots)
        diagnostics.append(
            error(
                Location(path, links[roots[1]].line, 1),
                INVALID_STRUCTURE,
                f"several root links: {listed}; a robot has exactly one link that is no "
                "joint's child",
            )
        )
        fatal = True
    if fatal or not roots:
        return None
    return roots[0]


def _read_joint(
    element: etree._Element,
    links: Mapping[str, Link],
    seen: Mapping[str, _RawJoint],
    path: str,
    diagnostics: list[Diagnostic],
) -> _RawJoint | None:
    """Read one <joint>; None when it cannot take part in the tree (diagnostics say why)."""
    named = _joint_name_and_type(element, seen, path, diagnostics)
    if named is None:
        return None
    name, joint_type = named
    ends = _joint_ends(element, name, links, path, diagnostics)
    if ends is None:
        return None

    raw = _RawJoint(name, joint_type, ends[0], ends[1], element)
    what = f"joint '{name}'"
    if joint_type == "planar":
        diagnostics.append(
            error(
                at(path, element),
                INVALID_STRUCTURE,
                f"joint '{name}' is planar; SAPIEN cannot load planar joints",
                "use two prismatic joints and a revolute joint with dummy links",
            )
        )
    if joint_type in ("revolute", "prismatic"):
        _read_limits(raw, path, diagnostics)
    elif joint_type == "continuous":
        _read_rates(raw, path, diagnostics)
    # Numbers SAPIEN parses for every joint: a typo there fails the load too.
    for tag, attribute in (("origin", "xyz"), ("origin", "rpy"), ("axis", "xyz")):
        sub = element.find(tag)
        if sub is not None:
            read_floats(sub, attribute, 3, path, diagnostics, f"{what} <{tag}>")

    _read_mimic(raw, path, diagnostics)
    return raw


def _joint_name_and_type(
    element: etree._Element,
    seen: Mapping[str, _RawJoint],
    path: str,
    diagnostics: list[Diagnostic],
) -> tuple[str, str] | None:
    """A joint's unique name and known type; None (diagnostics say why) otherwise."""
    name = element.get("name")
    if not name:
        diagnostics.append(error(at(path, element), INVALID_STRUCTURE, "joint without a name"))
        return None
    if name in seen:
        first = line_of(seen[name].element)
        diagnostics.append(
            error(
                at(path, element),
                INVALID_STRUCTURE,
                f"duplicate joint name '{name}' (first defined on line {first})",
            )
        )
        return None
    joint_type = element.get("type")
    if joint_type is None:
        diagnostics.append(
            error(at(path, element), INVALID_STRUCTURE, f"joint '{name}' has no type")
        )
        return None
    if joint_type not in URDF_JOINT_TYPES:
        diagnostics.append(
            error(
                at(path, element),
                INVALID_STRUCTURE,
                f"joint '{name}' has unknown type '{joint_type}'",
                "a ball joint: `mend: {spherical: hinges}` writes it as three continuous joints"
                if joint_type in ("spherical", "ball")
                else did_you_mean(joint_type, sorted(URDF_JOINT_TYPES)),
            )
        )
        return None
    return name, joint_type


def _joint_ends(
    element: etree._Element,
    name: str,
    links: Mapping[str, Link],
    path: str,
    diagnostics: list[Diagnostic],
) -> tuple[str, str] | None:
    """A joint's parent and child links, both known and not the same; None otherwise."""
    ends: dict[str, str] = {}
    for role in ("parent", "child"):
        end = element.find(role)
        link = end.get("link") if end is not None else None
        if end is None or not link:
            diagnostics.append(
                error(
                    at(path, end if end is not None else element),
                    INVALID_STRUCTURE,
                    f"joint '{name}' has no <{role} link=\"...\"/>",
                )
            )
            continue
        if link not in links:
            diagnostics.append(
                error(
                    at(path, end),
                    INVALID_STRUCTURE,
                    f"joint '{name}' names unknown {role} link '{link}'",
                    did_you_mean(link, list(links)),
                )
            )
            continue
        ends[role] = link
    if len(ends) != 2:
        return None
    if ends["parent"] == ends["child"]:
        diagnostics.append(
            error(
                at(path, element),
                INVALID_STRUCTURE,
                f"joint '{name}' has link '{ends['parent']}' as both parent and child",
            )
        )
        return None
    return ends["parent"], ends["child"]


def _read_mimic(raw: _RawJoint, path: str, diagnostics: list[Diagnostic]) -> None:
    """Fill raw.mimic from <mimic joint= multiplier= offset=> (the target is checked later)."""
    what = f"joint '{raw.name}'"
    mimic = raw.element.find("mimic")
    if mimic is not None:
        target = mimic.get("joint")
        if not target:
            diagnostics.append(
                error(at(path, mimic), INVALID_STRUCTURE, f'{what}: <mimic> without joint="..."')
            )
        else:
            multiplier = read_floats(mimic, "multiplier", 1, path, diagnostics, f"{what} <mimic>")
            offset = read_floats(mimic, "offset", 1, path, diagnostics, f"{what} <mimic>")
            raw.mimic = Mimic(
                target,
                multiplier[0] if multiplier else 1.0,
                offset[0] if offset else 0.0,
            )
            raw.mimic_element = mimic


def _read_limits(raw: _RawJoint, path: str, diagnostics: list[Diagnostic]) -> None:
    """Fill raw.lower/upper from <limit>; SAPIEN needs both for revolute and prismatic joints."""
    limit = raw.element.find("limit")
    if limit is None:
        diagnostics.append(
            error(
                at(path, raw.element),
                INVALID_STRUCTURE,
                f"{raw.type} joint '{raw.name}' has no <limit>",
                'add <limit lower="..." upper="..." effort="..." velocity="..."/>',
            )
        )
        return
    what = f"joint '{raw.name}' <limit>"
    values: dict[str, float] = {}
    for attribute in ("lower", "upper"):
        if limit.get(attribute) is None:
            # urchin leaves it None and SAPIEN turns it into a NaN limit.
            diagnostics.append(
                error(
                    at(path, limit),
                    INVALID_STRUCTURE,
                    f"{what} has no {attribute}=; SAPIEN would make the limit NaN",
                )
            )
            continue
        parsed = read_floats(limit, attribute, 1, path, diagnostics, what)
        if parsed is not None:
            values[attribute] = parsed[0]
    _read_rates(raw, path, diagnostics)
    lower, upper = values.get("lower"), values.get("upper")
    if lower is not None and upper is not None and lower > upper:
        diagnostics.append(
            error(
                at(path, limit),
                INVALID_STRUCTURE,
                f"{what} has lower={lower:g} above upper={upper:g}",
            )
        )
        return
    raw.lower, raw.upper = lower, upper


def _read_rates(raw: _RawJoint, path: str, diagnostics: list[Diagnostic]) -> None:
    """Fill raw.velocity/effort from <limit> (optional: `robospec inspect` shows them)."""
    limit = raw.element.find("limit")
    if limit is None:
        return
    what = f"joint '{raw.name}' <limit>"
    velocity = read_floats(limit, "velocity", 1, path, diagnostics, what)
    effort = read_floats(limit, "effort", 1, path, diagnostics, what)
    raw.velocity = velocity[0] if velocity else None
    raw.effort = effort[0] if effort else None


def _report_cycle(
    links: Mapping[str, Link],
    parent_joint: Mapping[str, _RawJoint],
    reachable: set[str],
    path: str,
    diagnostics: list[Diagnostic],
) -> None:
    """One diagnostic per cycle among the links no root reaches (each has exactly one parent)."""
    reported: set[str] = set()
    for start in links:
        if start in reachable or start in reported:
            continue
        trail: list[str] = []
        current = start
        while current not in trail and current not in reported:
            trail.append(current)
            current = parent_joint[current].parent
        if current in reported:
            reported.update(trail)
            continue
        cycle = trail[trail.index(current) :]
        reported.update(trail)
        joints = [parent_joint[name] for name in cycle]
        first = min(joints, key=lambda raw: line_of(raw.element))
        names = " -> ".join(f"'{raw.name}'" for raw in reversed(joints))
        diagnostics.append(
            error(
                at(path, first.element),
                INVALID_STRUCTURE,
                f"joints form a cycle: {names}",
            )
        )


def _articulation(
    path: str,
    links: Mapping[str, Link],
    raw_joints: Mapping[str, _RawJoint],
    parent_joint: Mapping[str, _RawJoint],
    base: str,
    diagnostics: list[Diagnostic],
) -> RobotDescription:
    """Pick the articulation ManiSkill keeps and list it in PhysX's order.

    SAPIEN splits the tree at floating joints: the base link and every child of a floating
    joint each root a separate object, and ManiSkill's BaseAgent keeps only the first one that
    has joints (``parse(...)["articulation_builders"][0]``).
    """
    children, roots = _split_at_floating(path, links, raw_joints, base, diagnostics)
    chosen = next((name for name in roots if children[name]), None)
    if chosen is None:
        diagnostics.append(
            error(
                Location(path, links[base].line, 1),
                INVALID_STRUCTURE,
                "the robot has no joints to articulate; ManiSkill loads a robot as an "
                "articulation and needs at least one non-floating joint",
            )
        )
        chosen = base
    order = bfs_order(chosen, children)
    articulated = set(order)  # built once: rebuilding it per link made this quadratic
    dropped = [name for name in links if name not in articulated]
    # The usual "world --floating--> base" pattern drops only the empty world link: expected.
    if dropped and not (chosen != base and dropped == [base]):
        shown = ", ".join(f"'{name}'" for name in dropped[:5])
        more = f" and {len(dropped) - 5} more" if len(dropped) > 5 else ""
        diagnostics.append(
            warning(
                Location(path, links[dropped[0]].line, 1),
                INVALID_STRUCTURE,
                f"links {shown}{more} are not part of the articulation ManiSkill loads "
                f"(rooted at '{chosen}'); floating joints split the tree",
            )
        )

    joints = _joints_in_order(order, parent_joint)
    return RobotDescription(
        kind="urdf",
        path=path,
        links=tuple(links[name] for name in order),
        joints=tuple(joints),
        active_joint_names=tuple(j.name for j in joints if j.type in ACTIVE_JOINT_TYPES),
        root_link=chosen,
        floating_root=chosen != base,
    )


def _split_at_floating(
    path: str,
    links: Mapping[str, Link],
    raw_joints: Mapping[str, _RawJoint],
    base: str,
    diagnostics: list[Diagnostic],
) -> tuple[dict[str, list[str]], list[str]]:
    """Each link's children through joints that are not floating, and the roots of the
    objects SAPIEN builds: the base link, then each floating joint's child."""
    children: dict[str, list[str]] = {name: [] for name in links}
    roots = [base]
    for raw in raw_joints.values():  # declaration order, as SAPIEN builds them
        if raw.type == "floating":
            if raw.parent != base:
                diagnostics.append(
                    error(
                        at(path, raw.element),
                        INVALID_STRUCTURE,
                        f"floating joint '{raw.name}' is not attached to the root link "
                        f"'{base}'; SAPIEN only loads floating joints from the root",
                    )
                )
            roots.append(raw.child)
            continue
        children[raw.parent].append(raw.child)

    for raw in raw_joints.values():
        if raw.type == "floating" and raw.parent == base and children[raw.child]:
            # SAPIEN 3.0.3's _parse_articulation looks up the builder of the floating joint's
            # parent, which lives in another object: KeyError. So such a URDF never loads.
            diagnostics.append(
                error(
                    at(path, raw.element),
                    INVALID_STRUCTURE,
                    f"floating joint '{raw.name}': SAPIEN's URDF loader fails on a floating "
                    "joint whose child has children",
                    f"remove link '{base}' and joint '{raw.name}' and load the robot with "
                    "fix_root_link: false",
                )
            )

    return children, roots


def _joints_in_order(order: Sequence[str], parent_joint: Mapping[str, _RawJoint]) -> list[Joint]:
    """The joints attaching the links of ``order`` after its root, as robospec's facts."""
    joints: list[Joint] = []
    for name in order[1:]:
        raw = parent_joint[name]
        joint_type: JointType = raw.type  # type: ignore[assignment]  # checked in _read_joint
        lower, upper = (
            (raw.lower, raw.upper) if raw.type in ("revolute", "prismatic") else (None, None)
        )
        joints.append(
            Joint(
                name=raw.name,
                type=joint_type,
                parent=raw.parent,
                child=raw.child,
                line=line_of(raw.element),
                lower=lower,
                upper=upper,
                mimic=raw.mimic,
                velocity=raw.velocity,
                effort=raw.effort,
            )
        )
    return joints


_UNKNOWN_TYPE = re.compile(r"^joint '.*' has unknown type '(?P<type>[^']*)'$")


def _fold_joint_types(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """Joints of one unknown type (pybullet's humanoid has eight spherical ones) are one
    diagnostic, at the first, naming the lines of the others."""
    from robospec.description.urdf_values import Findings

    found = Findings()
    for d in diagnostics:
        match = _UNKNOWN_TYPE.match(d.message)
        if match is None:
            found.add(d)
        else:
            found.add(d, fold_as=f"more joints of type '{match['type']}'")
    return sorted(found.result(), key=lambda d: (d.location.line, d.code))
