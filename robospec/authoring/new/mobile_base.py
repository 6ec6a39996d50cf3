"""Which robots ``robospec new`` gives a drivable planar base (the spec's ``mobile_base``,
applied by :mod:`robospec.derive.planar_base`), and the description it then scaffolds.

ManiSkill's guide drives a mobile base directly: an x slide, a y slide and a z hinge above the
base link, a ``pd_base_vel`` controller, the wheels kept out of the floor's collisions (wheels
rolling on a floor simulate slowly and transfer badly). ``new`` writes that section for

* a URDF that rolls on continuous wheel joints, with no legs and nothing that fixes or moves
  its root otherwise (Husky, R2-D2, the racecar), or an MJCF MuJoCo compiles that rolls so (its
  ball-jointed casters three hinges, its free root replaced by the base's joints): its wheel
  joints are welded (``wheel_joints: fixed``: fewer joints to simulate; Fetch's wheels are
  fixed joints too);
* a URDF whose base hangs from a ``planar`` or ``floating`` root joint, which SAPIEN loads as
  neither: the base's slides and hinge stand in for it;
* a description with no joint that moves (a platform): instead of nothing to control, a base
  to drive.

The links that touch the floor leave its collisions: the wheels (links named wheel, caster,
tire or tyre, and everything the wheel joints turn); without any, the base and the links fixed
to it, so that the body slides over the floor instead of dragging on it.

Everything after reading sees the derived description, the base's joints in it: the groups,
the keyframes and the rest-pose search are the same as for any robot. The same function reads
the file for the scaffold and for the gains' refinement in the probe's child process, so both
see one robot.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from robospec.authoring.description_file import DescriptionFile, read_description_file
from robospec.description import RobotDescription
from robospec.diagnostics import Diagnostic
from robospec.kinematics.morphology import WHEEL_WORDS, morphology
from robospec.kinematics.tree import KinematicTree
from robospec.model.mechanisms import MobileBase
from robospec.resolve.description_loading import mobile_base_settings

SECTION = "mobile_base"


def read_for_new(path: Path) -> tuple[DescriptionFile | None, list[Diagnostic]]:
    """The description ``new`` scaffolds: the file as it loads, or the derived copy with a
    planar base where one is wanted (:attr:`DescriptionFile.mobile_base` then says why and
    holds the section)."""
    source, diagnostics = read_description_file(path, compile_mjcf=True)
    if source is not None and source.description.active_joints:
        rolling = _wheeled(source)
        if rolling is None:
            return source, diagnostics
        links, joints = rolling
        why = "it rolls on wheels (" + ", ".join(joints) + ")"
        wheeled = {"wheels": links, "wheel_joints": "fixed"}
        return _with_base(path, wheeled, why, (source, diagnostics))
    # no joint that moves, or none ManiSkill loads as it is: a base is something to control
    as_written, _ = read_description_file(path, keep_errors=True)
    based, more = read_description_file(path, sections=_sections({}))
    if based is None or _legs(based):
        return source, diagnostics
    base = _base_link(based.description)
    section: dict[str, Any] = {}
    floor = _rigid_group(based.description, base) if base is not None else []
    if floor:
        section["wheels"] = floor
    why = _why_base(as_written.description if as_written else None, base)
    return _with_base(path, section, why, (based, more))


def _with_base(
    path: Path,
    section: dict[str, Any],
    why: str,
    fallback: tuple[DescriptionFile | None, list[Diagnostic]],
) -> tuple[DescriptionFile | None, list[Diagnostic]]:
    """The description with the planar base ``section`` asks for; ``fallback`` where it does
    not load so (the file's own problems are said as the file has them)."""
    based, diagnostics = read_description_file(path, sections=_sections(section), compile_mjcf=True)
    if based is None:
        return fallback
    return dataclasses.replace(based, mobile_base=section, mobile_base_why=why), diagnostics


def _sections(section: dict[str, Any]) -> dict[str, Any]:
    return {SECTION: mobile_base_settings(MobileBase(**section))}


def _wheeled(source: DescriptionFile) -> tuple[list[str], tuple[str, ...]] | None:
    """The links that touch the floor and the wheel joints of a URDF that rolls on its wheels
    and nothing else (no legs; a root that nothing anchors, slides or moves on planar joints),
    or None."""
    description = source.description
    if source.kind == "mjcf" and source.loader != "mujoco":
        return None  # (ManiSkill's MJCF loader: MuJoCo refused the file)
    body = morphology(description, None)
    if not body.wheels or body.legs or not body.walks_or_rolls:
        return None
    tree = KinematicTree(description)
    turned = {
        link
        for joint in body.wheels
        if (found := description.joint(joint)) is not None
        for link in _subtree(tree, found.child)
    }
    named = {link for link in description.link_names if WHEEL_WORDS.search(link)}
    links = [n for n in description.link_names if n in turned | named]
    if source.kind == "mjcf":
        # the MJCF's bodies (the section applies to the MJCF): a ball joint's intermediate
        # links are the compiled URDF's alone, and have no shapes
        links = [n for n in links if (link := description.link(n)) is not None and link.shaped]
    return links, body.wheels


def _subtree(tree: KinematicTree, link: str) -> list[str]:
    out, queue = [link], [link]
    while queue:
        for joint in tree.below.get(queue.pop(), []):
            out.append(joint.child)
            queue.append(joint.child)
    return out


def _base_link(description: RobotDescription) -> str | None:
    """The link the derived copy's yaw hinge carries (the base), or None."""
    yaw = description.joint(MobileBase().joints[2])
    return yaw.child if yaw is not None else None


def _rigid_group(description: RobotDescription, base: str) -> list[str]:
    """``base`` and the links fixed to it (through fixed joints, either way)."""
    fixed = [j for j in description.joints if j.type == "fixed"]
    group, queue = {base}, [base]
    while queue:
        link = queue.pop()
        for joint in fixed:
            for a, b in ((joint.parent, joint.child), (joint.child, joint.parent)):
                if a == link and b not in group:
                    group.add(b)
                    queue.append(b)
    return [n for n in description.link_names if n in group]


def _legs(source: DescriptionFile) -> bool:
    return bool(morphology(source.description, None).legs)


def _why_base(as_written: RobotDescription | None, base: str | None) -> str:
    planar = [j for j in as_written.joints if j.type == "planar"] if as_written else []
    if planar:
        return (
            f"its base moves on a planar joint ({planar[0].name}), which SAPIEN cannot load: "
            "the base's slides and hinge stand in for it"
        )
    if as_written is not None and as_written.floating_root:
        return (
            f"its base ({base}) hangs from a floating joint, which SAPIEN loads only at the "
            "root: the base's slides and hinge stand in for it"
        )
    return "it has no joint that moves: a platform, driven as a mobile base"
