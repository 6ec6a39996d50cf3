"""``robospec new``: a first spec for a robot description, guessed, checked and commented.

The spec validates as written, and is meant to be right for the robot, not just valid:

* Body: a floating robot (an MJCF free joint; legs or wheels and nothing fixing it to the world:
  :mod:`robospec.kinematics.morphology`) gets ``loader: {fix_root_link: false}``,
  ``balance_passive_force: false`` in every mode and a rest keyframe standing on the ground; a
  planar base a base controller.
* Groups: :mod:`.groups` (legs by side, arm, gripper, ...); controllers:
  :mod:`.scaffold_controllers` (MJCF actuator gains where the description has them).
* Keyframes: ``rest`` first — searched free of self-contact in ManiSkill when it is installed
  (:mod:`.rest_pose`) — then the description's own (an MJCF's ``<key>`` elements).
* Description path: ``{maniskill_assets}/...`` for a file inside ManiSkill's assets (portable
  across machines), otherwise relative to the spec's folder.
* Schema modeline: the nearest ``schemas/robospec.schema.json`` or ``robospec.schema.json``
  walking up from the spec's folder, no higher than the repository it is in (the first folder
  with a ``.git``), as a relative path; when there is none, the command writes
  ``robospec.schema.json`` beside the spec (editors then work offline, and the next spec written
  to that folder finds it).
* uid: ``--uid``, else the robot's name made a valid uid — the file's name when the robot's
  name names no robot (a CAD assembly, or only generic words: ``physics``, ``plane``,
  ``UF_ROBOT``) — with an ``rs_`` prefix when ManiSkill registers that uid already (robospec
  refuses to shadow ManiSkill's agents by accident).
"""

from __future__ import annotations

import dataclasses
import os
import re
import textwrap
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from robospec.authoring.description_file import DescriptionFile
from robospec.authoring.new.analysis import RobotAnalysis, immobile_reason
from robospec.authoring.new.exemptions import ADJACENT_WHY, filtered_cliques
from robospec.authoring.new.file_keyframes import fit_to_limits
from robospec.authoring.new.gains import DAMPING_RATIO, NATURAL_FREQUENCY, JointGains
from robospec.authoring.new.grip import grip_gains
from robospec.authoring.new.joint_gains import joint_gains
from robospec.authoring.new.ready_pose import ready_pose
from robospec.authoring.new.rest_pose import RestPose
from robospec.authoring.new.scaffold_controllers import controllers_and_modes, unbalanced
from robospec.authoring.new.task_members import gripper_fingers, task_members
from robospec.geometry import IDENTITY, Pose
from robospec.importer.groups import split_by_group
from robospec.importer.specdata import KeyPath, SpecDoc
from robospec.maniskill.installed import registered_uids
from robospec.model.names import NAME_PATTERN
from robospec.resolve.collision_packing import clique_pairs
from robospec.resolve.paths import ASSETS_PLACEHOLDER, maniskill_assets_dir
from robospec.resolve.root_pose import root_body_pose

SCHEMA_BESIDE = "robospec.schema.json"
# where a project keeps the schema, nearest first at each folder walking up
SCHEMA_FILES = (Path("schemas") / SCHEMA_BESIDE, Path(SCHEMA_BESIDE))
# a folder holding this is a repository's root: the walk stops there (a schema above it belongs
# to another project)
PROJECT_ROOT_MARKER = ".git"
HEADER_WIDTH = 98  # "# " + this: the header's lines stay within the line length of 100

# robot names that CAD exporters write (SolidWorks' sw_urdf_exporter: "ARM_URDF.SLDASM"):
# the assembly's file name, not what anyone calls the robot
_CAD_EXPORT_NAME = re.compile(r"\.(SLDASM|SLDPRT)$", re.IGNORECASE)
# words that name no robot: a name made of these (and of abbreviations of one or two letters, a
# vendor's "UF") is a placeholder the exporter or the author left; trailing a name, they go
_GENERIC_WORDS = frozenset(
    {
        "robot",
        "model",
        "physics",
        "plane",
        "world",
        "scene",
        "default",
        "untitled",
        "unnamed",
        "urdf",
        "mjcf",
        "mujoco",
        "xacro",
        "assembly",
        "export",
        "description",
    }
)
_GENERIC_SUFFIX = re.compile(
    r"([^A-Za-z0-9]+(" + "|".join(sorted(_GENERIC_WORDS)) + r"))+$", re.IGNORECASE
)
_NAME = re.compile(NAME_PATTERN)


