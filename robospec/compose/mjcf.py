"""Mount MJCF parts on an MJCF robot, as MuJoCo's ``attach`` would: the part's body tree under
the mount body, its assets, defaults and sections (contact, equality, tendon, actuator, sensor)
beside the robot's, clashing names prefixed.

Choices, each so the part reads in the combined model as it does alone:

- the part's top-level ``<default>`` becomes a class named after the part, inside the robot's
  main default, and the part's root body gets it as ``childclass``: the part's elements keep
  the part's defaults, the robot's keep the robot's;
- the part's ``<include>``s are read into it first (their defaults and assets are the part's),
  and an asset the robot defines alike by the same name is left out;
- the files the part names are written as paths from the robot's mesh and texture folders;
- the root body's pose becomes the mount pose composed with its own, as ``pos`` and ``quat``
  (which MuJoCo and ManiSkill read alike);
- what is about the model as a whole (``option``, ``size``, ``visual``, ``statistic``, the
  part's own ``compiler``) stays the robot's; the robot's keyframes get the part's joints at
  their reference positions, at rest.

A part must measure angles as the robot does (``<compiler angle>`` and ``eulerseq``), and hold
one body tree, fixed (no free joint), under its ``<worldbody>``.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

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
from robospec.description.mjcf_frames import ORIENTATION_ATTRIBUTES, Unparsable, body_pose
from robospec.description.mjcf_references import REFERENCES
from robospec.diagnostics.codes import (
    MIXED_FORMATS,
    NAME_CLASH,
    PART_NOT_A_FIXED_TREE,
    PART_PREFIXED,
)
from robospec.geometry import IDENTITY_POSE, compose

INDENT = "  "
# sections whose children are merged into the robot's (the elements of each, named or not)
SECTIONS = ("contact", "equality", "tendon", "actuator", "sensor")
# elements whose ``file`` names a file, and the compiler folder MuJoCo reads it from
FILE_FOLDERS = {"mesh": "meshdir", "hfield": "meshdir", "skin": "meshdir", "texture": "texturedir"}


def _kind(element: etree._Element) -> str | None:
    """The namespace an element's ``name`` lives in (MuJoCo's object types)."""
    tag = element.tag
    if not isinstance(tag, str):
        return None
    parent = element.getparent()
    section = parent.tag if parent is not None else None
    if section in ("actuator", "sensor", "equality", "tendon"):
        return section  # a tendon's own name; its <joint>s refer, they do not name
    if tag == "freejoint":
        return "joint"
    if tag in ("body", "joint", "geom", "site", "camera", "light") and section != "default":
        return tag
    if section == "asset":
        return tag  # mesh, material, texture, hfield, skin
    return None


def compose_mjcf(base: BaseSource, parts: Sequence[PartSource]) -> Composed:
    root = parse(base.text)
    if root is None or root.tag != "mujoco":
        return Composed("mjcf", None, Origins(()))  # the base's own parse says what is wrong
    provenance = Provenance()
    provenance.remember(root.iter(etree.Element), base.shown, path=base.path)
    base_folder = os.path.dirname(base.path)
    trees: dict[str, etree._Element] = {}
    problems: list[Problem] = []
    for part in parts:
        tree = parse(part.text)
        if tree is None or tree.tag != "mujoco":
            continue  # reported by the part's own compilation
        provenance.remember(tree.iter(etree.Element), part.shown, path=part.path)
        _read_includes(tree, part, provenance)
        trees[part.name] = tree
    names = _names(root, base_folder)
    bodies_of = {
        name: [str(b.get("name")) for b in t.iter("body") if b.get("name")]
        for name, t in trees.items()
    }
    base_bodies = [str(b.get("name")) for b in root.iter("body") if b.get("name")]
    ordered, order_problems = mount_order(
        base_bodies, [p for p in parts if p.name in trees], bodies_of
    )
    problems.extend(order_problems)
    mounted: list[Mounted] = []
    for part in ordered:
        result, found = _mount(root, trees[part.name], part, mounted, names, base, provenance)
        problems.extend(found)
        if result is not None:
            mounted.append(result)
            if result.renamed:
                listed = ", ".join(
                    f"{what} '{old}' -> '{new}'" for what, old, new in result.renamed[:6]
                )
                more = len(result.renamed) - 6
                problems.append(
                    Problem(
                        ("parts", part.name),
                        PART_PREFIXED,
                        f"part '{part.name}': names the robot already has are prefixed: {listed}"
                        + (f" (and {more} more)" if more > 0 else ""),
                        "name them so in this spec (the part's own spec keeps its names)",
                        severity="note",
                    )
                )
    if any(p.severity == "error" for p in problems):
        return Composed("mjcf", None, Origins(()), tuple(mounted), tuple(problems))
    first_line = root.sourceline if isinstance(root.sourceline, int) else 1
    text, origins = written(root, provenance, first_line)
    return Composed("mjcf", text, origins, tuple(mounted), tuple(problems))


def _read_includes(tree: etree._Element, part: PartSource, provenance: Provenance) -> None:
    """Each ``<include>`` of the part replaced by what it includes (one level, as ManiSkill
    reads them), remembered at the included file's lines."""
    folder = os.path.dirname(part.path)
    for include in list(tree.iter("include")):
        file = include.get("file")
        parent = include.getparent()
        if not file or parent is None:
            continue
        full = os.path.join(folder, file)
        try:
            with open(full, "rb") as handle:
                included = parse(handle.read())
        except OSError:
            included = None
        index = parent.index(include)
        parent.remove(include)
        if included is None:
            continue  # the part's own parse reported it
        shown = os.path.join(os.path.dirname(part.shown), file)
        children = [c for c in included if isinstance(c.tag, str) and c.tag != "include"]
        provenance.remember((e for c in children for e in c.iter(etree.Element)), shown, path=full)
        for offset, child in enumerate(children):
            parent.insert(index + offset, child)


