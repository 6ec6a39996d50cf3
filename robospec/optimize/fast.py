"""``robospec optimize --profile fast``: what the profile adds to optimize, each a change to
how the robot simulates, for speed, and each measured.

- **Primitive collision shapes** (:mod:`robospec.optimize.shapes`, ``primitives``): a box,
  capsule or sphere where one lies within ``--max-error`` of the mesh.
- **A contact offset for the robot's own shapes** (:mod:`robospec.optimize.contacts`): the
  agent sets it on every collision shape after loading (the spec's
  ``simulation.contact_offset``). Measured over sampled configurations: the pairs of the
  robot's links making contacts at ManiSkill's 2 cm and at the profile's offset.
- **A recommended sim config** for the robot's category (``simulation.category``, from
  ``--category`` or the body: a robot with a free root walks, unless it rolls on wheels and
  has no legs): 15 solver position iterations
  for manipulation (ManiSkill's default, which its notes call the balance of speed and
  accuracy; stable grasps want 15 or more), 4 for locomotion (ManiSkill's quadruped and
  humanoid control tasks use 4). The built package exposes it as ``sim_config_for(uid)``.

Its speed, and what it costs in behaviour, are measured by benchmarks/optimize_throughput.py,
benchmarks/optimize_fidelity.py and benchmarks/optimize_gpu.py, not here.
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from robospec.description import RobotDescription
    from robospec.optimize.collision_matrix import CollisionMatrix
    from robospec.optimize.options import OptimizeOptions
    from robospec.pipeline import CompiledSpec
    from robospec.resolve.resolved import ResolvedRobot

# solver iterations (position, velocity) by category
ITERATIONS = {"manipulation": (15, 1), "locomotion": (4, 1)}
# configurations the contact count is taken over: the matrix's first ones
CONTACT_SAMPLES = 1000


def category_of(
    robot: ResolvedRobot, asked: str | None, description: RobotDescription | None = None
) -> str:
    """The category asked for, else by the body: a robot whose root is free stands or walks
    (locomotion), unless it rolls on wheels with no legs to stand on — a mobile manipulator
    such as TIAGo, whose base drives and whose arm grasps, wants manipulation's iterations, as
    ManiSkill's Fetch tasks keep its default 15 (``description``: the robot's
    :class:`~robospec.description.RobotDescription`, whose body
    :mod:`robospec.kinematics.morphology` reads)."""
    if asked is not None:
        return asked
    if robot.fix_root_link:
        return "manipulation"
    if description is not None:
        from robospec.kinematics.morphology import morphology

        body = morphology(description, None)
        if body.rolls and len(body.legs) < 2:
            return "manipulation"
    return "locomotion"


def fast_simulation(
    urdf_file: Path,
    staged_spec: Path,
    compiled: CompiledSpec,
    matrix: CollisionMatrix | None,
    options: OptimizeOptions,
) -> tuple[dict[str, Any], list[dict[str, Any]]]:
    """The spec's ``simulation`` section for the fast profile, and the contact counts it
    measured (at ManiSkill's offset, then at the profile's; none without a matrix)."""
    assert compiled.robot is not None  # compiled
    from robospec.optimize.contacts import LARGEST_OFFSET

    robot = compiled.robot
    category = category_of(robot, options.category, compiled.description)
    positions, velocities = ITERATIONS[category]
    offset = options.contact_offset
    counts: list[dict[str, Any]] = []
    if matrix is not None and not robot.disable_self_collisions:
        before, after = _measure(urdf_file, staged_spec, matrix, options, offset)
        offset = after.offset
        counts = [asdict(before), asdict(after)]
    if offset is None:
        offset = LARGEST_OFFSET
    simulation = {
        "profile": "fast",
        "category": category,
        "contact_offset": float(f"{offset:.6g}"),
        "solver_position_iterations": positions,
        "solver_velocity_iterations": velocities,
    }
    return simulation, counts


def _measure(
    urdf_file: Path,
    staged_spec: Path,
    matrix: CollisionMatrix,
    options: OptimizeOptions,
    offset: float | None,
) -> tuple[Any, Any]:
    """Contact counts at ManiSkill's offset and at the profile's (``offset``, or the one
    the first count calls for), over the matrix's first configurations."""
    from robospec.maniskill.scenes import CONTACT_OFFSET
    from robospec.optimize.collision_matrix import configurations, joint_ranges, load_for_contacts
    from robospec.optimize.contacts import count_contacts_at, disabled_pairs, profile_offset
    from robospec.pipeline import compile_spec

    packed = compile_spec(staged_spec)
    assert packed.robot is not None and packed.description is not None
    bits = [
        (rule.bit, rule.links)
        for rule in packed.robot.collision_rules
        if rule.group == 2 and rule.value == 1
    ]
    bits += list(packed.description.loader_collision_bits)
    loaded = load_for_contacts(str(urdf_file), fix_root_link=packed.robot.fix_root_link)
    links = [link.name for link in loaded.robot.links]
    skip = disabled_pairs(links, matrix.adjacent, bits)
    names, lower, upper = joint_ranges(loaded.robot)
    rows = configurations(
        names, lower, upper, loaded.mimics, (), min(options.samples, CONTACT_SAMPLES), options.seed
    )
    never = matrix.never
    before = count_contacts_at(loaded, rows, CONTACT_OFFSET, skip, never)
    chosen = offset if offset is not None else profile_offset(before.nearest_gap)
    after = count_contacts_at(loaded, rows, chosen, skip, never)
    return before, after
