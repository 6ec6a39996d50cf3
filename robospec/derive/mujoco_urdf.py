"""An MJCF compiled by MuJoCo, written as the URDF ManiSkill's URDF loader reads
(``description: {mjcf: robot.xml, loader: mujoco}``).

ManiSkill 3's own MJCF loader reads no ``<inertial>`` (every link weighs what its geoms would at
their density), stops at 32 bodies, loads no ball joint and gives a body of visual geoms no
mass. MuJoCo's compiler is the reference for what the file means — defaults and classes,
includes, angle units, mesh scale and recentring, ``inertiafromgeom``, frames — so this route
compiles the file with MuJoCo (:func:`robospec.derive.mjcf_files.compiled_model`) and
writes what the compiled ``MjModel`` says:

- every body a link, named as the MJCF names it (an unnamed one ``body<id>``, MuJoCo's id), at
  MuJoCo's body frame, with MuJoCo's mass, centre of mass and principal inertia
  (``body_mass``, ``body_ipos``, ``body_iquat``, ``body_inertia``);
- a hinge a revolute joint (continuous when unlimited), a slide a prismatic one, each about
  its axis through its anchor, its value counted from ``ref`` (0 is the pose as written, as
  ManiSkill's MJCF loader counts it), with ``damping`` and ``frictionloss``; a joint whose
  anchor is off the body's origin, and each joint but the last of a body with several, turns
  an intermediate link (``{body}_{joint}``), as does each of the three hinges (x, y, z) a ball
  joint becomes (``{joint}_x``…); intermediate links weigh the 1 g robospec's mass bound gives;
- a free joint on the root body: the root floats (no joint; the spec's ``fix_root_link:
  false``); a root body with other joints hangs from a link ``world``;
- the robot: the first body tree that moves, as ManiSkill's loader chooses, or, where several
  trees welded to the world are driven by the file's actuators (a bimanual scene's arms), all
  of them, each hung from a link ``world``;
- geoms: collision shapes where MuJoCo collides them (``contype`` or ``conaffinity``), drawn
  where MuJoCo draws them by default (groups 0-2) with their colour; boxes, spheres, cylinders
  and capsules as URDF's, meshes (as MuJoCo recentred and scaled them) and ellipsoids as OBJ
  files written, named by their content, into robospec's cache (``derived/``; ``build`` copies
  them into the package like any mesh).

A ``<connect>`` between two of the robot's bodies is carried as a closed loop (the
description's closures: ``robospec new`` writes it under ``loops:``, closed by a drive after
loading). Joint armature is a description fact too, which the agent sets through SAPIEN
(``PhysxArticulationJoint.set_armature``). What the URDF cannot carry is one warning per kind
(RS791): the other ``<equality>`` constraints, ``<tendon>``, ``<contact>`` pairs and
exclusions, actuators (the spec's controllers drive the joints), ball-joint cones (each hinge
gets the cone's limit), planes, height fields, other body trees of a scene. A file MuJoCo
refuses is RS790, at the line MuJoCo names.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from lxml import etree

from robospec.derive.document import Source
from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.diagnostics.codes import (
    INVALID_STRUCTURE,
    MUJOCO_COMPILE_ERROR,
    MUJOCO_COMPILE_WARNING,
    MUJOCO_NOT_CARRIED,
    MUJOCO_SITE_UNWRITABLE,
)
from robospec.geometry import IDENTITY, ZERO, Pose, Vector, compose, rpy_from_quaternion

DERIVED_FOLDER = "derived"  # robospec's cache folder for the files derived copies name
WORLD = "world"  # MuJoCo's name of body 0: the root link of a robot whose root body moves
# an intermediate link's mass and inertia (it holds a joint, no body): the bound of
# robospec's mass mend (1 g, radius of gyration 2 mm)
_LINK_MASS = 1e-3
_LINK_INERTIA = _LINK_MASS * 0.002**2
# kg m^2: SAPIEN asserts on a principal moment that is not positive, and PhysX keeps none
# under this (measured, SAPIEN 3.0.3: Jaco's b_6, 3.3e-13 in MuJoCo, simulates at 1e-12)
INERTIA_FLOOR = 1e-12
_VISIBLE_GROUPS = 3  # MuJoCo draws geom groups 0, 1 and 2 by default
_LINE = re.compile(r"line (\d+)")  # where MuJoCo's message names the element
_ELEMENT = re.compile(r"Element '(\w+)'")
# what a compiler warning is about: "flex 'cloth' is ...", "compiler attribute 'x' is ..."
_SUBJECT = re.compile(r"^<?(\w+)>?(?: attribute)? '([^']*)'")
_NAMED = re.compile(r"Element name '([^']*)'")
_ELLIPSOID_STEPS = (16, 8)  # longitude, latitude
_LISTED = 6  # names a warning lists before it counts the rest


@dataclass
class Compiled:
    """The URDF written from the model, its notes, and where each of its lines came from."""

    text: str | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    line_map: tuple[tuple[int, tuple[str, int]], ...] = ()
    files: tuple[str, ...] = ()  # the files MuJoCo read besides the model (meshes, includes)
    # what the URDF's text cannot say and the description carries (RobotDescription's fields):
    # the model's <key> keyframes and actuators as MuJoCo compiled them, a floating root
    facts: dict[str, Any] = field(default_factory=dict)


def compile_urdf(
    source: Source,
    entry: Location | None = None,
    sites: Sequence[tuple[str, Location]] = (),
) -> Compiled:
    """The URDF of the MJCF ``source`` as MuJoCo compiles it; its text None (and an RS790
    error) where MuJoCo refuses the file: at the line MuJoCo names, else at ``entry`` (where
    the spec names the file). ``sites`` (each with where the spec names it) become links of
    their own."""
    from robospec.derive.mjcf_files import compiled_with_warnings, inlined
    from robospec.description.urdf import parse_xml

    # what the file's own reading says first, at its line, as the other routes say it: not
    # XML (RS051), an include that cannot be read (RS050; MuJoCo would name no line)
    _, malformed = parse_xml(source.data, source.shown)
    if malformed:
        return Compiled(None, malformed)
    unreadable = inlined(source).refusals
    if unreadable:
        return Compiled(None, unreadable)
    lines = _source_lines(source)
    try:
        model, said = compiled_with_warnings(source.data, source.path)
    except ValueError as exc:
        return Compiled(None, [_compile_error(source, lines, str(exc), entry)])
    writer = _Writer(model, source, lines)
    writer.diagnostics.extend(_compile_warning(source, lines, text, entry) for text in said)
    writer.write()
    if writer.links:
        writer.write_sites(sites)
    text = etree.tostring(writer.robot, encoding="unicode", pretty_print=True)
    facts = {
        "keyframes": writer.keyframes(),
        "actuators": writer.actuators(),
        "floating_root": writer.floating,
        "closures": writer.closures(),
        "armature": tuple(writer.armature.items()),
    }
    if writer.root_pose is not None:  # the root link is the root body: no offset between
        facts.update(root_body_pose=writer.root_pose, root_body_offset=(ZERO, IDENTITY))
    files = tuple(sorted(_read_files(source)))
    return Compiled(text, writer.diagnostics, writer.line_map(text), files, facts)


# -- reading the user's file: where its elements stand -------------------------------------


# the compiled arrays the URDF is written from, per element kind: MuJoCo compiles a NaN
# in a joint's range or a body's pos with only a warning ("XML contains a 'NaN'"), and
# the URDF written from it would load a different robot without a word
_COMPILED_NUMBERS = {
    "joint": ("jnt_range", "jnt_axis", "jnt_pos"),
    "body": ("body_pos", "body_quat", "body_mass", "body_ipos", "body_iquat", "body_inertia"),
}


@dataclass
class _Lines:
    """Where the MJCF's elements stand in the user's files (the model and what it includes,
    as diagnostics name them): the first of each tag, each named element."""

    named: dict[tuple[str, str], tuple[str, int]] = field(default_factory=dict)
    first: dict[str, tuple[str, int]] = field(default_factory=dict)
    shown: str = ""
    paths: dict[str, str] = field(default_factory=dict)  # file as shown -> its path

    def location(self, at: tuple[str, int], tag: str) -> Location:
        """The location of the element ``tag`` at ``at``: its start tag's column."""
        from robospec.description.source_columns import tag_column

        path = self.paths.get(at[0])
        return Location(at[0], at[1], tag_column(path, at[1], tag) if path else 1)

    def of(self, tag: str, name: str | None = None) -> tuple[str, int]:
        """(file, line) of the element: by name, else the first of its tag, else line 1."""
        if name is not None and (tag, name) in self.named:
            return self.named[(tag, name)]
        return self.first.get(tag, (self.shown, 1))


