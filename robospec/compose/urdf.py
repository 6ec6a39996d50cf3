"""Mount URDF parts on a URDF robot: the part's links and joints appended to the robot's, its
root fixed to the mount link by a joint of the part's name, names that clash prefixed, and the
files it names written as paths from the robot's folder (so the combined text loads from there,
as ManiSkill's own combined files do)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass

from lxml import etree

from robospec.compose.model import BaseSource, Composed, Mounted, Origins, PartSource, Problem
from robospec.compose.order import mount_order
from robospec.compose.xml import (
    Provenance,
    append_lines,
    comment_text,
    number,
    parse,
    relative_file,
    written,
)
from robospec.diagnostics.codes import (
    NAME_CLASH,
    NOTHING_TO_FOLD,
    PART_NOT_A_FIXED_TREE,
    PART_PREFIXED,
)
from robospec.geometry import Pose, compose, quaternion_from_rpy, rpy_from_quaternion

INDENT = "  "


def compose_urdf(base: BaseSource, parts: Sequence[PartSource]) -> Composed:
    root = parse(base.text)
    if root is None or root.tag != "robot":
        return Composed("urdf", None, Origins(()))  # the base's own parse says what is wrong
    provenance = Provenance()
    provenance.remember(root.iter(etree.Element), base.shown, path=base.path)
    trees: dict[str, etree._Element] = {}
    problems: list[Problem] = []
    for part in parts:
        tree = parse(part.text)
        if tree is None or tree.tag != "robot":
            continue  # reported by the part's own compilation
        trees[part.name] = tree
    links_of = {name: _names(tree, "link") for name, tree in trees.items()}
    ordered, order_problems = mount_order(
        _names(root, "link"), [p for p in parts if p.name in trees], links_of
    )
    problems.extend(order_problems)
    mounted: list[Mounted] = []
    base_folder = os.path.dirname(base.path)
    for part in ordered:
        result, found = _mount(root, trees[part.name], part, mounted, base_folder, provenance)
        problems.extend(found)
        if result is not None:
            mounted.append(result)
            if result.renamed:
                problems.append(_prefixed_note(part, result))
    if any(p.severity == "error" for p in problems):
        return Composed("urdf", None, Origins(()), tuple(mounted), tuple(problems))
    first_line = root.sourceline if isinstance(root.sourceline, int) else 1
    text, origins = written(root, provenance, first_line)
    return Composed("urdf", text, origins, tuple(mounted), tuple(problems))


def _names(root: etree._Element, tag: str) -> list[str]:
    return [str(e.get("name")) for e in root.findall(tag) if e.get("name")]


def _mount(
    root: etree._Element,
    tree: etree._Element,
    part: PartSource,
    mounted: list[Mounted],
    base_folder: str,
    provenance: Provenance,
) -> tuple[Mounted | None, list[Problem]]:
    """Mount ``part`` (its tree) on ``root``: the part as mounted, or None, and the problems."""
    root_name = _part_root(tree, part)
    if isinstance(root_name, Problem):
        return None, [root_name]
    place, problems = _placement(root, tree, part, root_name, mounted)
    links, joints = _names(tree, "link"), _names(tree, "joint")  # without a folded root frame
    names = _part_names(root, tree, part, place, links, joints, problems)
    if any(p.severity == "error" for p in problems):
        return None, problems
    return _write_part(root, tree, part, place, names, base_folder, provenance), problems


def _part_root(tree: etree._Element, part: PartSource) -> str | Problem:
    """The part's one root link, or RS731 when its links hang from none or several."""
    links = _names(tree, "link")
    children = {c.get("link") for j in tree.findall("joint") for c in j.findall("child")} - {None}
    roots = [name for name in links if name not in children]
    if len(roots) == 1:
        return roots[0]
    what = (
        "no root link (every link is a joint's child)"
        if not roots
        else (f"{len(roots)} root links ({', '.join(roots[:4])})")
    )
    return Problem(
        ("parts", part.name, part.key),
        PART_NOT_A_FIXED_TREE,
        f"part '{part.name}' is not one tree of links: its description has {what}",
        "mount a description whose links hang from one root",
    )


@dataclass(frozen=True)
class _Placement:
    """Where a part hangs once empty frames are folded away (``fold_frames``)."""

    at: str  # the link it is mounted on
    pose: Pose  # its root's pose there
    root: str  # the part's root link
    folded: tuple[str, ...]  # the frames left out, and the part's joint that held its root
    holder: etree._Element | None  # the robot's joint that held a folded mount frame
    taken_links: frozenset[str]  # the robot's links, less a folded mount frame


