"""``robospec new --from-urdf``: a first spec for a robot description, guessed and commented.

The spec validates as written: every active joint is in a group (:mod:`.groups`), every group
is driven in both control modes, the keyframe lies inside the limits and keeps mimic relations.

* Description path: ``{maniskill_assets}/...`` for a file inside ManiSkill's assets (portable
  across machines), otherwise relative to the spec's folder.
* Schema modeline: the nearest ``schemas/robospec.schema.json`` or ``robospec.schema.json``
  walking up from the spec's folder, no higher than the repository it is in (the first folder
  with a ``.git``), as a relative path; when there is none, the command writes
  ``robospec.schema.json`` beside the spec (editors then work offline, and the next spec written
  to that folder finds it).
* uid: ``--uid``, else the robot's name made a valid uid; a name ManiSkill already registers
  gets an ``rs_`` prefix (robospec refuses to shadow ManiSkill's agents by accident).
* Gains are ManiSkill's Panda's (stiffness 1e3, damping 1e2, force_limit 100); wheels and mobile
  roots get a joint-velocity controller (damping 1e3, force_limit 500, ±1) in both modes.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path
from typing import Any

from robospec.authoring.description_file import DescriptionFile
from robospec.authoring.groups import Groups, guess_groups
from robospec.importer.groups import split_by_group
from robospec.importer.specdata import KeyPath, SpecDoc
from robospec.maniskill.builtin_uids import MANISKILL_UIDS
from robospec.resolve.paths import ASSETS_PLACEHOLDER, maniskill_assets_dir

SCHEMA_BESIDE = "robospec.schema.json"
# where a project keeps the schema, nearest first at each folder walking up
SCHEMA_FILES = (Path("schemas") / SCHEMA_BESIDE, Path(SCHEMA_BESIDE))
# a folder holding this is a repository's root: the walk stops there (a schema above it belongs
# to another project)
PROJECT_ROOT_MARKER = ".git"

GAINS: dict[str, Any] = {"stiffness": 1e3, "damping": 1e2, "force_limit": 100}
BASE_VELOCITY: dict[str, Any] = {"lower": -1.0, "upper": 1.0, "damping": 1e3, "force_limit": 500}
DELTA = 0.1


# robot names that CAD exporters write (SolidWorks' sw_urdf_exporter: "ARM_URDF.SLDASM"):
# the assembly's file name, not what anyone calls the robot
_CAD_EXPORT_NAME = re.compile(r"\.(SLDASM|SLDPRT)$", re.IGNORECASE)


def default_uid(robot_name: str | None, path: Path) -> str:
    """The robot's name as a valid uid (the file's stem when the description has no name, or
    only the CAD assembly's name)."""
    raw = robot_name or ""
    if not raw or _CAD_EXPORT_NAME.search(raw):
        raw = path.name.split(".")[0]
    uid = re.sub(r"[^A-Za-z0-9_.\-]+", "_", raw).lstrip("_.-")[:64].rstrip("_") or "robot"
    if uid in MANISKILL_UIDS:
        uid = f"rs_{uid}"[:64]
    return uid


def schema_reference(spec_dir: Path) -> str | None:
    """The schema a spec in ``spec_dir`` should name, relative to it; None when there is none
    in ``spec_dir`` or above it, up to the root of the repository it is in."""
    folder = spec_dir.resolve()
    for parent in (folder, *folder.parents):
        for candidate in SCHEMA_FILES:
            if (parent / candidate).is_file():
                return Path(os.path.relpath(parent / candidate, folder)).as_posix()
        if (parent / PROJECT_ROOT_MARKER).exists():
            break
    return None


def description_reference(source: DescriptionFile, spec_dir: Path) -> str:
    absolute = source.path.resolve()
    assets = maniskill_assets_dir()
    if assets is not None and absolute.is_relative_to(assets.resolve()):
        return f"{ASSETS_PLACEHOLDER}/" + absolute.relative_to(assets.resolve()).as_posix()
    return Path(os.path.relpath(absolute, spec_dir.resolve())).as_posix()


def safe_position(lower: float | None, upper: float | None) -> float:
    """0 when the limits allow it (or there are none), else the middle of the range."""
    if lower is None or upper is None:
        return 0.0
    if lower <= 0.0 <= upper:
        return 0.0
    return (lower + upper) / 2