def _source_lines(source: Source) -> _Lines:
    from robospec.description.mjcf_mujoco import MAX_INCLUDE_DEPTH, Includes
    from robospec.description.urdf import parse_xml, read_file_bytes

    found = _Lines(shown=source.shown, paths={source.shown: source.path})
    root, _ = parse_xml(source.data, source.path)
    includes = Includes(source.path, read_file_bytes, {})
    folder = os.path.dirname(os.path.abspath(source.path))

    def walk(element: etree._Element, shown: str, depth: int) -> None:
        for inner in element.iter():
            if not isinstance(inner.tag, str) or not isinstance(inner.sourceline, int):
                continue
            if inner.tag == "include" and depth < MAX_INCLUDE_DEPTH:
                included = includes.root(inner)
                if included is not None:
                    path = includes.file_of[included]
                    relative = os.path.relpath(path, folder)
                    shown_there = os.path.normpath(
                        os.path.join(os.path.dirname(source.shown), relative)
                    )
                    found.paths[shown_there] = path
                    walk(included, shown_there, depth + 1)
                continue
            found.first.setdefault(inner.tag, (shown, inner.sourceline))
            name = inner.get("name")
            if name is not None:
                found.named.setdefault((inner.tag, name), (shown, inner.sourceline))

    if root is not None:
        walk(root, source.shown, 0)
    return found


def _read_files(source: Source) -> set[str]:
    """The files MuJoCo reads for the model: its includes and what it names (meshes)."""
    from robospec.derive.mjcf_files import named_files

    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    try:
        root = etree.fromstring(source.data, parser)
    except etree.XMLSyntaxError:
        return set()
    folder = os.path.dirname(os.path.abspath(source.path))
    files = {path for _element, path in named_files(root, source.path)}
    files |= {
        os.path.normpath(os.path.join(folder, i.get("file", ""))) for i in root.iter("include")
    }
    return {f for f in files if os.path.isfile(f)}


