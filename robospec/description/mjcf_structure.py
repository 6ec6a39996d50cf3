"""What ManiSkill's MJCF loader does to the model's structure, reported at the element:

* RS082 — ``<include>`` anywhere but directly under ``<mujoco>`` is not read (ElementTree
  leaves it an unknown element): whatever it holds is not loaded, and when that is the robot's
  bodies, ManiSkill takes the next body with a joint for the robot (gymnasium-robotics' Adroit:
  the pen instead of the hand) or finds none (its Shadow hand).
* RS081 — the loader gives the k-th body of the robot bit k of collision group 2, shared with
  its parent body: bit 30 is the ground's in ManiSkill's scenes (those bodies fall through the
  floor) and a 33rd body's bit 32 does not fit SAPIEN's 32-bit groups (``set_collision_groups``
  refuses it: dm_control's dog and rodent).
* RS083 — a ``<worldbody>`` body holding nothing but one body is skipped, and its pose with it.
* RS084 — joint attributes the loader does not read: ``ref``, ``stiffness`` (springs),
  ``armature``.
* RS094 — an asset name defined twice (per kind, an unnamed mesh named after its file): MuJoCo
  refuses the model, the loader keeps the last definition without a word.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator

from lxml import etree

from robospec.description.mjcf_frames import Unparsable, body_pose, same_rotation
from robospec.description.mjcf_loaded import LoadedBody, LoadedMjcf
from robospec.description.mjcf_mujoco import MAIN_CLASS, Includes
from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.diagnostics.codes import (
    MJCF_COLLISION_BITS,
    MJCF_JOINT_ATTRIBUTES,
    MJCF_REPEATED_ASSET,
    MJCF_SKIPPED_WRAPPER,
    MJCF_UNREAD_INCLUDE,
)
from robospec.geometry import IDENTITY
from robospec.maniskill.scenes import GROUND_BITS

NAMED_ASSETS = ("mesh", "texture", "material", "hfield", "skin")

GROUND_BIT = GROUND_BITS[0]  # the loader gives the 31st body the first of the ground's bits
GROUP_BITS = 32


def names(items: list[str], most: int = 6) -> str:
    """``a, b, c`` — or the first ``most`` and how many more."""
    quoted = [f"'{item}'" for item in items]
    if len(quoted) <= most:
        return ", ".join(quoted)
    return ", ".join(quoted[:most]) + f" and {len(quoted) - most} more"


def unread_includes(
    root: etree._Element,
    includes: Includes,
    where: Callable[[etree._Element], Location],
    chosen: etree._Element | None,
) -> Iterator[Diagnostic]:
    """RS082 for each ``<include>`` of the model file that is not a child of ``<mujoco>``."""
    for include in root.iter("include"):
        if include.getparent() is root:
            continue
        included = includes.root(include)
        if included is None:
            continue  # MuJoCo cannot read it either; nothing ManiSkill loses
        file = include.get("file", "")
        bodies = [b for b in included.iter("body")]
        joints = [j for j in included.iter("joint", "freejoint")]
        parent = include.getparent()
        where_it_is = f"<{parent.tag!s}>" if parent is not None else "here"
        message = (
            f'<include file="{file}"> inside {where_it_is} is not read by ManiSkill\'s MJCF '
            "loader (only those directly under <mujoco> are)"
        )
        hint = f"write the contents of {os.path.basename(file)} in place of the <include>"
        if joints:
            message += f": its {len(bodies)} bodies and {len(joints)} joints are not loaded"
            if chosen is None:
                message += ", and no body with a joint is left for ManiSkill to load"
            elif not _inside(include, chosen):
                message += f"; the robot ManiSkill loads is body '{chosen.get('name', '')}'"
            yield error(where(include), MJCF_UNREAD_INCLUDE, message, hint)
        else:
            what = {child.tag for child in included if isinstance(child.tag, str)}
            held = ", ".join(f"<{tag}>" for tag in sorted(what)) or "nothing"
            yield warning(where(include), MJCF_UNREAD_INCLUDE, f"{message}: it holds {held}", hint)


def _inside(element: etree._Element, ancestor: etree._Element) -> bool:
    return any(parent is ancestor for parent in element.iterancestors())


def collision_bits(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS081: bodies whose loader bit is the ground's, or does not fit."""
    count = len(loaded.robot)
    too_many = [body for body in loaded.robot if body.bit >= GROUP_BITS]
    if too_many:
        fixed = sum(1 for body in loaded.robot if not body.moves and body.parent is not None)
        if count - fixed <= GROUP_BITS:
            hint = (
                f"merge the {fixed} bodies without joints into their parents (their geoms "
                f"move up, posed as the body was) in a copy of the model: {count - fixed} "
                "bodies fit; `description: {mend: {bodies: merge}}` does it"
            )
        else:
            hint = (
                f"ManiSkill 3.0.1's MJCF loader loads robots of at most {GROUP_BITS} bodies; "
                "`description: {mjcf: ..., loader: mujoco}` loads every body, as MuJoCo "
                "compiles the file"
            )
        first = too_many[0]
        yield error(
            loaded.where(first.element),
            MJCF_COLLISION_BITS,
            f"the robot has {count} bodies: ManiSkill's MJCF loader gives the k-th body bit k "
            f"of collision group 2, and from body '{first.name}' on (the "
            f"{GROUP_BITS + 1}rd) the bit does not fit SAPIEN's {GROUP_BITS}-bit groups: "
            "loading fails (set_collision_groups: incompatible function arguments)",
            hint,
        )
    ground = next((body for body in loaded.robot if body.bit == GROUND_BIT), None)
    if ground is not None and not too_many:
        yield warning(
            loaded.where(ground.element),
            MJCF_COLLISION_BITS,
            f"ManiSkill's MJCF loader gives body '{ground.name}' (the {GROUND_BIT + 1}st) and "
            f"its parent '{ground.parent_link}' bit {GROUND_BIT} of collision group 2, which "
            "ManiSkill's scenes set on the ground: these two links do not collide with the floor",
            "bodies without joints merged into their parents leave fewer bodies: "
            "`description: {mend: {bodies: merge}}` does it in a copy of the model",
        )