class ModelFolders:
    """Where a model's files are: its folder and its compiler's mesh and texture folders."""

    def __init__(self, root: etree._Element, folder: str) -> None:
        compiler = root.find("compiler")
        get = compiler.get if compiler is not None else (lambda _k, d=None: d)
        assets = get("assetdir", "") or ""
        self.folder = folder
        self.dirs = {
            "meshdir": os.path.join(folder, get("meshdir", assets) or ""),
            "texturedir": os.path.join(folder, get("texturedir", assets) or ""),
        }
        self.degrees = (get("angle", "degree") or "degree").lower() == "degree"
        self.eulerseq = get("eulerseq", "xyz") or "xyz"

    def file(self, element: etree._Element) -> str | None:
        folder = FILE_FOLDERS.get(str(element.tag))
        name = element.get("file")
        if folder is None or not name:
            return None
        return os.path.normpath(os.path.join(self.dirs[folder], name))


def _with_includes(root: etree._Element, folder: str) -> list[etree._Element]:
    """The robot's model and the files it includes (one level, as ManiSkill reads them)."""
    trees = [root]
    for include in root.findall("include"):
        try:
            with open(os.path.join(folder, include.get("file") or ""), "rb") as handle:
                included = parse(handle.read())
        except OSError:
            included = None
        if included is not None:
            trees.append(included)
    return trees


def _names(root: etree._Element, folder: str) -> dict[str, set[str]]:
    """The robot's names by kind, its included files' too."""
    out: dict[str, set[str]] = {}
    for tree in _with_includes(root, folder):
        for element in tree.iter(etree.Element):
            _add_name(out, element)
    return out


def _add_name(names: dict[str, set[str]], element: etree._Element) -> None:
    if element.tag == "default" and element.get("class"):
        names.setdefault("class", set()).add(str(element.get("class")))
        return
    kind = _kind(element)
    if kind is not None and element.get("name"):
        names.setdefault(kind, set()).add(str(element.get("name")))