def names_no_robot(name: str) -> bool:
    """Whether a description's robot name is a placeholder: a CAD assembly's, or generic words
    with at most abbreviations of one or two letters beside them (``UF_ROBOT``; ``a1`` and
    ``g1`` carry a digit: models' names)."""
    if _CAD_EXPORT_NAME.search(name):
        return True
    words = [w.lower() for w in re.split(r"[^A-Za-z0-9]+", name) if w]
    generic = [w for w in words if w in _GENERIC_WORDS]
    return bool(generic) and all(
        w in _GENERIC_WORDS or (len(w) <= 2 and w.isalpha()) for w in words
    )


def default_uid(robot_name: str | None, path: Path) -> str:
    """The robot's name as a valid uid (the file's name when the description has no name, or
    one that names no robot), without the generic words that trail it (ROS's
    ``go2_description``, ``husky_robot``)."""
    raw = robot_name or ""
    if not raw or names_no_robot(raw):
        raw = path.name.split(".")[0]
    raw = _GENERIC_SUFFIX.sub("", raw) or raw
    uid = re.sub(r"[^A-Za-z0-9_.\-]+", "_", raw).lstrip("_.-")[:64].rstrip("_") or "robot"
    if uid in registered_uids():
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


def scaffold(
    analysis: RobotAnalysis,
    spec_path: Path,
    rest: RestPose,
    uid: str | None = None,
    absolute_paths: bool = False,
    gains: Mapping[str, JointGains] | None = None,
    refined: bool = False,
    iterations: int | None = None,
) -> SpecDoc:
    """The spec; ``absolute_paths`` names the description by its absolute path (the draft
    :mod:`.rest_pose` loads from a temporary folder). ``gains`` by joint: the drives (default:
    :func:`.joint_gains.joint_gains` at the rest pose); ``refined``: they were measured in
    ManiSkill and changed where they missed (the comment says so); ``iterations``: the solver
    position iterations the loops were measured to need (:mod:`.refinement`, step 4)."""
    source = analysis.source
    groups = analysis.groups
    floating = analysis.body.floating
    uid = uid or default_uid(source.robot_name, source.path)
    notes: dict[KeyPath, str] = {}
    data: dict[str, Any] = {"robospec": 1, "uid": uid}

    data["description"] = _description_section(
        _with_cut_linkage_mend(source, rest), spec_path, absolute_paths, notes
    )
    if floating:
        data["loader"] = {"fix_root_link": False}
        notes[("loader", "fix_root_link")] = analysis.body.why_floating
    if source.mobile_base is not None:
        data["mobile_base"] = dict(source.mobile_base)
        if rest.root_height:  # ManiSkill's scenes load it at the origin: the base rides up
            data["mobile_base"] = {"height": rest.root_height, **source.mobile_base}
        notes[("mobile_base",)] = (
            "driven directly: x and y slides and a z hinge above the base link (pd_base_vel)"
        )

    data["groups"] = {name: list(joints) for name, joints in groups.groups.items()}
    notes[("groups",)] = "guessed from joint names and the kinematic tree: check them"

    _start(analysis, rest, data, notes)
    entries = _never_collide(analysis, rest)
    if entries:
        # (the header says why, entry by entry)
        data["never_collide"] = [list(links) for links, _ in entries]

    if analysis.loops:
        data["loops"] = {
            loop.name: {
                "links": list(loop.links),
                "at": [[_tidy(v) for v in point] for point in loop.at],
                **({"weld": True} if loop.weld else {}),
            }
            for loop in analysis.loops
        }
        notes[("loops",)] = "closed by a drive after loading; their other joints follow"
    if iterations is not None:
        data["simulation"] = {"solver_position_iterations": iterations}
        notes[("simulation",)] = (
            "measured: the loops stay closed under check's random actions with this many "
            "(ManiSkill's scenes solve 15); gym.make(..., sim_config=sim_config_for(uid))"
        )

    if gains is None:
        gains = joint_gains(analysis, rest.qpos, unbalanced(analysis))
    controllers, modes = controllers_and_modes(analysis, grip_gains(analysis, gains), rest.qpos)
    if controllers:  # (a base with nothing else to drive: the mobile_base section's mode)
        data["controllers"] = controllers
        notes[("controllers",)] = _gains_note(analysis, refined)
        data["control_modes"] = modes
        notes[("control_modes",)] = "the first is the default"
    members = task_members(analysis, rest.qpos)
    if members:
        data.update(members)
        notes[(next(iter(members)),)] = _members_note(members)
    return SpecDoc(data, _header(analysis, rest, entries, gains), notes)