def _placement(
    root: etree._Element,
    tree: etree._Element,
    part: PartSource,
    root_name: str,
    mounted: list[Mounted],
) -> tuple[_Placement, list[Problem]]:
    """Where the part goes, with its empty root frame and an empty mount frame folded away
    (removed from ``tree`` and ``root``), and a warning (RS741) when ``fold_frames`` finds
    neither."""
    taken_links = set(_names(root, "link"))
    pose = (part.position, part.quaternion)
    folded: list[str] = []
    inner = None
    if part.fold_frames:
        found = _root_frame(tree, root_name)
        if found is not None:
            frame, joint, inner = found
            root_name = str(joint.find("child").get("link"))  # type: ignore[union-attr]
            folded += [str(frame.get("name")), str(joint.get("name"))]
            tree.remove(frame)
            tree.remove(joint)
    at = _mount_link(part.at, taken_links, mounted)
    holder = _leaf_frame(root, at) if part.fold_frames else None
    if holder is not None:
        frame, holder_joint, outer = holder
        folded.insert(0, at)
        at = str(holder_joint.find("parent").get("link"))  # type: ignore[union-attr]
        pose = compose(outer, pose)
        root.remove(frame)
        taken_links.discard(str(frame.get("name")))
    problems: list[Problem] = []
    if part.fold_frames and not folded:
        problems.append(
            Problem(
                ("parts", part.name, "fold_frames"),
                NOTHING_TO_FOLD,
                f"fold_frames: neither '{part.at}' nor the root of part '{part.name}' is an "
                "empty frame that can be left out",
                "remove fold_frames (an empty frame is a link with nothing in it, fixed to "
                "one other link)",
                severity="warning",
            )
        )
    if inner is not None:
        pose = compose(pose, inner)
    place = _Placement(
        at,
        pose,
        root_name,
        tuple(folded),
        holder[1] if holder is not None else None,
        frozenset(taken_links),
    )
    return place, problems


@dataclass(frozen=True)
class _PartNames:
    """The part's names in the combined description (a material the robot defines alike:
    None), and the name of the joint that mounts it."""

    links: dict[str, str]
    joints: dict[str, str]
    materials: dict[str, str | None]
    mount_joint: str


def _part_names(
    root: etree._Element,
    tree: etree._Element,
    part: PartSource,
    place: _Placement,
    links: list[str],
    joints: list[str],
    problems: list[Problem],
) -> _PartNames:
    """The part's links, joints and materials renamed where the robot has them; a clash each
    is a problem (RS732), and so is a mount joint named as one of the robot's."""
    taken_joints = set(_names(root, "joint"))
    if place.holder is not None:
        taken_joints.discard(str(place.holder.get("name")))
    link_names = _renames(part, "link", links, place.taken_links, problems)
    joint_names = _renames(part, "joint", joints, taken_joints, problems)
    materials = _material_renames(root, tree, part, problems)
    mount_joint = part.joint
    if place.holder is not None and not part.joint_given:
        mount_joint = str(place.holder.get("name"))  # the frame's joint now holds the part
    if mount_joint in taken_joints or mount_joint in joint_names.values():
        problems.append(
            Problem(
                ("parts", part.name, "joint"),
                NAME_CLASH,
                f"the joint that mounts part '{part.name}', '{mount_joint}', has the name of "
                "a joint the robot already has",
                "name it with `joint:`",
            )
        )
    return _PartNames(link_names, joint_names, materials, mount_joint)