def _mount(
    root: etree._Element,
    tree: etree._Element,
    part: PartSource,
    mounted: list[Mounted],
    names: dict[str, set[str]],
    base: BaseSource,
    provenance: Provenance,
) -> tuple[Mounted | None, list[Problem]]:
    base_folder = os.path.dirname(base.path)
    here, there = ModelFolders(root, base_folder), ModelFolders(tree, os.path.dirname(part.path))
    mixed = _mixed_angles(part, here, there)
    if mixed is not None:
        return None, [mixed]
    root_body = _root_body(tree, part)
    if isinstance(root_body, Problem):
        return None, [root_body]
    problems: list[Problem] = []
    dropped = _same_assets(root, tree, here, there)
    renames = _renames(tree, part, names, dropped, problems)
    main_class = _class_name(part, names, problems)
    at = _mount_body(root, part.at, mounted)
    if at is None:
        return None, problems  # mount_order found it; nothing more to say
    if any(p.severity == "error" for p in problems):
        return None, problems
    # files from the robot's folders, names as renamed
    for element in tree.iter(etree.Element):
        full = there.file(element)
        if full is not None:
            folder = here.dirs[FILE_FOLDERS[str(element.tag)]]
            element.set("file", relative_file(full, folder))
    _apply(tree, renames)
    _pose_root_body(root_body, part, there)
    if root_body.get("childclass") is None and tree.find("default") is not None:
        root_body.set("childclass", main_class)  # a part without defaults gets no class
    joints = [j for j in root_body.iter("joint") if j.getparent() is not None]
    _extend_keys(root, joints, len(_children(tree, "actuator")))
    _merge_defaults(root, tree, main_class)
    _merge_assets(root, tree, dropped)
    for section in SECTIONS:
        _merge_section(root, tree, section)
    header = etree.Comment(
        comment_text(
            f"part '{part.name}' ({part.shown}), mounted on '{at.get('name')}' by robospec"
        )
    )
    append_lines(at, [header, root_body], INDENT * (_depth(at) + 1))
    return _mounted(part, at, root_body, joints, renames), problems


def _mixed_angles(part: PartSource, here: ModelFolders, there: ModelFolders) -> Problem | None:
    """RS735 when the part measures angles otherwise than the robot."""
    if (here.degrees, here.eulerseq.lower()) == (there.degrees, there.eulerseq.lower()):
        return None
    units = {True: "degrees", False: "radians"}
    return Problem(
        ("parts", part.name, part.key),
        MIXED_FORMATS,
        f"part '{part.name}' measures angles in {units[there.degrees]} "
        f"(eulerseq {there.eulerseq}) and this robot in {units[here.degrees]} "
        f"(eulerseq {here.eulerseq}): robospec does not convert one model's angles",
        "set the part's <compiler angle> and eulerseq as the robot's",
    )


def _root_body(tree: etree._Element, part: PartSource) -> etree._Element | Problem:
    """The part's one body under its ``<worldbody>``, or RS731 when it has
    none, several or a free one."""
    worldbody = tree.find("worldbody")
    bodies = worldbody.findall("body") if worldbody is not None else []
    if (
        len(bodies) != 1
        or bodies[0].find("freejoint") is not None
        or any(j.get("type") == "free" for j in bodies[0].findall("joint"))
    ):
        what = f"{len(bodies)} bodies under <worldbody>" if len(bodies) != 1 else "a free root"
        return Problem(
            ("parts", part.name, part.key),
            PART_NOT_A_FIXED_TREE,
            f"part '{part.name}' is not one body tree fixed at its root: it has {what}",
            "mount a model of the part with one body tree and no free joint",
        )
    return bodies[0]


def _pose_root_body(root_body: etree._Element, part: PartSource, there: ModelFolders) -> None:
    """The mount pose composed with the root body's own, written as ``pos`` and ``quat``."""
    try:
        own = body_pose(dict(root_body.attrib), there.degrees, there.eulerseq)
    except (Unparsable, ValueError):
        own = IDENTITY_POSE
    position, quaternion = compose((part.position, part.quaternion), own)
    for attribute in ("pos", *ORIENTATION_ATTRIBUTES):
        root_body.attrib.pop(attribute, None)
    root_body.set("pos", " ".join(number(v) for v in position))
    root_body.set("quat", " ".join(number(v) for v in quaternion))