def keyframe_qpos(source: DescriptionFile, groups: Groups) -> dict[str, float]:
    """A safe pose by joint: mimic followers follow their leader (clamped into their limits)."""
    description = source.description
    qpos = {j.name: safe_position(j.lower, j.upper) for j in description.active_joints}
    for link in groups.mimic:
        joint = description.joint(link.follower)
        assert joint is not None
        value = qpos[link.leader] * link.multiplier + link.offset
        low = -math.inf if joint.lower is None else joint.lower
        high = math.inf if joint.upper is None else joint.upper
        qpos[link.follower] = min(max(value, low), high)
    return {name: _tidy(value) for name, value in qpos.items()}


def _tidy(value: float) -> float:
    return float(round(value, 6)) + 0.0  # +0.0: never write -0.0


def scaffold(source: DescriptionFile, spec_path: Path, uid: str | None = None) -> SpecDoc:
    spec_dir = spec_path.parent
    description = source.description
    groups = guess_groups(description)
    uid = uid or default_uid(source.robot_name, source.path)
    notes: dict[KeyPath, str] = {}
    data: dict[str, Any] = {"robospec": 1, "uid": uid}

    key = "urdf" if source.kind == "urdf" else source.kind
    data["description"] = {key: description_reference(source, spec_dir)}
    notes[("description",)] = "relative paths are relative to this file"
    if description.floating_root:
        data["loader"] = {"fix_root_link": False}
        notes[("loader", "fix_root_link")] = "the root is attached by a free joint"

    data["groups"] = {name: list(joints) for name, joints in groups.groups.items()}
    notes[("groups",)] = "guessed from joint names and the kinematic tree: check them"

    qpos = keyframe_qpos(source, groups)
    partition = [(name, tuple(joints)) for name, joints in groups.groups.items()]
    by_group = split_by_group(list(qpos.values()), tuple(qpos), partition)
    assert by_group is not None  # one value per active joint, by construction
    data["keyframes"] = {"rest": {"qpos": by_group}}
    notes[("keyframes",)] = "rest: 0 where the limits allow, else mid-range"

    controllers, modes = _controllers(groups)
    data["controllers"] = controllers
    notes[("controllers",)] = "defined once, used by the control modes below"
    data["control_modes"] = modes
    notes[("control_modes",)] = "the first is the default"

    header = (
        f"robospec spec scaffolded by `robospec new` from {source.path.name}.",
        "Check the groups, gains and keyframe, then: robospec validate <this file>",
    )
    return SpecDoc(data, header, notes)


def _controllers(groups: Groups) -> tuple[dict[str, Any], dict[str, Any]]:
    controllers: dict[str, Any] = {}
    absolute: dict[str, str] = {}
    relative: dict[str, str] = {}
    mimic_maps = {m.follower: m for m in groups.mimic}
    for name, kind in groups.kinds.items():
        if kind == "base":
            controllers[f"{name}_vel"] = {"type": "pd_joint_vel", "joints": name, **BASE_VELOCITY}
            absolute[name] = relative[name] = f"{name}_vel"
        elif kind == "mimic":
            mimic: dict[str, Any] = {}
            for joint in groups.groups[name]:
                link = mimic_maps.get(joint)
                if link is None:
                    continue
                if link.multiplier == 1.0 and link.offset == 0.0:
                    mimic[joint] = link.leader
                else:
                    mimic[joint] = {
                        "joint": link.leader,
                        "multiplier": link.multiplier,
                        "offset": link.offset,
                    }
            controllers[name] = {
                "type": "pd_joint_pos_mimic",
                "joints": name,
                "lower": None,
                "upper": None,
                **GAINS,
                "normalize_action": False,
                "mimic": mimic,
            }
            absolute[name] = relative[name] = name
        else:
            controllers[f"{name}_pos"] = {
                "type": "pd_joint_pos",
                "joints": name,
                "lower": None,
                "upper": None,
                **GAINS,
                "normalize_action": False,
            }
            controllers[f"{name}_delta_pos"] = {
                "extends": f"{name}_pos",
                "lower": -DELTA,
                "upper": DELTA,
                "use_delta": True,
                "normalize_action": True,
            }
            absolute[name] = f"{name}_pos"
            relative[name] = f"{name}_delta_pos"
    modes = {"pd_joint_delta_pos": relative, "pd_joint_pos": absolute}
    return controllers, modes