def _with_cut_linkage_mend(source: DescriptionFile, rest: RestPose) -> DescriptionFile:
    """``source`` with the ``mimic: controller`` mend where the probe found a closed linkage the
    URDF cuts open (exemptions.pinned_pairs): PhysX's couplings of its ``<mimic>`` joints
    (fixed tendons, which ManiSkill builds for a follower beside its leader or below its
    leader's link) and the mimic controller's drives on the same joints jammed the xArm
    gripper, closing in the air: one side stayed open and the arm was flung about; the
    controller alone closes it."""
    pinned = ADJACENT_WHY["pinned"]
    if source.kind == "mjcf" or "mimic" in source.mends or pinned not in rest.why.values():
        return source
    if not any(joint.mimic for joint in source.description.joints):
        return source
    return dataclasses.replace(source, mends={**source.mends, "mimic": "controller"})


def _description_section(
    source: DescriptionFile, spec_path: Path, absolute_paths: bool, notes: dict[KeyPath, str]
) -> dict[str, Any]:
    """The spec's ``description``: the file (relative to the spec), its loader and mends."""
    key = "urdf" if source.kind == "urdf" else source.kind
    where = str(source.path.resolve()) if absolute_paths else None
    section: dict[str, Any] = {key: where or description_reference(source, spec_path.parent)}
    notes[("description",)] = "relative paths are relative to this file"
    if source.loader is not None:
        section["loader"] = source.loader
        notes[("description", "loader")] = source.why
    if source.mends:
        from robospec.derive import mend_class

        section["mend"] = dict(source.mends)
        notes[("description", "mend")] = (
            "robospec mends a copy of the description (never the file): see docs/mends.md"
        )
        for name in source.mends:
            mend = mend_class(name)
            if mend is not None:
                notes[("description", "mend", name)] = mend.WHY
    return section


def _start(
    analysis: RobotAnalysis, rest: RestPose, data: dict[str, Any], notes: dict[KeyPath, str]
) -> None:
    """The keyframes, and the one every episode starts at (``ready`` where new found one: the
    fingers pointing down in front of the arm; else ``rest``)."""
    data["keyframes"], notes[("keyframes",)] = _keyframes(analysis, rest, notes)
    start = "rest"
    ready = rest.ready
    if not rest.ready_checked:  # no probe in ManiSkill: from the kinematics alone
        fingers = gripper_fingers(analysis, rest.qpos)
        ready = ready_pose(analysis, rest.qpos, fingers) if fingers is not None else None
    if ready is not None:
        data["keyframes"]["ready"] = _ready_keyframe(analysis, rest, ready)
        notes[("keyframes", "ready")] = READY_CHECKED if rest.ready_checked else READY_NOTE
        start = "ready"
    data["reset"] = {"keyframe": start}
    notes[("reset",)] = (
        f"every episode starts at {start} (ManiSkill's tasks reset only the robots they know)"
    )
    if ready is None and rest.ready_refused:
        notes[("reset",)] += (
            "; no ready pose (fingers pointing down in front of the arm): in the first found, "
            + rest.ready_refused
        )


# why an MJCF's collision filters make a never_collide entry (the header says it for each)
FILTERED_WHY = "kept apart by the MJCF (contype and conaffinity, <contact><exclude>)"


# the comment on the ready keyframe (.ready_pose)
READY_NOTE = (
    "ready: fingers pointing down in front of the arm, where ManiSkill's solutions start "
    "(robospec solve); found by inverse kinematics, not contact-checked"
)
READY_CHECKED = (
    "ready: fingers pointing down in front of the arm, where ManiSkill's solutions start "
    "(robospec solve); no two links touch, none below the ground (checked in ManiSkill)"
)


def _ready_keyframe(analysis: RobotAnalysis, rest: RestPose, qpos: dict[str, float]) -> Any:
    """The ready keyframe as the rest one is written: by group, with the rest's root pose."""
    names = tuple(analysis.description.active_joint_names)
    partition = [(name, tuple(joints)) for name, joints in analysis.groups.groups.items()]
    values = [_tidy(qpos.get(name, rest.qpos[name])) for name in names]
    frame: dict[str, Any] = {"qpos": split_by_group(values, names, partition)}
    standing = standing_pose(analysis, rest)
    if standing is not None:
        frame["pose"] = _pose(standing)
    return frame