def _compile_error(
    source: Source, lines: _Lines, message: str, entry: Location | None
) -> Diagnostic:
    from robospec.description.source_columns import tag_column

    text = " ".join(message.split())
    line = _LINE.search(message)
    tag = _ELEMENT.search(message)
    if line is not None:
        number = int(line[1])
        column = tag_column(source.path, number, tag[1]) if tag is not None else 1
        where = Location(source.shown, number, column)
    else:  # a compiler error names the element, not its line ("Element name 'cloth', id 0")
        where = _named_element(lines, text) or entry or Location(source.shown, 1, 1)
    return error(
        where,
        MUJOCO_COMPILE_ERROR,
        f"MuJoCo cannot compile '{source.shown}': {text}",
        "fix the file as MuJoCo's message says (`python -m mujoco.viewer` shows the same)",
    )


def _compile_warning(
    source: Source, lines: _Lines, message: str, entry: Location | None
) -> Diagnostic:
    """What MuJoCo's compiler warned about (it compiles the file anyway), at the element its
    message names, else where the spec names the file."""
    text = " ".join(message.split())
    where = _named_element(lines, text) or entry or Location(source.shown, 1, 1)
    return warning(
        where,
        MUJOCO_COMPILE_WARNING,
        f"MuJoCo warns while compiling '{source.shown}': {text}",
        "MuJoCo compiles the file anyway; fix it as the message says, or the robot may not "
        "be the one the file meant",
    )


def _named_element(lines: _Lines, text: str) -> Location | None:
    """Where the element a compiler message names stands: by tag and name, else by name alone
    (``flex 'cloth'`` is a ``<flexcomp>``), else the first element of the tag (``compiler
    attribute 'settotalmass'``: the ``<compiler>``); None where it names none."""
    subject, named = _SUBJECT.search(text), _NAMED.search(text)
    tag = subject[1] if subject is not None else None
    name = named[1] if named is not None and named[1] else None
    at: tuple[str, int] | None = None
    if tag is not None and name is not None:
        at = lines.named.get((tag, name))
    if at is None and name is not None:
        tag, at = next(((t, w) for (t, n), w in lines.named.items() if n == name), (tag, None))
    if at is None and tag is not None:
        at = lines.first.get(tag)
    return lines.location(at, tag or "") if at is not None else None


# -- writing the URDF ----------------------------------------------------------------------


