"""Which link pairs of a robot never collide: the MoveIt Setup Assistant's sampling method.

The robot is loaded into a bare SAPIEN scene (no renderer, gravity off, every self-collision
enabled) and put in many configurations: the keyframes given, then random ones drawn uniformly
within the joint limits. At each, PhysX computes contacts and every pair of the robot's own links
touching (a contact point with separation <= 0) is counted. Then, as MoveIt classifies them:

- ``adjacent``: parent and child in the articulation, which PhysX never collides;
- ``always``: touching in every sample (e.g. two links whose meshes overlap at the joint);
- ``never``: touching in no sample;
- ``sometimes``: the rest, which must keep colliding.

Mimic joints follow their leaders in every sample, as in MoveIt's random states.

``never`` is statistical: a pair that touches only in a rare corner of the joint space can be
missed. Measured against 3000 fresh samples: after 1000 samples the Panda has one such pair
(link2/link6, in 0.13 % of poses; MoveIt's own panda SRDF calls it "Never" too), Fetch seven,
a G1 humanoid about a hundred; after 10,000 samples (MoveIt's default) none, one and six. Many
links want many samples. MoveIt calls a pair "always" from 95 % of samples on; here it takes
every sample, so a pair that can come apart keeps colliding. MoveIt also disables the pairs
touching in the all-zero pose ("Default"); here that pose is only a keyframe if given.

``never ∪ always`` become ``never_collide`` entries (:func:`never_collide_pairs`), packed into
group-2 bits by :func:`robospec.resolve.collision_packing.pack`; when bits run short that packing
also disables pairs in ``sometimes`` (its ``side_effects``: RS321).

SAPIEN and numpy are imported inside the functions: importing this module stays cheap.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Collection, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from itertools import combinations
from typing import TYPE_CHECKING, Any

from robospec.maniskill.render_fallback import strip_urdf_visuals
from robospec.resolve.collision_packing import Pair, pair

if TYPE_CHECKING:
    import numpy as np
    import sapien
    from sapien.physx import PhysxArticulation

# Long enough for PhysX to run its collision pass, short enough that the contact impulses it
# then applies move nothing measurably before the next sample resets the pose.
CONTACT_TIMESTEP = 1e-6


@dataclass(frozen=True)
class CollisionMatrix:
    """Every pair of links with collision shapes (sorted names, a < b), in exactly one set."""

    adjacent: frozenset[Pair]  # joined by a joint (PhysX never collides them)
    always: frozenset[Pair]  # in contact in every sample
    never: frozenset[Pair]  # in contact in no sample (and not adjacent)
    sometimes: frozenset[Pair]  # the rest: must keep colliding
    samples: int  # configurations tried, keyframes included


@dataclass(frozen=True)
class Mimic:
    """A URDF ``<mimic>``: ``joint`` = ``multiplier`` * ``leader`` + ``offset``."""

    joint: str
    leader: str
    multiplier: float
    offset: float


@dataclass(frozen=True)
class ContactScene:
    """A bare SAPIEN scene holding one robot, ready for :func:`count_contacts`."""

    scene: sapien.Scene
    robot: PhysxArticulation
    mimics: tuple[Mimic, ...]


def sample_collision_matrix(
    urdf_path: str,
    *,
    samples: int = 1000,
    seed: int = 0,
    keyframes: Sequence[Mapping[str, float]] = (),
    fix_root_link: bool = True,
) -> CollisionMatrix:
    """Classify the link pairs of the URDF at ``urdf_path`` by sampling: every keyframe (joint
    name -> position; joints it leaves out at 0, clipped into their limits), then ``samples``
    random configurations from ``numpy.random.default_rng(seed)``. Deterministic for a seed."""
    if samples < 0:
        raise ValueError(f"samples must be >= 0, not {samples}")
    if samples == 0 and not keyframes:
        raise ValueError("nothing to sample: give samples > 0 or at least one keyframe")
    loaded = load_for_contacts(urdf_path, fix_root_link=fix_root_link)
    names, lower, upper = joint_ranges(loaded.robot)
    rows = configurations(names, lower, upper, loaded.mimics, keyframes, samples, seed)
    shaped = [link for link in loaded.robot.links if link.collision_shapes]
    return classify(
        universe={pair(a.name, b.name) for a, b in combinations(shaped, 2)},
        adjacent=adjacent_pairs(shaped),
        counts=count_contacts(loaded, rows),
        total=len(rows),
    )


# -- loading ------------------------------------------------------------------------------------


def load_for_contacts(urdf_path: str, *, fix_root_link: bool = True) -> ContactScene:
    """The robot alone in a bare SAPIEN scene, every self-collision enabled and gravity off."""
    import sapien
    from sapien.wrapper.urdf_loader import URDFLoader

    class CollisionOnlyLoader(URDFLoader):
        # Visuals are dropped: without a rendering device SAPIEN fails on <material> tags and
        # primitive visuals, and contacts need only the collision shapes.
        def _parse_urdf(self, urdf_string: str) -> Any:
            return super()._parse_urdf(strip_urdf_visuals(urdf_string))

    # physics only: a default Scene() also makes a render system, which needs a device
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(CONTACT_TIMESTEP)
    loader = CollisionOnlyLoader()
    loader.set_scene(scene)
    loader.fix_root_link = fix_root_link
    # srdf_file="" is no file: SAPIEN would otherwise read the SRDF beside the URDF and disable
    # its pairs, which are what this method must find out for itself. Through the builder, not
    # load(): load() also mounts the URDF's cameras, which need a render system.
    builder = loader.load_file_as_articulation_builder(urdf_path, srdf_file="")
    # no PhysX mimic constraints (they go NaN on the CPU): configurations() applies the mimics
    robot = builder.build(build_mimic_joints=False)
    # contacts are found from the poses each sample sets, before the solver runs; what the
    # solver then does is never read, so it does the least it can (a quarter of the time)
    robot.set_solver_position_iterations(1)
    robot.set_solver_velocity_iterations(0)
    for link in robot.links:
        link.disable_gravity = True
        for shape in link.collision_shapes:
            # group 2 bits disable pairs (SRDF, ManiSkill's disable_self_collisions): none here
            groups = shape.get_collision_groups()
            shape.set_collision_groups([groups[0], groups[1], 0, groups[3]])
    mimics = tuple(
        Mimic(record.joint, record.mimic, float(record.multiplier), float(record.offset))
        for record in builder.mimic_joint_records
    )
    return ContactScene(scene, robot, mimics)


def joint_ranges(robot: PhysxArticulation) -> tuple[list[str], np.ndarray, np.ndarray]:
    """The active joints' names and limits, one value per degree of freedom; an unbounded
    (continuous) joint ranges over [-pi, pi]."""
    import numpy as np

    names, lower, upper = [], [], []
    for joint in robot.active_joints:
        for low, high in joint.limit:
            names.append(joint.name)
            lower.append(low if math.isfinite(low) else -math.pi)
            upper.append(high if math.isfinite(high) else math.pi)
    return names, np.array(lower), np.array(upper)


def adjacent_pairs(links: Iterable[Any]) -> frozenset[Pair]:
    """Parent-child pairs among ``links`` (SAPIEN link components)."""
    present = {link.name for link in links}
    return frozenset(
        pair(link.name, link.parent.name)
        for link in links
        if link.parent is not None and link.parent.name in present
    )


# -- sampling -----------------------------------------------------------------------------------


def configurations(
    names: Sequence[str],
    lower: np.ndarray,
    upper: np.ndarray,
    mimics: Sequence[Mimic],
    keyframes: Sequence[Mapping[str, float]],
    samples: int,
    seed: int,
) -> np.ndarray:
    """The keyframes, then ``samples`` uniform draws within the limits: one row each. A mimic
    joint follows its leader (unless a keyframe sets it), as the real mechanism does: drawn on
    its own it would reach poses the robot cannot, and call pairs "sometimes" that never touch."""
    import numpy as np

    index = {name: i for i, name in enumerate(names)}
    default = np.clip(np.zeros(len(names)), lower, upper)
    rows = []
    for keyframe in keyframes:
        unknown = sorted(set(keyframe) - set(index))
        if unknown:
            raise ValueError(f"keyframe names joints the robot has not: {', '.join(unknown)}")
        row = default.copy()
        for name, value in keyframe.items():
            row[index[name]] = value
        _follow(row[None, :], index, [m for m in mimics if m.joint not in keyframe])
        rows.append(row)
    drawn = np.random.default_rng(seed).uniform(lower, upper, size=(samples, len(names)))
    _follow(drawn, index, mimics)
    return np.concatenate([np.array(rows).reshape(-1, len(names)), drawn])


def _follow(rows: np.ndarray, index: Mapping[str, int], mimics: Sequence[Mimic]) -> None:
    """Set each mimic joint's column from its leader's, in place. One pass per mimic: a chain
    (a mimic of a mimic) then settles whatever order the URDF lists them in."""
    present = [m for m in mimics if m.joint in index and m.leader in index]
    for _ in present:
        for mimic in present:
            leader = rows[:, index[mimic.leader]]
            rows[:, index[mimic.joint]] = mimic.multiplier * leader + mimic.offset


def posed_contacts(loaded: ContactScene, rows: np.ndarray) -> Iterator[list[Any]]:
    """The robot at each configuration of ``rows`` in turn, still and its root where it was
    loaded: the contacts PhysX finds there."""
    import numpy as np

    scene, robot = loaded.scene, loaded.robot
    still = np.zeros(rows.shape[1])
    origin = robot.get_root_pose()
    for qpos in rows:
        robot.set_qpos(qpos)
        robot.set_qvel(still)
        # a floating root keeps the velocity each sample's contact impulses give it: over
        # thousands of samples it reaches hundreds of m/s and the robot goes to NaN, after which
        # no pair touches (and pairs would be called "never" on the samples before it)
        robot.set_root_pose(origin)
        robot.set_root_linear_velocity([0.0, 0.0, 0.0])
        robot.set_root_angular_velocity([0.0, 0.0, 0.0])
        scene.step()  # PhysX computes contacts only in a step
        yield scene.get_contacts()


def count_contacts(loaded: ContactScene, rows: np.ndarray) -> Counter[Pair]:
    """In how many of the configurations ``rows`` each pair of the robot's links touches."""
    # id() of the link components as contacts name them; the list keeps those Python objects
    # alive, so pybind11 hands back these same objects in every contact
    links = list(loaded.robot.links)
    names = {id(link): link.name for link in links}
    counts: Counter[Pair] = Counter()
    for contacts in posed_contacts(loaded, rows):
        counts.update(touching_pairs(contacts, names))
    return counts