def _never_collide(analysis: RobotAnalysis, rest: RestPose) -> list[tuple[tuple[str, ...], str]]:
    """The scaffold's never_collide entries, each with why it is there: the links an MJCF's
    collision filters keep apart, then the pairs the rest-pose search declared."""
    filtered = filtered_cliques(analysis.source.description)
    kept_apart = {pair for links in filtered for pair in clique_pairs(links)}
    entries = [(tuple(links), FILTERED_WHY) for links in filtered]
    entries += [
        (pair, rest.reason(pair))
        for pair in rest.never_collide
        if tuple(sorted(pair)) not in kept_apart
    ]
    return entries


def _members_note(members: dict[str, Any]) -> str:
    """The comment on what ManiSkill's tasks call: where each part of it came from."""
    named = isinstance(members.get("tcp"), str)
    if "grasping" not in members:
        return "what ManiSkill's tasks call (agent.tcp): the link named as a tcp, check it"
    tcp = "tcp: the link named so; " if named else ""
    return (
        "what ManiSkill's tasks call (PickCube-v1: tcp_pose, is_grasping, is_static): "
        f"{tcp}guessed from the gripper, check them"
    )


def _gains_note(analysis: RobotAnalysis, refined: bool) -> str:
    """Where the controllers' gains come from (the comment above them)."""
    source = "the MJCF's actuators where it has them, else " if analysis.drives else ""
    text = (
        f"gains: {source}{NATURAL_FREQUENCY:g} rad/s, damping ratio {DAMPING_RATIO:g} "
        "about each joint's inertia at rest; force limits: its ratings"
    )
    return text + ("; then tuned in ManiSkill" if refined else "")


def _keyframes(
    analysis: RobotAnalysis, rest: RestPose, notes: dict[KeyPath, str]
) -> tuple[dict[str, Any], str]:
    """``rest`` and the file's own keyframes (inside the joints' limits: a value past one is
    clamped, and ``notes`` say so), and what the comment on them says."""
    description = analysis.description
    names = tuple(description.active_joint_names)
    partition = [(name, tuple(joints)) for name, joints in analysis.groups.groups.items()]

    def by_group(qpos: dict[str, float]) -> dict[str, Any]:
        values = [_tidy(qpos.get(name, rest.qpos[name])) for name in names]
        split = split_by_group(values, names, partition)
        assert split is not None  # one value per active joint, by construction
        return split

    keyframes: dict[str, Any] = {"rest": {"qpos": by_group(rest.qpos)}}
    standing = standing_pose(analysis, rest)
    if standing is not None:
        keyframes["rest"]["pose"] = _pose(standing)
    for key in description.keyframes:
        name = key.name if _NAME.match(key.name) else re.sub(r"[^A-Za-z0-9_.\-]", "_", key.name)
        while name in keyframes:
            name += "_file"
        fitted = fit_to_limits(description, dict(key.qpos))
        frame: dict[str, Any] = {}
        if analysis.body.floating and key.root_pose is not None:
            frame["pose"] = _pose(key.root_pose)
        frame["qpos"] = by_group(fitted.qpos)
        keyframes[name] = frame
        moved = fitted.note()
        if moved is not None:
            notes[("keyframes", name)] = moved
    if not rest.checked:
        note = "rest: 0 where the limits allow, else mid-range (not contact-checked)"
    elif any((a, b) not in rest.never_collide for a, b, _ in rest.touching):
        note = "rest: the least self-contact found (see the header)"
    else:
        note = "rest: no two links touch (checked in ManiSkill)"
    if description.keyframes:
        note += "; then the file's own keyframes"
    return keyframes, note


def standing_pose(analysis: RobotAnalysis, rest: RestPose) -> Pose | None:
    """The rest keyframe's pose for a floating robot whose standing height was measured, or a
    fixed one that reaches below the ground at the origin: the root link that high, upright —
    written as a keyframe's pose means it (for an MJCF robot the root body's, which hangs below
    that link: robospec.resolve.root_pose)."""
    if rest.root_height is None or analysis.source.mobile_base is not None:
        return None  # (a planar base rides at its height: mobile_base.height)
    return root_body_pose(analysis.description, ((0.0, 0.0, rest.root_height), rest.upright))