def _write_part(
    root: etree._Element,
    tree: etree._Element,
    part: PartSource,
    place: _Placement,
    names: _PartNames,
    base_folder: str,
    provenance: Provenance,
) -> Mounted:
    """The part renamed and appended to ``root`` after a comment, with the fixed joint that
    mounts it (or the folded frame's joint holding it)."""
    links, joints = _names(tree, "link"), _names(tree, "joint")  # the part's own names
    materials = names.materials
    _rename(tree, names.links, names.joints, materials)
    _move_files(tree, part, base_folder)
    provenance.remember(
        (e for e in tree.iter(etree.Element) if e is not tree), part.shown, path=part.path
    )
    child = names.links.get(place.root, place.root)
    pose = place.pose
    rpy = part.rpy if part.rpy is not None and not place.folded else rpy_from_quaternion(pose[1])
    origin = (pose[0], rpy)
    mount: etree._Element | None = None
    if place.holder is not None:
        _hold(place.holder, names.mount_joint, child, origin)
    else:
        mount = _mount_joint(names.mount_joint, place.at, child, origin)
        provenance.remember(mount.iter(etree.Element), *part.entry, path=part.entry_path)
    header = etree.Comment(
        comment_text(f"part '{part.name}' ({part.shown}), mounted on '{place.at}' by robospec")
    )
    # a material the robot defines alike is left out; everything else moves, comments too
    moved = [
        e
        for e in tree
        if not (
            e.tag == "material" and e.get("name") in materials and not materials[str(e.get("name"))]
        )
    ]
    append_lines(root, [header, *([mount] if mount is not None else []), *moved], INDENT)
    renamed = tuple(
        [("link", old, new) for old, new in names.links.items() if old != new]
        + [("joint", old, new) for old, new in names.joints.items() if old != new]
        + [
            ("material", old, new)
            for old, new in materials.items()
            if new is not None and old != new
        ]
    )
    return Mounted(
        name=part.name,
        at=place.at,
        joint=names.mount_joint,
        root=child,
        links=tuple(names.links.get(n, n) for n in links),
        joints=tuple(names.joints.get(n, n) for n in joints),
        renamed=renamed,
        folded=place.folded,
    )


def _renames(
    part: PartSource, what: str, names: list[str], taken: AbstractSet[str], problems: list[Problem]
) -> dict[str, str]:
    """Each of the part's ``names`` -> its name in the combined description: prefixed where
    the robot has it already. A prefixed name the robot (or the part) also has is RS732."""
    out: dict[str, str] = {}
    own = set(names)
    for name in names:
        if name not in taken:
            out[name] = name
            continue
        new = part.prefix + name
        if new in taken or new in own:
            problems.append(
                Problem(
                    ("parts", part.name, "prefix"),
                    NAME_CLASH,
                    f"part '{part.name}' and the robot both have a {what} '{name}', and "
                    f"'{new}', the prefixed name, is taken too",
                    "give the part another `prefix:`",
                )
            )
        out[name] = new
    return out


def _material_renames(
    root: etree._Element, tree: etree._Element, part: PartSource, problems: list[Problem]
) -> dict[str, str | None]:
    """The part's top-level ``<material>``s: kept as they are, dropped (None) where the robot
    defines the same material by the same name, prefixed where it defines another."""
    defined = {m.get("name"): m for m in root.findall("material") if m.get("name")}
    out: dict[str, str | None] = {}
    for material in tree.findall("material"):
        name = material.get("name")
        if not name:
            continue
        if name not in defined:
            out[name] = name
        elif _same(defined[name], material):
            out[name] = None
        else:
            new = part.prefix + name
            if new in defined:
                problems.append(
                    Problem(
                        ("parts", part.name, "prefix"),
                        NAME_CLASH,
                        f"part '{part.name}' and the robot both define material '{name}', and "
                        f"'{new}' is taken too",
                        "give the part another `prefix:`",
                    )
                )
            out[name] = new
    return out


def _same(a: etree._Element, b: etree._Element) -> bool:
    def canonical(e: etree._Element) -> bytes:
        copy = etree.fromstring(etree.tostring(e, with_tail=False))
        for node in copy.iter():
            node.text = (node.text or "").strip() or None
            node.tail = None
        return etree.tostring(copy)

    return canonical(a) == canonical(b)


def _mount_link(at: str, taken: set[str], mounted: list[Mounted]) -> str:
    """The mount link's name in the combined description: the robot's own first, else a
    mounted part's link as the part's file names it."""
    if at in taken:
        return at
    for part in mounted:
        new = part.new_name("link", at)
        if new in taken:
            return new
    return at


def _rename(
    tree: etree._Element,
    links: dict[str, str],
    joints: dict[str, str],
    materials: dict[str, str | None],
) -> None:
    for link in tree.findall("link"):
        link.set("name", links.get(str(link.get("name")), str(link.get("name"))))
    for joint in tree.iter("joint"):
        name = joint.get("name")
        if name in joints:
            joint.set("name", joints[name])
        for tag in ("parent", "child"):
            for end in joint.findall(tag):
                if end.get("link") in links:
                    end.set("link", links[str(end.get("link"))])
        for mimic in joint.findall("mimic"):
            if mimic.get("joint") in joints:
                mimic.set("joint", joints[str(mimic.get("joint"))])
    for gazebo in tree.findall("gazebo"):
        reference = gazebo.get("reference")
        if reference in links:
            gazebo.set("reference", links[reference])
        elif reference in joints:
            gazebo.set("reference", joints[reference])
    for material in tree.iter("material"):
        new = materials.get(str(material.get("name")))
        if new is not None:
            material.set("name", new)