def touching_pairs(contacts: Iterable[Any], names: Mapping[int, str]) -> set[Pair]:
    """Pairs of distinct named bodies in contact. ``names`` maps ``id()`` of a body component to
    its link name; bodies it does not name (other objects) are skipped, and so are contacts that
    only come within PhysX's contact offset (every point at a positive separation). Runs once
    per sampled configuration, ten thousand times a robot: no more work than the pairs need."""
    touching: set[Pair] = set()
    for contact in contacts:
        a, b = (names.get(id(body)) for body in contact.bodies)
        if a is None or b is None or a == b:
            continue
        if any(point.separation <= 0 for point in contact.points):
            touching.add(pair(a, b))
    return touching


def classify(
    universe: Collection[Pair], adjacent: Collection[Pair], counts: Mapping[Pair, int], total: int
) -> CollisionMatrix:
    """MoveIt's rules: adjacent first, then always (every sample), never (none), sometimes."""
    rest = set(universe) - set(adjacent)
    always = {p for p in rest if counts.get(p, 0) >= total}
    never = {p for p in rest if counts.get(p, 0) == 0}
    return CollisionMatrix(
        adjacent=frozenset(adjacent),
        always=frozenset(always),
        never=frozenset(never),
        sometimes=frozenset(rest - always - never),
        samples=total,
    )


# -- into the spec ------------------------------------------------------------------------------


def never_collide_pairs(matrix: CollisionMatrix) -> list[list[str]]:
    """``never ∪ always`` as the spec's ``never_collide`` entries: ``[link_a, link_b]`` pairs,
    sorted. Adjacent pairs are left out: PhysX already ignores them."""
    return [list(p) for p in sorted(matrix.never | matrix.always)]