def _pose(pose: Pose) -> dict[str, Any]:
    p, q = pose
    out: dict[str, Any] = {"p": [_tidy(v) for v in p]}
    if any(abs(a - b) > 1e-9 for a, b in zip(q, IDENTITY, strict=True)):
        out["q"] = [_tidy(v) for v in q]
    return out


def _tidy(value: float) -> float:
    return float(round(value, 6)) + 0.0  # +0.0: never write -0.0


def _gravity_bound(analysis: RobotAnalysis, gains: Mapping[str, JointGains]) -> str | None:
    """The joints whose rating gravity nearly takes at rest, said where the spec starts: held
    at its rating such a joint cannot lift its own link far, whatever its gains (robospec
    check's step says so at the rating: RS534)."""
    from robospec.physics.rating import GRAVITY_SHARE

    found = []
    for name, drive in gains.items():
        if drive.rating is None or drive.load < GRAVITY_SHARE * drive.rating.value:
            continue
        joint = analysis.description.joint(name)
        unit = "N" if joint is not None and joint.type == "prismatic" else "N m"
        found.append(
            f"{name} (rated {drive.rating.value:g} {unit} by {drive.rating.what}, "
            f"{drive.load:.3g} {unit} of gravity at rest)"
        )
    if not found:
        return None
    return (
        "Ratings gravity nearly takes: "
        + ", ".join(found)
        + ". Held at its rating such a joint cannot lift its own link far, whatever its "
        "gains: a property of the robot as rated (robospec check warns RS534 where its step "
        "meets the rating). If the motor gives more, correct the rating."
    )


def _header(
    analysis: RobotAnalysis,
    rest: RestPose,
    never_collide: list[tuple[tuple[str, ...], str]],
    gains: Mapping[str, JointGains] | None = None,
) -> tuple[str, ...]:
    source = analysis.source
    lines = [
        f"robospec spec scaffolded by `robospec new` from {source.path.name}.",
        "Check the groups, gains and keyframes, then: robospec validate <this file>",
    ]
    paragraphs = [*_body_paragraphs(analysis), *_base_paragraphs(analysis)]
    paragraphs += _loop_paragraphs(analysis)
    carried = _gravity_bound(analysis, gains or {})
    if carried:
        paragraphs.append(carried)
    paragraphs.append(_rest_paragraph(analysis, rest))
    for paragraph in paragraphs:
        lines.append("")
        lines.extend(textwrap.wrap(paragraph, HEADER_WIDTH, break_on_hyphens=False))
    if never_collide:
        lines += ["", "never_collide: links that do not collide with each other, and why:"]
        for links, why in never_collide:
            lines += textwrap.wrap(
                f"{' + '.join(links)}: {why}",
                HEADER_WIDTH,
                initial_indent="  ",
                subsequent_indent="    ",
                break_on_hyphens=False,
            )
    return tuple(lines)


def _body_paragraphs(analysis: RobotAnalysis) -> list[str]:
    """The header's paragraphs on the robot's body: a floating or welded root, joints that
    cannot move, passive joints."""
    body = analysis.body
    paragraphs: list[str] = []
    if body.floating:
        paragraphs.append(
            f"Floating base: {body.why_floating}. Its root is free (fix_root_link: false) and "
            "every mode has balance_passive_force: false, or ManiSkill would cancel gravity "
            "and hold it up in mid-air."
        )
    elif body.welded:
        paragraphs.append(
            "Its root body has no free joint, so ManiSkill's MJCF loader welds it in place "
            "whatever the legs or wheels do. To let it stand and move, add <freejoint/> to the "
            "root body and run robospec new again."
        )
    immobile = [
        f"{joint} ({immobile_reason(found)})"
        for name, kind in analysis.groups.kinds.items()
        if kind == "immobile"
        for joint in analysis.groups.groups[name]
        if (found := analysis.description.joint(joint)) is not None
    ]
    if immobile:
        paragraphs.append(
            "Joints that cannot move are left to a passive controller (a drive could only "
            "push them against their limits): " + ", ".join(immobile) + "."
        )
    if not body.floating and analysis.has_passive:
        paragraphs.append(
            "Joints no MJCF actuator drives are passive; every mode has balance_passive_force: "
            "false, or ManiSkill would hold them up against gravity."
        )
    return paragraphs