class _Writer:
    """The URDF of one compiled model, built element by element."""

    def __init__(self, model: Any, source: Source, lines: _Lines) -> None:
        import mujoco

        self.mujoco = mujoco
        self.model = model
        self.source = source
        self.lines = lines
        self.diagnostics: list[Diagnostic] = []
        self.robot = etree.Element("robot", name=_model_name(source))
        self.links: dict[int, str] = {}  # body -> its link
        self.taken_links: set[str] = set()
        self.taken_joints: set[str] = set()
        # (tag, URDF name) -> (file, line) of the MJCF element it was written from
        self.origin_of: dict[tuple[str, str], tuple[str, int]] = {}
        # kind -> the first's (file, line) and tag, and what
        self.dropped: dict[str, tuple[tuple[str, int], str, list[str]]] = {}
        self.limit_cones: list[str] = []
        self.floating = False  # the root body's free joint: the root link floats
        # the root body's world pose in the file (MuJoCo's qpos0), when the root link is that
        # body: a keyframe without a pose leaves it there, as MuJoCo does (robospec.resolve.
        # root_pose); None when the root link is MuJoCo's world
        self.root_pose: Pose | None = None
        self.free_joint: int | None = None
        self.ball_joints: dict[int, list[str]] = {}  # ball joint -> its three hinges' names
        self.hinges: dict[int, str] = {}  # hinge or slide -> its URDF joint
        self.armature: dict[str, float] = {}  # URDF joint -> its dof's armature, where not 0

    # -- what MuJoCo compiles although it is not a number

    def _not_numbers(self) -> bool:
        """RS052 at each joint and body whose compiled values are not all finite numbers."""
        import numpy as np

        names = {"joint": self.joint_name, "body": self.body_name}
        found = []
        for tag, arrays in _COMPILED_NUMBERS.items():
            for index in range(len(getattr(self.model, arrays[0]))):
                bad = [a for a in arrays if not np.isfinite(getattr(self.model, a)[index]).all()]
                if bad and not (tag == "body" and index == 0):  # the world body
                    name = names[tag](index)
                    found.append(
                        error(
                            self.lines.location(self.lines.of(tag, name), tag),
                            INVALID_STRUCTURE,
                            f"{tag} '{name}' compiles to values that are not numbers "
                            f"({', '.join(a.split('_', 1)[1] for a in bad)}: NaN or infinite)",
                            "write each of the element's numbers as a finite number",
                        )
                    )
        self.diagnostics.extend(found)
        return bool(found)

    # -- names

    def body_name(self, body: int) -> str:
        name = self.mujoco.mj_id2name(self.model, self.mujoco.mjtObj.mjOBJ_BODY, body)
        return name or f"body{body}"

    def joint_name(self, joint: int) -> str:
        name = self.mujoco.mj_id2name(self.model, self.mujoco.mjtObj.mjOBJ_JOINT, joint)
        return name or f"joint{joint}"

    def _unique(self, name: str, taken: set[str]) -> str:
        candidate, n = name, 1
        while candidate in taken:
            n += 1
            candidate = f"{name}_{n}"
        taken.add(candidate)
        return candidate

    # -- the tree

    def write(self) -> None:
        model, mj = self.model, self.mujoco
        if self._not_numbers():
            return
        tops = [b for b in range(1, model.nbody) if int(model.body_parentid[b]) == 0]
        if not tops:
            self.diagnostics.append(
                error(
                    self.lines.location(self.lines.of("worldbody"), "worldbody"),
                    MUJOCO_COMPILE_ERROR,
                    f"'{self.source.shown}' has no body below <worldbody>: no robot to load",
                    "give the robot's bodies in <worldbody>",
                )
            )
            return
        moving = [b for b in tops if self._subtree_moves(b)]
        top = (moving or tops)[0]
        # several trees welded to the world that the file's actuators drive (a bimanual
        # scene's arms) are one robot, hung from a link `world`; else the first that moves,
        # as ManiSkill's loader chooses (an unactuated door or a free cube is the scene's)
        driven = [b for b in moving if self._welded(b) and self._driven(b)]
        robot = driven if len(driven) > 1 else [top]
        others = [self.body_name(b) for b in tops if b not in robot]
        if others:
            chosen = ", ".join(f"'{self.body_name(b)}'" for b in robot)
            why = (
                f"the trees welded to the world that the actuators drive, {chosen}"
                if len(robot) > 1
                else f"the first tree that moves, {chosen}"
            )
            self._drop(
                "body",
                "other body trees of the scene",
                f"bodies {', '.join(others)} (the robot is {why})",
                next(self.body_name(b) for b in tops if b not in robot),
            )
        if len(robot) > 1:
            self.links[0] = self._link(WORLD, "worldbody", None)
            for body in range(1, model.nbody):
                if int(model.body_rootid[body]) in robot:
                    self._body(body)
            self._report_dropped()
            return
        jointed = [int(model.body_jntadr[top]) + k for k in range(int(model.body_jntnum[top]))]
        free = [j for j in jointed if int(model.jnt_type[j]) == int(mj.mjtJoint.mjJNT_FREE)]
        if not jointed or (free and len(jointed) == 1):
            self.floating = bool(free)
            self.free_joint = free[0] if free else None
            self.root_pose = (_vector(model.body_pos[top]), _quaternion(model.body_quat[top]))
            root = self._link(self.body_name(top), "body", self.body_name(top))
            self.links[top] = root
            self._inertial(root, top)
            self._geoms(root, top)
        else:
            world = self._link(WORLD, "worldbody", None)
            self.links[0] = world
            self._body(top)
        for body in range(top + 1, model.nbody):
            if int(model.body_rootid[body]) == top:
                self._body(body)
        self._report_dropped()

    def write_sites(self, sites: Sequence[tuple[str, Location]]) -> None:
        """Each site the spec names as a link of its own, named as the site, fixed to its
        body's link where the site sits and weighing what an intermediate link does; RS793
        at the spec's entry where it cannot be one (no such site, a site of a body that is not
        the robot's, a name a link already has)."""
        from robospec.diagnostics.suggest import did_you_mean

        model, mj = self.model, self.mujoco
        named = [mj.mj_id2name(model, mj.mjtObj.mjOBJ_SITE, i) for i in range(model.nsite)]
        for name, where in sites:
            site = mj.mj_name2id(model, mj.mjtObj.mjOBJ_SITE, name)
            body = int(model.site_bodyid[site]) if site >= 0 else -1
            if site < 0:
                bodies = [int(b) for b in model.site_bodyid]
                ours = sorted(
                    n for n, b in zip(named, bodies, strict=True) if n and b in self.links
                )
                found = (
                    f"; its robot's sites: {', '.join(ours)}" if ours else ", and its robot none"
                )
                problem = f"'{self.source.shown}' has no site '{name}'{found}"
                hint = did_you_mean(name, ours) or "name a <site> of the robot's bodies"
            elif body not in self.links:
                problem = (
                    f"site '{name}' sits on body '{self.body_name(body)}', which is not the "
                    "robot's (the scene's)"
                )
                hint = "name a site of the robot's bodies, or leave it out"
            elif name in self.taken_links:
                problem = f"a link is named '{name}' already: the site cannot be a link so named"
                hint = "leave the site out and name that link, or rename the site in the MJCF"
            else:
                link = self._link(name, "site", name)
                self._intermediate(link)
                pose = (_vector(model.site_pos[site]), _quaternion(model.site_quat[site]))
                self._joint(
                    f"{name}_site", "fixed", self.links[body], link, pose, None, "site", name
                )
                continue
            self.diagnostics.append(error(where, MUJOCO_SITE_UNWRITABLE, problem, hint))

    def _welded(self, top: int) -> bool:
        """Whether the top-level body ``top`` is fixed to the world (no free joint)."""
        model, free = self.model, int(self.mujoco.mjtJoint.mjJNT_FREE)
        first = int(model.body_jntadr[top])
        joints = range(first, first + int(model.body_jntnum[top]))
        return not any(int(model.jnt_type[j]) == free for j in joints)

    def _driven(self, top: int) -> bool:
        """Whether an actuator of the file drives a joint of the tree below ``top``."""
        model, by_joint = self.model, int(self.mujoco.mjtTrn.mjTRN_JOINT)
        return any(
            int(model.actuator_trntype[a]) == by_joint
            and int(model.body_rootid[int(model.jnt_bodyid[int(model.actuator_trnid[a][0])])])
            == top
            for a in range(int(model.nu))
        )

    def _subtree_moves(self, top: int) -> bool:
        model = self.model
        return any(
            int(model.body_jntnum[b]) > 0
            for b in range(top, model.nbody)
            if int(model.body_rootid[b]) == top
        )

    def _body(self, body: int) -> None:
        """The link of ``body`` and the joints that hang it from its parent's link."""
        model = self.model
        name = self.body_name(body)
        parent = self.links[int(model.body_parentid[body])]
        offset: Pose = (_vector(model.body_pos[body]), _quaternion(model.body_quat[body]))
        steps = self._steps(body)
        link = self._link(name, "body", name)
        self.links[body] = link
        previous = parent
        if not steps:
            self._joint(f"{name}_fixed", "fixed", previous, link, offset, None, "body", name)
            previous = link
        for k, (joint, axis, kind, anchor, label) in enumerate(steps):
            last = k == len(steps) - 1
            origin = compose(offset, (anchor, IDENTITY))
            if last and anchor == ZERO:
                child = link
            else:
                child = self._link(f"{name}_{label}", "joint", self.joint_name(joint))
                self._intermediate(child)
            written = self._joint(
                label, kind, previous, child, origin, (joint, axis), "joint", None
            )
            if int(self.model.jnt_type[joint]) == int(self.mujoco.mjtJoint.mjJNT_BALL):
                self.ball_joints.setdefault(joint, []).append(written)
            else:
                self.hinges[joint] = written
            self.origin_of[("joint", label)] = self.lines.of("joint", self.joint_name(joint))
            previous = child
            offset = ((-anchor[0], -anchor[1], -anchor[2]), IDENTITY)
        if previous != link:
            self._joint(f"{name}_anchor", "fixed", previous, link, offset, None, "body", name)
        self._inertial(link, body)
        self._geoms(link, body)

    def _steps(self, body: int) -> list[tuple[int, Vector, str, Vector, str]]:
        """The one-degree-of-freedom joints that move ``body``, in MuJoCo's order: (MuJoCo
        joint, axis, URDF type, anchor, URDF name)."""
        model, mj = self.model, self.mujoco
        steps = []
        for joint in range(
            int(model.body_jntadr[body]), int(model.body_jntadr[body] + model.body_jntnum[body])
        ):
            kind = int(model.jnt_type[joint])
            name = self.joint_name(joint)
            anchor = _vector(model.jnt_pos[joint])
            if kind == int(mj.mjtJoint.mjJNT_HINGE):
                limited = bool(model.jnt_limited[joint])
                urdf = "revolute" if limited else "continuous"
                steps.append((joint, _vector(model.jnt_axis[joint]), urdf, anchor, name))
            elif kind == int(mj.mjtJoint.mjJNT_SLIDE):  # a slide moves the same from anywhere
                steps.append((joint, _vector(model.jnt_axis[joint]), "prismatic", ZERO, name))
            elif kind == int(mj.mjtJoint.mjJNT_BALL):
                limited = bool(model.jnt_limited[joint])
                urdf = "revolute" if limited else "continuous"
                if limited:
                    self.limit_cones.append(name)
                for axis, suffix in (((1.0, 0.0, 0.0), "x"), ((0.0, 1.0, 0.0), "y")):
                    steps.append((joint, axis, urdf, anchor, f"{name}_{suffix}"))
                steps.append((joint, (0.0, 0.0, 1.0), urdf, anchor, f"{name}_z"))
            else:  # a free joint below the root: MuJoCo allows it only on a top-level body
                self._drop("joint", "free joints below the root", name, name)
        return steps

    # -- elements

    def _link(self, name: str, tag: str, mjcf_name: str | None) -> str:
        name = self._unique(name, self.taken_links)
        etree.SubElement(self.robot, "link", name=name)
        self.origin_of[("link", name)] = self.lines.of(tag, mjcf_name)
        return name

    def _element(self, link: str) -> etree._Element:
        found = self.robot.find(f"link[@name='{link}']")
        assert found is not None
        return found

    def _joint(
        self,
        name: str,
        kind: str,
        parent: str,
        child: str,
        origin: Pose,
        moving: tuple[int, Vector] | None,
        tag: str,
        mjcf_name: str | None,
    ) -> str:
        name = self._unique(name, self.taken_joints)
        element = etree.SubElement(self.robot, "joint", name=name, type=kind)
        etree.SubElement(element, "parent", link=parent)
        etree.SubElement(element, "child", link=child)
        _origin(element, origin)
        self.origin_of.setdefault(("joint", name), self.lines.of(tag, mjcf_name))
        if moving is None:
            return name
        model = self.model
        joint, axis = moving
        etree.SubElement(element, "axis", xyz=_numbers(axis))
        address = int(model.jnt_qposadr[joint])
        dof = int(model.jnt_dofadr[joint])
        ball = int(model.jnt_type[joint]) == int(self.mujoco.mjtJoint.mjJNT_BALL)
        if kind != "continuous":
            if ball:
                lower, upper = -float(model.jnt_range[joint][1]), float(model.jnt_range[joint][1])
            elif bool(model.jnt_limited[joint]):
                ref = float(model.qpos0[address])  # values count from ref: 0 is as written
                lower, upper = (float(v) - ref for v in model.jnt_range[joint])
            else:
                lower, upper = -math.inf, math.inf
            etree.SubElement(
                element,
                "limit",
                lower=_number(lower),
                upper=_number(upper),
                # not rated here: robospec new reads the joint's actuatorfrcrange and the
                # actuators' forceranges from the file itself
                effort="0",
                velocity="0",
            )
        damping, friction = float(model.dof_damping[dof]), float(model.dof_frictionloss[dof])
        if damping or friction:
            etree.SubElement(
                element, "dynamics", damping=_number(damping), friction=_number(friction)
            )
        armature = float(model.dof_armature[dof])  # (a ball's three dofs: its one value)
        if armature:
            self.armature[name] = armature
        return name

    def _inertial(self, link: str, body: int) -> None:
        model = self.model
        mass = float(model.body_mass[body])
        moments = [max(float(v), INERTIA_FLOOR) for v in model.body_inertia[body]]
        if mass <= 0:  # a massless MuJoCo body: SAPIEN would make it 1 kg
            mass, moments = _LINK_MASS, [_LINK_INERTIA] * 3
        pose = (_vector(model.body_ipos[body]), _quaternion(model.body_iquat[body]))
        _write_inertial(self._element(link), mass, pose, moments)

    def _intermediate(self, link: str) -> None:
        _write_inertial(self._element(link), _LINK_MASS, (ZERO, IDENTITY), [_LINK_INERTIA] * 3)

    def _geoms(self, link: str, body: int) -> None:
        model = self.model
        element = self._element(link)
        start = int(model.body_geomadr[body])
        for geom in range(start, start + int(model.body_geomnum[body])):
            shape = self._shape(geom)
            if shape is None:
                continue
            pose = (_vector(model.geom_pos[geom]), _quaternion(model.geom_quat[geom]))
            collides = bool(model.geom_contype[geom]) or bool(model.geom_conaffinity[geom])
            if collides:
                collision = etree.SubElement(element, "collision")
                _origin(collision, pose)
                collision.append(_copy(shape))
            if int(model.geom_group[geom]) < _VISIBLE_GROUPS:
                visual = etree.SubElement(element, "visual")
                _origin(visual, pose)
                visual.append(_copy(shape))
                material = int(model.geom_matid[geom])
                rgba = model.mat_rgba[material] if material >= 0 else model.geom_rgba[geom]
                colour = etree.SubElement(visual, "material", name=f"{link}_geom{geom}")
                etree.SubElement(colour, "color", rgba=_numbers(rgba))

    def _shape(self, geom: int) -> etree._Element | None:
        """The URDF ``<geometry>`` of ``geom``; None (and what is dropped) for a type URDF
        has no shape for."""
        model, types = self.model, self.mujoco.mjtGeom
        kind = int(model.geom_type[geom])
        size = [float(v) for v in model.geom_size[geom]]
        geometry = etree.Element("geometry")
        radius = _number(size[0])
        length = _number(2 * size[1]) if len(size) > 1 else "0"  # MuJoCo gives half lengths
        if kind == int(types.mjGEOM_BOX):
            etree.SubElement(geometry, "box", size=_numbers([2 * s for s in size]))
        elif kind == int(types.mjGEOM_SPHERE):
            etree.SubElement(geometry, "sphere", radius=_number(size[0]))
        elif kind == int(types.mjGEOM_CYLINDER):
            etree.SubElement(geometry, "cylinder", radius=radius, length=length)
        elif kind == int(types.mjGEOM_CAPSULE):
            etree.SubElement(geometry, "capsule", radius=radius, length=length)
        elif kind == int(types.mjGEOM_MESH):
            file = self._mesh_file(int(model.geom_dataid[geom]))
            etree.SubElement(geometry, "mesh", filename=file)
        elif kind == int(types.mjGEOM_ELLIPSOID):
            etree.SubElement(geometry, "mesh", filename=_ellipsoid_file(size))
        else:
            what = {int(types.mjGEOM_PLANE): "planes", int(types.mjGEOM_HFIELD): "height fields"}
            name = self.mujoco.mj_id2name(model, self.mujoco.mjtObj.mjOBJ_GEOM, geom)
            self._drop(
                "geom", f"{what.get(kind, 'geoms of this type')}", name or f"geom {geom}", name
            )
            return None
        return geometry

    def _mesh_file(self, mesh: int) -> str:
        model = self.model
        start, count = int(model.mesh_vertadr[mesh]), int(model.mesh_vertnum[mesh])
        first, faces = int(model.mesh_faceadr[mesh]), int(model.mesh_facenum[mesh])
        vertices = model.mesh_vert[start : start + count]
        triangles = model.mesh_face[first : first + faces]
        name = self.mujoco.mj_id2name(model, self.mujoco.mjtObj.mjOBJ_MESH, mesh) or f"mesh{mesh}"
        return _obj_file(name, vertices, triangles)

    # -- what is not carried

    def _drop(self, tag: str, kind: str, what: str, mjcf_name: str | None) -> None:
        at = self.lines.of(tag, mjcf_name)
        self.dropped.setdefault(kind, (at, tag, []))[2].append(what)

    def _report_dropped(self) -> None:
        model = self.model
        # a <connect> between two of the robot's bodies is carried: a closed loop (the
        # description's closures, which new writes under loops:); other equalities are not
        carried = len(self.closures())
        counted = (
            ("equality", int(model.neq) - carried, "equality constraints (<equality>)"),
            ("tendon", int(model.ntendon), "tendons (<tendon>)"),
            ("contact", int(model.npair) + int(model.nexclude), "contact pairs and exclusions"),
            ("actuator", int(model.nu), "actuators (the spec's controllers drive the joints)"),
        )
        for tag, count, kind in counted:
            if count:
                self.dropped[kind] = (self.lines.of(tag), tag, [f"{count} in the model"])
        if self.limit_cones:
            self.dropped["ball joint cones (each of its hinges gets the cone's angle)"] = (
                self.lines.of("joint", self.limit_cones[0]),
                "joint",
                self.limit_cones,
            )
        for kind, (at, tag, listed) in self.dropped.items():
            shown = ", ".join(listed[:_LISTED])
            more = f" and {len(listed) - _LISTED} more" if len(listed) > _LISTED else ""
            what = shown + more
            self.diagnostics.append(
                warning(
                    self.lines.location(at, tag),
                    MUJOCO_NOT_CARRIED,
                    f"the URDF written from MuJoCo's model carries no {kind}: {what}",
                    "ManiSkill's URDF loader has nothing for them; give what matters as the "
                    "spec's sections (controllers, mimic, loops)",
                )
            )

    # -- what the description carries besides the URDF

    def keyframes(self) -> tuple[Any, ...]:
        """The model's ``<key>`` elements in ManiSkill's terms: each joint counted from its
        ``qpos0`` (``ref``), a ball joint as its three hinges' turns (x, then y, then z), the
        free root's part as the root body's world pose."""
        from robospec.description.facts import FileKeyframe

        model, mj = self.model, self.mujoco
        found = []
        for key in range(int(model.nkey)):
            qpos, qvel = model.key_qpos[key], model.key_qvel[key]
            positions: list[tuple[str, float]] = []
            velocities: list[tuple[str, float]] = []
            for joint, name in self.hinges.items():
                address, dof = int(model.jnt_qposadr[joint]), int(model.jnt_dofadr[joint])
                positions.append((name, float(qpos[address] - model.qpos0[address])))
                velocities.append((name, float(qvel[dof])))
            for joint, names in self.ball_joints.items():
                address = int(model.jnt_qposadr[joint])
                turns = _xyz_turns(_quaternion(qpos[address : address + 4]))
                positions.extend(zip(names, turns, strict=True))
            root_pose = None
            if self.free_joint is not None:
                address = int(model.jnt_qposadr[self.free_joint])
                root_pose = (_vector(qpos[address : address + 3]), _quaternion(qpos[address + 3 :]))
            name = mj.mj_id2name(model, mj.mjtObj.mjOBJ_KEY, key) or f"key{key}"
            found.append(
                FileKeyframe(
                    name=name,
                    line=self.lines.of("key", name)[1],
                    qpos=tuple(positions),  # the parsed URDF's qpos order: resolve sorts them
                    root_pose=root_pose,
                    qvel=tuple(v for v in velocities if v[1]),
                )
            )
        return tuple(found)

    def closures(self) -> tuple[Any, ...]:
        """The model's ``<connect>`` equalities between two of the robot's bodies (or sites on
        them) as closed loops: each anchor in the first body's frame, as MuJoCo compiled it
        (``eq_data``'s first three numbers; a site's position in its body)."""
        from robospec.description.facts import Closure

        model, mj = self.model, self.mujoco
        found = []
        for eq in range(int(model.neq)):
            if int(model.eq_type[eq]) != int(mj.mjtEq.mjEQ_CONNECT):
                continue
            first, second = int(model.eq_obj1id[eq]), int(model.eq_obj2id[eq])
            anchor = _vector(model.eq_data[eq][:3])
            if int(model.eq_objtype[eq]) == int(mj.mjtObj.mjOBJ_SITE):
                anchor = _vector(model.site_pos[first])
                first, second = int(model.site_bodyid[first]), int(model.site_bodyid[second])
            if first not in self.links or second not in self.links or 0 in (first, second):
                continue
            name = mj.mj_id2name(model, mj.mjtObj.mjOBJ_EQUALITY, eq)
            line = self.lines.of("connect", name)[1]
            found.append(Closure("connect", self.links[first], self.links[second], anchor, line))
        return tuple(found)

    def actuators(self) -> tuple[Any, ...]:
        """The model's actuators on joints as MuJoCo compiled them: a position servo's kp and
        kv where the gain is fixed and the bias affine ``(0, -kp, -kv)``, a velocity servo's
        kv, a motor's ranges."""
        from robospec.description.facts import Actuator

        model, mj = self.model, self.mujoco
        found = []
        for actuator in range(int(model.nu)):
            name = mj.mj_id2name(model, mj.mjtObj.mjOBJ_ACTUATOR, actuator) or ""
            transmission = int(model.actuator_trntype[actuator])
            target = int(model.actuator_trnid[actuator][0])
            joint = self.hinges.get(target) if transmission == int(mj.mjtTrn.mjTRN_JOINT) else None
            kind, kp, kv = _servo(model, actuator, mj)
            low, high = (float(v) for v in model.actuator_ctrlrange[actuator])
            ctrl = (low, high)
            low, high = (float(v) for v in model.actuator_forcerange[actuator])
            force = (low, high)
            found.append(
                Actuator(
                    name=name,
                    line=self._actuator_line(name),
                    type=kind,
                    joint=joint,
                    kp=kp,
                    kv=kv,
                    ctrl_range=ctrl if bool(model.actuator_ctrllimited[actuator]) else None,
                    force_range=force if bool(model.actuator_forcelimited[actuator]) else None,
                    gear=float(model.actuator_gear[actuator][0]),
                )
            )
        return tuple(found)

    def _actuator_line(self, name: str) -> int:
        from robospec.description.mjcf_control import ACTUATOR_TAGS

        for tag in ACTUATOR_TAGS if name else ():
            if (tag, name) in self.lines.named:
                return self.lines.named[(tag, name)][1]
        return self.lines.of("actuator")[1]

    def line_map(self, text: str) -> tuple[tuple[int, tuple[str, int]], ...]:
        """Each line of ``text`` in a link or a joint -> the line of the MJCF element it was
        written from: the URDF's diagnostics point into the user's file."""
        written = etree.fromstring(text.encode("utf-8"))
        found: dict[int, tuple[str, int]] = {1: (self.source.shown, 1)}
        for element in written:
            origin = self.origin_of.get((str(element.tag), element.get("name", "")))
            if origin is None:
                continue
            for inner in element.iter():
                # every line of the element: a problem inside it is the MJCF element's
                if isinstance(inner.sourceline, int):
                    found[inner.sourceline] = origin
        return tuple(sorted(found.items()))