def _move_files(tree: etree._Element, part: PartSource, base_folder: str) -> None:
    """Each mesh and texture robospec found for the part, named from the robot's folder."""
    for element in tree.iter("mesh", "texture"):
        uri = element.get("filename")
        if uri is not None and uri in part.files:
            element.set("filename", relative_file(part.files[uri], base_folder))


def _empty(link: etree._Element) -> bool:
    """A link with nothing in it: no mass, no shape (a frame)."""
    return not any(child.tag in ("inertial", "visual", "collision") for child in link)


def _origin(joint: etree._Element) -> Pose | None:
    """A joint's ``<origin>`` as (position, quaternion); None when it does not read."""
    origin = joint.find("origin")
    try:
        xyz = [
            float(v)
            for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()
        ]
        rpy = [
            float(v)
            for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()
        ]
    except ValueError:
        return None
    if len(xyz) != 3 or len(rpy) != 3:
        return None
    return (xyz[0], xyz[1], xyz[2]), quaternion_from_rpy(rpy[0], rpy[1], rpy[2])


def _fixed_joints(tree: etree._Element, end: str, name: str) -> list[etree._Element]:
    return [j for j in tree.findall("joint") if any(e.get("link") == name for e in j.findall(end))]


def _root_frame(
    tree: etree._Element, root: str
) -> tuple[etree._Element, etree._Element, Pose] | None:
    """The part's root, when it is an empty frame fixed to exactly one link: the frame, its
    joint and that joint's pose."""
    frame = next((link for link in tree.findall("link") if link.get("name") == root), None)
    below = _fixed_joints(tree, "parent", root)
    if frame is None or not _empty(frame) or len(below) != 1 or below[0].get("type") != "fixed":
        return None
    origin = _origin(below[0])
    return (frame, below[0], origin) if origin is not None else None


def _leaf_frame(
    root: etree._Element, at: str
) -> tuple[etree._Element, etree._Element, Pose] | None:
    """The mount link, when it is an empty leaf frame fixed to its parent: the frame, the
    joint that holds it and that joint's pose."""
    frame = next((link for link in root.findall("link") if link.get("name") == at), None)
    above = _fixed_joints(root, "child", at)
    if (
        frame is None
        or not _empty(frame)
        or _fixed_joints(root, "parent", at)
        or len(above) != 1
        or above[0].get("type") != "fixed"
    ):
        return None
    origin = _origin(above[0])
    return (frame, above[0], origin) if origin is not None else None


def _hold(
    joint: etree._Element, name: str, child: str, origin: tuple[Sequence[float], Sequence[float]]
) -> None:
    """Make the joint that held a folded mount frame hold the part's root instead."""
    joint.set("name", name)
    for end in joint.findall("child"):
        end.set("link", child)
    element = joint.find("origin")
    if element is None:
        element = etree.SubElement(joint, "origin")
    element.set("xyz", " ".join(number(v) for v in origin[0]))
    element.set("rpy", " ".join(number(v) for v in origin[1]))


def _mount_joint(
    name: str, at: str, child: str, origin: tuple[Sequence[float], Sequence[float]]
) -> etree._Element:
    position, rpy = origin
    joint = etree.Element("joint", name=name, type="fixed")
    joint.text = "\n" + INDENT * 2
    origin_element = etree.SubElement(
        joint,
        "origin",
        xyz=" ".join(number(v) for v in position),
        rpy=" ".join(number(v) for v in rpy),
    )
    origin_element.tail = "\n" + INDENT * 2
    parent = etree.SubElement(joint, "parent", link=at)
    parent.tail = "\n" + INDENT * 2
    child_element = etree.SubElement(joint, "child", link=child)
    child_element.tail = "\n" + INDENT
    return joint


def _prefixed_note(part: PartSource, mounted: Mounted) -> Problem:
    listed = ", ".join(f"{what} '{old}' -> '{new}'" for what, old, new in mounted.renamed[:6])
    more = len(mounted.renamed) - 6
    return Problem(
        ("parts", part.name),
        PART_PREFIXED,
        f"part '{part.name}': names the robot already has are prefixed: {listed}"
        + (f" (and {more} more)" if more > 0 else ""),
        "name them so in this spec (the part's own spec keeps its names)",
        severity="note",
    )