def _base_paragraphs(analysis: RobotAnalysis) -> list[str]:
    """The header's paragraphs on a mobile base: the one written, or how to write one."""
    source, body = analysis.source, analysis.body
    paragraphs: list[str] = []
    if source.mobile_base is not None:
        wheels = source.mobile_base.get("wheels")
        floor = (
            f" {', '.join(wheels)} {'leave' if len(wheels) > 1 else 'leaves'} the floor's "
            "collisions (group 2, bit 30, which "
            "ManiSkill's scenes set on the ground)"
            + (" and their joints are welded" if "wheel_joints" in source.mobile_base else "")
            + (
                ": wheels rolling on a floor simulate slowly and transfer badly."
                if "wheel_joints" in source.mobile_base
                else ": the base slides over it instead of dragging on it."
            )
            if wheels
            else ""
        )
        paragraphs.append(
            f"Mobile base: {source.mobile_base_why}. As ManiSkill's guide builds a mobile base, "
            "mobile_base adds to a copy of the description a slide along x, a slide along y "
            "and a hinge about z above the base link, and drives them with a pd_base_vel "
            "controller (base) in every mode: forward and sideways speed, turning speed." + floor
        )
    elif body.wheels and body.planar_base is None:
        paragraphs.append(
            "Mobile base: ManiSkill's base controllers (pd_base_vel, pd_base_forward_vel) move "
            "a base through three joints at its root that slide along x and y and turn about z "
            "(ManiSkill's fetch.urdf: root_x_axis_joint, root_y_axis_joint, "
            "root_z_rotation_joint). This description has none, so its wheels are driven by "
            "joint velocity (group wheels). To drive the base directly, write a mobile_base "
            "section (docs/reference.md)."
        )
    if body.planar_base is not None and source.mobile_base is None:
        paragraphs.append(
            "Mobile base: the base moves through its planar joints ("
            + ", ".join(body.planar_base)
            + "), driven by a base controller."
        )
    return paragraphs


def _loop_paragraphs(analysis: RobotAnalysis) -> list[str]:
    """The header's paragraph on closed loops, where the description has any."""
    paragraphs: list[str] = []
    if analysis.loops:
        closed = "; ".join(
            f"{loop.name}: {loop.links[0]} meets {loop.links[1]} ({loop.source})"
            for loop in analysis.loops
        )
        paragraphs.append(
            f"Closed loops ({closed}): a PhysX articulation is a tree, so each loop is closed "
            "after loading by a drive between the two links where they meet (loops:), as "
            "ManiSkill's Robotiq agents close their four-bars. The loops' drivers make the "
            "gripper controller; their other joints are passive (group linkage): the linkage "
            "moves them."
        )
    return paragraphs


def _rest_paragraph(analysis: RobotAnalysis, rest: RestPose) -> str:
    if not rest.checked:
        text = (
            f"rest keyframe: not contact-checked ({rest.unchecked_because}): 0 where the limits "
            "allow, else mid-range. robospec check will say whether links touch."
        )
        if analysis.body.floating:
            text += " Its standing height was not measured: set keyframes.rest.pose.p."
        return text
    left = [t for t in rest.touching if (t[0], t[1]) not in rest.never_collide]
    if left:
        pairs = ", ".join(f"{a} + {b} ({d * 1000:.1f} mm)" for a, b, d in left)
        text = (
            f"rest keyframe: after {rest.tried} poses these links still touch: {pairs}. Move "
            "the keyframe apart, or declare the contact with never_collide if it is meant."
        )
    else:
        text = (
            f"rest keyframe: no two links touch (robospec check's test, in ManiSkill; "
            f"{rest.tried} pose(s) tried)."
        )
    standing = standing_pose(analysis, rest)
    if standing is not None and analysis.body.floating:
        text += (
            f" Its pose stands the robot {standing[0][2]:.3f} m up: there its lowest collision "
            "point touches the ground."
        )
        if rest.upright != IDENTITY:
            text += (
                " Its description is written with another axis than z up (its feet lie "
                "sideways of its root frame): the pose's q turns it upright in ManiSkill's "
                "z-up world."
            )
    elif analysis.source.mobile_base is not None and rest.root_height:
        text += (
            f" The base rides {rest.root_height:.3f} m up (mobile_base.height): at the "
            "origin, where ManiSkill's scenes load it, its links reach into the ground."
        )
    elif standing is not None:
        text += (
            f" Its pose mounts the robot {rest.root_height:.3f} m up: at the origin, where "
            "ManiSkill's scenes load it, its links reach into the ground."
        )
    return text