# -- numbers, frames and files -------------------------------------------------------------


def _servo(model: Any, actuator: int, mj: Any) -> tuple[str, float | None, float | None]:
    """What the actuator is (as MuJoCo's shortcut elements name it) and its servo gains."""
    gain, bias = model.actuator_gainprm[actuator], model.actuator_biasprm[actuator]
    fixed = int(model.actuator_gaintype[actuator]) == int(mj.mjtGain.mjGAIN_FIXED)
    biastype = int(model.actuator_biastype[actuator])
    if fixed and biastype == int(mj.mjtBias.mjBIAS_NONE):
        return "motor", None, None
    if fixed and biastype == int(mj.mjtBias.mjBIAS_AFFINE) and float(bias[0]) == 0:
        kp = float(gain[0])
        if kp and math.isclose(float(bias[1]), -kp, rel_tol=1e-9, abs_tol=1e-12):
            return "position", kp, -float(bias[2]) + 0.0
        if float(bias[1]) == 0 and math.isclose(float(bias[2]), -kp, rel_tol=1e-9):
            return "velocity", None, kp
    return "general", None, None


def _xyz_turns(quaternion: tuple[float, float, float, float]) -> Vector:
    """The turns about x, then the turned y, then the twice-turned z (R = Rx Ry Rz) that make
    the rotation ``quaternion``: URDF's rpy of its inverse (R^T = Rz(-c) Ry(-b) Rx(-a)),
    negated."""
    from robospec.geometry import conjugate, normalized

    roll, pitch, yaw = rpy_from_quaternion(conjugate(normalized(quaternion)))
    return (-roll + 0.0, -pitch + 0.0, -yaw + 0.0)