def _mounted(
    part: PartSource,
    at: etree._Element,
    root_body: etree._Element,
    joints: list[etree._Element],
    renames: dict[str, dict[str, str]],
) -> Mounted:
    """The part as mounted: its links and joints, and each name it changed."""
    links = [str(b.get("name")) for b in root_body.iter("body") if b.get("name")]
    renamed = tuple(
        (kind, old, new)
        for kind, table in sorted(renames.items())
        for old, new in table.items()
        if old != new
    )
    # ManiSkill names the links of a body with n joints {body}_dummy_0 .. _{n-2}, then {body}
    link_renames = tuple(
        ("link", f"{old}{suffix}", f"{new}{suffix}")
        for kind, old, new in renamed
        if kind == "body"
        for suffix in ("", *(f"_dummy_{i}" for i in range(_joint_count(root_body, new) - 1)))
    )
    return Mounted(
        name=part.name,
        at=str(at.get("name")),
        joint="",
        root=str(root_body.get("name") or ""),
        links=tuple(links),
        joints=tuple(str(j.get("name")) for j in joints if j.get("name")),
        renamed=link_renames + renamed,
    )


def _joint_count(tree: etree._Element, body: str) -> int:
    found = next((b for b in tree.iter("body") if b.get("name") == body), None)
    return len(found.findall("joint")) if found is not None else 0


def _children(tree: etree._Element, section: str) -> list[etree._Element]:
    return [c for s in tree.findall(section) for c in s if isinstance(c.tag, str)]


def _same_assets(
    root: etree._Element, tree: etree._Element, here: ModelFolders, there: ModelFolders
) -> set[tuple[str, str]]:
    """(kind, name) of the part's assets the robot defines alike (same attributes, the same
    file): they are left out, and the part's references use the robot's."""

    def key(element: etree._Element, folders: ModelFolders) -> tuple:
        attributes = dict(element.attrib)
        full = folders.file(element)
        if full is not None:
            attributes["file"] = full
        return tuple(sorted(attributes.items()))

    robots: dict[tuple[str, str], tuple] = {}
    model = _with_includes(root, here.folder)
    for asset in (a for tree in model for a in tree.iter("asset")):
        for element in asset:
            if isinstance(element.tag, str) and element.get("name"):
                robots[(element.tag, str(element.get("name")))] = key(element, here)
    same: set[tuple[str, str]] = set()
    for asset in tree.iter("asset"):
        for element in asset:
            if not isinstance(element.tag, str) or not element.get("name"):
                continue
            name = (str(element.tag), str(element.get("name")))
            if robots.get(name) == key(element, there):
                same.add(name)
    return same


def _renames(
    tree: etree._Element,
    part: PartSource,
    names: dict[str, set[str]],
    dropped: set[tuple[str, str]],
    problems: list[Problem],
) -> dict[str, dict[str, str]]:
    """kind -> {name: new name} for the part's names; the robot's names grow by them."""
    own: dict[str, set[str]] = {}
    for element in tree.iter(etree.Element):
        _add_name(own, element)
    out: dict[str, dict[str, str]] = {}
    for kind, found in own.items():
        taken = names.setdefault(kind, set())
        table = out.setdefault(kind, {})
        for name in sorted(found):
            if (kind, name) in dropped:
                table[name] = name
                continue
            new = name if name not in taken else part.prefix + name
            if new != name and (new in taken or new in found):
                problems.append(
                    Problem(
                        ("parts", part.name, "prefix"),
                        NAME_CLASH,
                        f"part '{part.name}' and the robot both have a {kind} '{name}', and "
                        f"'{new}', the prefixed name, is taken too",
                        "give the part another `prefix:`",
                    )
                )
            table[name] = new
        taken.update(table.values())
    return out


def _class_name(part: PartSource, names: dict[str, set[str]], problems: list[Problem]) -> str:
    """The class the part's main default becomes: the part's name (prefixed if taken)."""
    taken = names.setdefault("class", set())
    name = part.name if part.name not in taken else part.prefix + part.name
    if name in taken:
        problems.append(
            Problem(
                ("parts", part.name, "prefix"),
                NAME_CLASH,
                f"the robot has default classes '{part.name}' and '{name}': the part's defaults "
                "need a class of their own",
                "give the part another `prefix:`",
            )
        )
    taken.add(name)
    return name