def skipped_wrapper(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS083: the loader skipped the robot's worldbody body, and its pose with it."""
    wrapper = loaded.robot_element
    if not loaded.robot or loaded.robot[0].element is wrapper:
        return
    try:
        position, rotation = body_pose(wrapper.attrib, loaded.degrees, loaded.eulerseq)
    except Unparsable:
        return
    if math.dist(position, (0.0, 0.0, 0.0)) < 1e-12 and same_rotation(rotation, IDENTITY, 1e-12):
        return
    inner = loaded.robot[0].name
    yield warning(
        loaded.where(wrapper),
        MJCF_SKIPPED_WRAPPER,
        f"ManiSkill's MJCF loader skips body '{wrapper.get('name', '')}', which holds only "
        f"body '{inner}', and with it its pos/orientation: '{inner}' is loaded relative to "
        "the robot's root pose as if the wrapper were not there",
        "robospec's keyframe poses put the robot where the file does (see docs/loaders.md); "
        "a pose a task sets for the robot does not include the wrapper's",
    )


# attribute -> (is it set?, what the robot lacks without it)
_IGNORED_JOINT_ATTRIBUTES: dict[str, str] = {
    "ref": "ManiSkill measures these joints from the pose the file draws, MuJoCo from ref: "
    "their ranges and keyframe values are offset by ref",
    "stiffness": "the joint springs (stiffness, springref) are not loaded: nothing pulls "
    "these joints back",
    "armature": "armature (rotor inertia) is not loaded: these joints are lighter than in "
    "MuJoCo, and stiff drives on them less stable (loader: mujoco sets it)",
}


def joint_attributes(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS084: one warning per attribute the loader ignores, at the first joint that sets it."""
    found: dict[str, list[tuple[LoadedBody, etree._Element]]] = {}
    for body in loaded.robot:
        childclass = _childclass(body)
        for joint in body.joints:
            table = loaded.mujoco_classes.get(joint.get("class", childclass)) or {}
            attributes = {**table.get("joint", {}), **joint.attrib}
            for name in _IGNORED_JOINT_ATTRIBUTES:
                if _nonzero(attributes.get(name)):
                    found.setdefault(name, []).append((body, joint))
    for name, lack in _IGNORED_JOINT_ATTRIBUTES.items():
        joints = found.get(name)
        if not joints:
            continue
        listed = names([joint.get("name", "") for _, joint in joints])
        yield warning(
            loaded.where(joints[0][1]),
            MJCF_JOINT_ATTRIBUTES,
            f"ManiSkill's MJCF loader ignores joint {name}=, set on {len(joints)} joint(s) "
            f"({listed}): {lack}",
        )


def _childclass(body: LoadedBody) -> str:
    """The childclass in force in ``body`` (MuJoCo: the nearest body's up the tree)."""
    for element in (body.element, *body.element.iterancestors("body")):
        if element.get("childclass") is not None:
            return str(element.get("childclass"))
    return MAIN_CLASS


def _nonzero(text: str | None) -> bool:
    if text is None:
        return False
    try:
        return any(float(part) != 0 for part in text.split()[:1])
    except ValueError:
        return False


def repeated_assets(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS094: asset names defined more than once, one error for the file, at the first repeat."""
    found: dict[tuple[str, str], list[etree._Element]] = {}
    for section in loaded.sections("asset"):
        for element in loaded.includes.children(section):
            if element.tag not in NAMED_ASSETS:
                continue
            name = element.get("name")
            if not name and element.tag == "mesh":
                name = os.path.splitext(os.path.basename(element.get("file", "")))[0]
            if name:
                found.setdefault((str(element.tag), name), []).append(element)
    repeated = [(key, elements) for key, elements in found.items() if len(elements) > 1]
    if not repeated:
        return
    (tag, name), elements = repeated[0]
    first = loaded.where(elements[0])
    listed = names([f"{t} {n}" for (t, n), _ in repeated])
    yield error(
        loaded.where(elements[1]),
        MJCF_REPEATED_ASSET,
        f"{tag} '{name}' is defined again (first at line {first.line})"
        + (f", and {len(repeated) - 1} more name(s) too ({listed})" if len(repeated) > 1 else "")
        + ": MuJoCo refuses the model (repeated name), and ManiSkill's MJCF loader keeps the "
        "last definition without a word, so geoms meant for the first load another file",
        "remove or rename the repeats, or keep one definition of each in a copy: "
        "`description: {mend: {asset_names: first}}` (or `last`)",
    )