def _model_name(source: Source) -> str:
    return os.path.splitext(os.path.basename(source.path))[0] or "robot"


def _vector(values: Any) -> Vector:
    return (float(values[0]), float(values[1]), float(values[2]))


def _quaternion(values: Any) -> tuple[float, float, float, float]:
    return (float(values[0]), float(values[1]), float(values[2]), float(values[3]))


def _number(value: float) -> str:
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return repr(float(value) + 0.0)  # + 0.0: never "-0.0"


def _numbers(values: Any) -> str:
    return " ".join(_number(float(v)) for v in values)


def _origin(element: etree._Element, pose: Pose) -> None:
    etree.SubElement(
        element, "origin", xyz=_numbers(pose[0]), rpy=_numbers(rpy_from_quaternion(pose[1]))
    )


def _write_inertial(link: etree._Element, mass: float, pose: Pose, moments: list[float]) -> None:
    inertial = etree.Element("inertial")
    _origin(inertial, pose)
    etree.SubElement(inertial, "mass", value=_number(mass))
    etree.SubElement(
        inertial,
        "inertia",
        ixx=_number(moments[0]),
        ixy="0",
        ixz="0",
        iyy=_number(moments[1]),
        iyz="0",
        izz=_number(moments[2]),
    )
    link.insert(0, inertial)