def _apply(tree: etree._Element, renames: dict[str, dict[str, str]]) -> None:
    for element in tree.iter(etree.Element):
        if element.tag == "default" and element.get("class"):
            element.set(
                "class",
                renames.get("class", {}).get(str(element.get("class")), str(element.get("class"))),
            )
        else:
            kind = _kind(element)
            name = element.get("name")
            if kind is not None and name is not None:
                element.set("name", renames.get(kind, {}).get(name, name))
        for kind, attributes in REFERENCES.items():
            table = renames.get(kind, {})
            for attribute in attributes:
                value = element.get(attribute)
                if value is not None and value in table and not _own_name(element, attribute):
                    element.set(attribute, table[value])


def _own_name(element: etree._Element, attribute: str) -> bool:
    """``class`` on a ``<default>`` is its own name, renamed as one."""
    return element.tag == "default" and attribute == "class"


def _mount_body(root: etree._Element, at: str, mounted: list[Mounted]) -> etree._Element | None:
    names = [at, *(m.new_name("link", at) for m in mounted)]
    for name in names:
        found = next((b for b in root.iter("body") if b.get("name") == name), None)
        if found is not None:
            return found
    return None


def _depth(element: etree._Element) -> int:
    depth = 0
    parent = element.getparent()
    while parent is not None:
        depth += 1
        parent = parent.getparent()
    return depth


def _first(root: etree._Element, tag: str, before: str = "worldbody") -> etree._Element:
    """The robot's first ``<tag>`` section, made (before ``before``) when it has none."""
    found = root.find(tag)
    if found is not None:
        return found
    element = etree.Element(tag)
    anchor = root.find(before)
    if anchor is not None:
        anchor.addprevious(element)
        element.tail = "\n" + INDENT
    else:
        append_lines(root, [element], INDENT)
    return element


def _merge_defaults(root: etree._Element, tree: etree._Element, main_class: str) -> None:
    """The part's top-level defaults, as one class inside the robot's main default."""
    defaults = [d for d in tree.findall("default")]
    if not defaults:
        return
    cls = etree.Element("default", {"class": main_class})
    for default in defaults:
        for child in list(default):
            same = next(
                (
                    c
                    for c in cls
                    if c.tag == child.tag and c.tag != "default" and isinstance(child.tag, str)
                ),
                None,
            )
            if same is not None:  # repeated: later settings win, as ManiSkill merges them
                same.attrib.update(child.attrib)
            else:
                cls.append(child)
    target = _first(root, "default")
    append_lines(target, [cls], INDENT * 2)


def _merge_assets(
    root: etree._Element, tree: etree._Element, dropped: set[tuple[str, str]]
) -> None:
    moved = [
        element
        for asset in tree.findall("asset")
        for element in asset
        if isinstance(element.tag, str) and (element.tag, element.get("name")) not in dropped
    ]
    if moved:
        append_lines(_first(root, "asset"), moved, INDENT * 2)


def _merge_section(root: etree._Element, tree: etree._Element, section: str) -> None:
    moved = _children(tree, section)
    if moved:
        target = root.find(section)
        if target is None:
            target = etree.Element(section)
            append_lines(root, [target], INDENT)
        append_lines(target, moved, INDENT * 2)


def _extend_keys(root: etree._Element, joints: list[etree._Element], actuators: int) -> None:
    """The robot's keyframes, with the part's joints at their reference positions at rest
    (MuJoCo wants every key as long as the model's state)."""
    qpos: list[str] = []
    for joint in joints:
        kind = joint.get("type", "hinge")
        if kind == "ball":
            qpos += ["1", "0", "0", "0"]
        else:
            qpos.append(joint.get("ref", "0"))
    speeds = sum(3 if j.get("type") == "ball" else 1 for j in joints)
    for key in root.iter("key"):
        for attribute, extra in (
            ("qpos", qpos),
            ("qvel", ["0"] * speeds),
            ("ctrl", ["0"] * actuators),
        ):
            if key.get(attribute) is not None and extra:
                key.set(attribute, " ".join([*str(key.get(attribute)).split(), *extra]))