def _copy(element: etree._Element) -> etree._Element:
    import copy

    return copy.deepcopy(element)


def _obj_file(name: str, vertices: Any, triangles: Any) -> str:
    """The absolute path of an OBJ file of ``vertices`` and ``triangles``, written once into
    robospec's cache folder under a name made of its content."""
    from robospec.files import cache_root

    lines = [f"v {_number(x)} {_number(y)} {_number(z)}" for x, y, z in vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles.tolist()]
    data = ("\n".join(lines) + "\n").encode("ascii")
    key = hashlib.sha256(data).hexdigest()[:32]
    stem = re.sub(r"[^A-Za-z0-9_.\-]", "_", name) or "mesh"
    folder = cache_root() / DERIVED_FOLDER
    target = folder / f"{stem}.{key}.obj"
    if not target.is_file():
        folder.mkdir(parents=True, exist_ok=True)
        staging = target.with_name(target.name + f".{os.getpid()}.tmp")
        staging.write_bytes(data)
        os.replace(staging, target)  # whole or absent: a reader never sees a part
    return str(target)


def _ellipsoid_file(size: list[float]) -> str:
    """An OBJ of the ellipsoid of semi-axes ``size`` (URDF has no ellipsoid): a latitude and
    longitude grid, closed at the poles."""
    import numpy as np

    around, up = _ELLIPSOID_STEPS
    points = [(0.0, 0.0, -size[2])]
    for i in range(1, up):
        polar = math.pi * i / up - math.pi / 2
        for j in range(around):
            turn = 2 * math.pi * j / around
            points.append(
                (
                    size[0] * math.cos(polar) * math.cos(turn),
                    size[1] * math.cos(polar) * math.sin(turn),
                    size[2] * math.sin(polar),
                )
            )
    points.append((0.0, 0.0, size[2]))
    faces = []
    top = len(points) - 1

    def ring(i: int, j: int) -> int:
        return 1 + (i - 1) * around + j % around

    for j in range(around):
        faces.append((0, ring(1, j + 1), ring(1, j)))
        faces.append((top, ring(up - 1, j), ring(up - 1, j + 1)))
        for i in range(1, up - 1):
            faces.append((ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)))
            faces.append((ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)))
    return _obj_file("ellipsoid", np.asarray(points), np.asarray(faces))
