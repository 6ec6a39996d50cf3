"""What each joint of a robot carries at a pose, from the description alone: its effective
inertia and the torque gravity puts on it, with the root held and, for a robot on legs,
standing on its feet. :mod:`.gains` turns these into a scaffold's first drive gains.

* **Masses.** URDF: each link's ``<inertial>`` as SAPIEN uses it (mass and inertia both given;
  otherwise PhysX computes them from the collision shapes at density 1000, estimated here from
  the primitive ones: boxes, cylinders, spheres). MJCF: from the geoms, as ManiSkill's loader
  does (it recomputes masses from geometry, density 1000 unless a geom says otherwise), else
  the body's ``<inertial>`` when its geoms are meshes.
* **Effective inertia** of a joint: the joint-space mass matrix's diagonal entry, what the
  joint's drive accelerates when every other joint is locked and the root held: the inertia of
  everything beyond the joint about its axis (revolute), or that mass (prismatic), plus the
  joint's armature (MJCF).
* **Gravity load, root held**: the torque (force) about the joint's axis of the weight of
  everything beyond it — what a drive holds on a test stand, or on a fixed robot whose modes
  do not cancel gravity.
* **Gravity load, standing**: a floating robot at its rest pose on its feet (the lowest link
  frame of each leg), the ground carrying its weight split between the feet so that it balances
  (the least-squares split with the centre of mass over them): each leg joint holds the weight
  beyond it and the ground's push on the foot beyond it.
* **Toppling stiffness, standing**: a leg joint with the foot fixed carries the rest of the
  robot as an inverted pendulum: turned by ``θ`` about axis ``a`` through pivot ``p``, the rest's
  centre of mass ``c`` sinks by ``θ²/2 · (r_z - (a·r) a_z)`` (``r = c - p``), so gravity's torque
  grows by ``m g (r_z - (a·r) a_z)`` per radian — shared between the legs as their feet share
  the weight.

The links' poses and the joints' axes come from the robot's forward kinematics
(:mod:`robospec.kinematics.forward`: yourdfpy, MuJoCo); the sums here are plain Python, and
approximate on purpose: these are a first guess that ``robospec new`` refines in ManiSkill
when it is installed.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from lxml import etree

from robospec.description.inertia import DENSITY  # PhysX's and MuJoCo's default
from robospec.description.numbers import finite_numbers
from robospec.description.urdf import parse_xml
from robospec.geometry import (
    IDENTITY_MATRIX,
    ZERO,
    Matrix,
    Quaternion,
    Vector,
    cross,
    dot,
    matrix_from_quaternion,
    quaternion_from_rpy,
    shifted,
    turned,
    z_towards,
)
from robospec.kinematics.mjcf_model import MjBody, MjcfModel

if TYPE_CHECKING:
    import numpy as np

    from robospec.kinematics.forward import KinematicModel


@dataclass(frozen=True)
class Frame:
    """Where a part (a geom, an inertial) sits in its link: ``x -> rotation @ x + translation``."""

    rotation: Matrix = IDENTITY_MATRIX
    translation: Vector = ZERO

    @staticmethod
    def of(q: Quaternion, p: Sequence[float]) -> Frame:
        return Frame(matrix_from_quaternion(q), (float(p[0]), float(p[1]), float(p[2])))


GRAVITY = 9.81  # m/s², along the world's -z (the root frame turned as its rest pose stands it)


@dataclass(frozen=True)
class Inertial:
    """A link's mass, its centre of mass and its inertia about it, in the link's frame."""

    mass: float
    com: Vector
    inertia: Matrix


@dataclass(frozen=True)
class JointLoad:
    """One joint at one pose: effective inertia (kg m², kg for a prismatic joint), the gravity
    torque (N m, or N) it holds with the root held, and standing on the feet (None: the robot
    does not stand)."""

    inertia: float
    held: float
    standing: float | None = None
    # N m/rad: standing, how much gravity's torque on the joint grows as it gives way — the rest
    # of the robot above it tipping over its feet like an inverted pendulum (this joint's
    # share, by the weight its feet carry). Its drive must be stiffer than this or the robot
    # topples whatever holds the pose: the dm_control humanoid's ankles, at the stiffness
    # their own feet's inertia asks for, let it fall on its face
    topple: float = 0.0

    @property
    def load(self) -> float:
        """The larger of the two gravity loads (magnitudes)."""
        return max(abs(self.held), abs(self.standing or 0.0))


# -- masses -------------------------------------------------------------------------------------


def _diagonal(x: float, y: float, z: float) -> Matrix:
    return ((x, 0.0, 0.0), (0.0, y, 0.0), (0.0, 0.0, z))


def combine(parts: Iterable[tuple[float, Frame, Matrix]]) -> Inertial | None:
    """One body of several parts: (mass, the part's frame in the body's with its centre of
    mass at the origin, its inertia in that frame). None when there is no mass."""
    items = [(m, frame, inertia) for m, frame, inertia in parts if m > 0]
    mass = sum(m for m, _, _ in items)
    if mass <= 0:
        return None
    com = tuple(sum(m * frame.translation[i] for m, frame, _ in items) / mass for i in range(3))
    total = [[0.0] * 3 for _ in range(3)]
    for m, frame, inertia in items:
        offset = tuple(frame.translation[i] - com[i] for i in range(3))
        about = shifted(turned(frame.rotation, inertia), m, offset)  # type: ignore[arg-type]
        for i in range(3):
            for j in range(3):
                total[i][j] += about[i][j]
    return Inertial(mass, com, tuple(tuple(row) for row in total))  # type: ignore[arg-type]


def box(half: Sequence[float], density: float) -> tuple[float, Matrix]:
    a, b, c = (abs(v) for v in half)
    m = density * 8 * a * b * c
    return m, _diagonal(m * (b * b + c * c) / 3, m * (a * a + c * c) / 3, m * (a * a + b * b) / 3)


def sphere(r: float, density: float) -> tuple[float, Matrix]:
    m = density * 4 / 3 * math.pi * r**3
    return m, _diagonal(*(0.4 * m * r * r,) * 3)


def ellipsoid(radii: Sequence[float], density: float) -> tuple[float, Matrix]:
    a, b, c = (abs(v) for v in radii)
    m = density * 4 / 3 * math.pi * a * b * c
    return m, _diagonal(m * (b * b + c * c) / 5, m * (a * a + c * c) / 5, m * (a * a + b * b) / 5)


def cylinder(r: float, half_length: float, density: float) -> tuple[float, Matrix]:
    """About its centre, its axis along z."""
    h = 2 * half_length
    m = density * math.pi * r * r * h
    side = m * (3 * r * r + h * h) / 12
    return m, _diagonal(side, side, m * r * r / 2)


def capsule(r: float, half_length: float, density: float) -> tuple[float, Matrix]:
    """A cylinder with two hemispherical caps, about its centre, its axis along z."""
    m_cyl, i_cyl = cylinder(r, half_length, density)
    m_ball = density * 4 / 3 * math.pi * r**3
    # each cap's centre of mass sits 3r/8 beyond the cylinder's end
    arm = half_length + 3 * r / 8
    side = i_cyl[0][0] + m_ball * (0.4 * r * r + arm * arm)
    return m_cyl + m_ball, _diagonal(side, side, i_cyl[2][2] + 0.4 * m_ball * r * r)


def urdf_inertials(text: bytes | str) -> dict[str, Inertial]:
    """Link name -> its inertial as SAPIEN loads the URDF (links without one are left out)."""
    root, _ = parse_xml(text, "")
    if root is None:
        return {}
    out: dict[str, Inertial] = {}
    for link in root.iterfind("link"):
        name = link.get("name", "")
        found = _urdf_inertial(link.find("inertial")) or _urdf_shapes(link)
        if found is not None:
            out[name] = found
    return out


def _origin(element: etree._Element | None) -> Frame:
    if element is None:
        return Frame()
    rpy = finite_numbers(element.get("rpy"), 3) or (0.0, 0.0, 0.0)
    xyz = finite_numbers(element.get("xyz"), 3) or (0.0, 0.0, 0.0)
    return Frame.of(quaternion_from_rpy(*rpy), xyz)


def _urdf_inertial(inertial: etree._Element | None) -> Inertial | None:
    """The ``<inertial>`` when SAPIEN uses it: a positive mass and a non-zero inertia."""
    if inertial is None:
        return None
    mass_element, inertia_element = inertial.find("mass"), inertial.find("inertia")
    if mass_element is None or inertia_element is None:
        return None
    mass = finite_numbers(mass_element.get("value"), 1)
    names = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    values = [finite_numbers(inertia_element.get(n, "0"), 1) for n in names]
    if mass is None or mass[0] <= 0 or any(v is None for v in values):
        return None
    xx, xy, xz, yy, yz, zz = (v[0] for v in values)  # type: ignore[index]
    if not any((xx, xy, xz, yy, yz, zz)):
        return None
    frame = _origin(inertial.find("origin"))
    inertia = turned(frame.rotation, ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz)))
    return Inertial(mass[0], frame.translation, inertia)


def _urdf_shapes(link: etree._Element) -> Inertial | None:
    """What PhysX computes for a link SAPIEN gives no inertial: its primitive collision shapes
    at density 1000 (meshes are left out: their volume needs the file)."""
    parts = []
    for collision in link.iterfind("collision"):
        geometry = collision.find("geometry")
        if geometry is None:
            continue
        frame = _origin(collision.find("origin"))
        shape = next((child for child in geometry if isinstance(child.tag, str)), None)
        if shape is None:
            continue
        if shape.tag == "box":
            size = finite_numbers(shape.get("size"), 3)
            if size:
                parts.append((*box([v / 2 for v in size], DENSITY), frame))
        elif shape.tag == "sphere":
            radius = finite_numbers(shape.get("radius"), 1)
            if radius:
                parts.append((*sphere(radius[0], DENSITY), frame))
        elif shape.tag == "cylinder":
            radius = finite_numbers(shape.get("radius"), 1)
            length = finite_numbers(shape.get("length"), 1)
            if radius and length:
                parts.append((*cylinder(radius[0], length[0] / 2, DENSITY), frame))
    return combine((m, frame, inertia) for m, inertia, frame in parts)


def mjcf_inertials(model: MjcfModel) -> dict[str, Inertial]:
    """Body name -> its inertial as ManiSkill's MJCF loader makes it: from the geoms."""
    out: dict[str, Inertial] = {}
    for body in model.walk():
        found = _mjcf_geoms(model, body) or _mjcf_inertial(model, body)
        if found is not None:
            out[body.name] = found
    return out


def _mjcf_geoms(model: MjcfModel, body: MjBody) -> Inertial | None:
    parts = []
    for attributes in body.geoms:
        shape = _mjcf_shape(model, attributes)
        if shape is not None:
            parts.append(shape)
    return combine(parts)


def _mjcf_shape(
    model: MjcfModel, attributes: Mapping[str, str]
) -> tuple[float, Frame, Matrix] | None:
    kind = attributes.get("type", "sphere")
    size = finite_numbers(attributes.get("size"), None) or ()
    given_mass = finite_numbers(attributes.get("mass"), 1)
    density = (finite_numbers(attributes.get("density"), 1) or (DENSITY,))[0]
    frame = Frame.of(model.rotation(dict(attributes)), _position(attributes.get("pos")))
    fromto = finite_numbers(attributes.get("fromto"), 6)
    half_length = size[1] if len(size) > 1 else 0.0
    if fromto is not None and kind in ("capsule", "cylinder", "box", "ellipsoid"):
        a, b = fromto[:3], fromto[3:]
        axis = tuple(b[i] - a[i] for i in range(3))
        half_length = math.sqrt(sum(c * c for c in axis)) / 2
        centre = tuple((a[i] + b[i]) / 2 for i in range(3))
        frame = Frame(_z_towards(axis), centre)  # type: ignore[arg-type]
    if not size:
        return None
    if kind == "sphere":
        mass, inertia = sphere(size[0], density)
    elif kind == "capsule":
        mass, inertia = capsule(size[0], half_length, density)
    elif kind == "cylinder":
        mass, inertia = cylinder(size[0], half_length, density)
    elif kind == "box" and len(size) >= 3:
        mass, inertia = box(size[:3], density)
    elif kind == "ellipsoid" and len(size) >= 3:
        mass, inertia = ellipsoid(size[:3], density)
    else:
        return None  # a mesh, a plane, a height field: nothing a box of numbers can say
    if given_mass is not None and mass > 0:
        scale = given_mass[0] / mass
        mass, inertia = given_mass[0], _scaled(inertia, scale)
    return mass, frame, inertia


def _scaled(inertia: Matrix, factor: float) -> Matrix:
    return tuple(tuple(v * factor for v in row) for row in inertia)  # type: ignore[return-value]


def _z_towards(axis: Sequence[float]) -> Matrix:
    """The shortest rotation taking (0, 0, 1) to ``axis`` (MuJoCo's ``fromto``)."""
    norm = math.sqrt(sum(c * c for c in axis))
    if norm < 1e-12:
        return IDENTITY_MATRIX
    return matrix_from_quaternion(z_towards((axis[0] / norm, axis[1] / norm, axis[2] / norm)))


def _position(text: str | None) -> Vector:
    values = finite_numbers(text, 3)
    return values if values is not None else ZERO  # type: ignore[return-value]


def _mjcf_inertial(model: MjcfModel, body: MjBody) -> Inertial | None:
    element = body.inertial
    if element is None:
        return None
    mass = finite_numbers(element.get("mass"), 1)
    if mass is None or mass[0] <= 0:
        return None
    diagonal = finite_numbers(element.get("diaginertia"), 3)
    full = finite_numbers(element.get("fullinertia"), 6)
    if diagonal is not None:
        inertia = _diagonal(*diagonal)
    elif full is not None:
        xx, yy, zz, xy, xz, yz = full
        inertia = ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz))
    else:
        return None
    rotation = matrix_from_quaternion(model.rotation(element))
    return Inertial(mass[0], _position(element.get("pos")), turned(rotation, inertia))


# -- loads ----------------------------------------------------------------------------------------


def joint_loads(
    model: KinematicModel,
    inertials: Mapping[str, Inertial],
    qpos: Mapping[str, float],
    armature: Mapping[str, float] | None = None,
    feet: Sequence[Sequence[str]] = (),
    upright: Matrix = IDENTITY_MATRIX,
) -> dict[str, JointLoad]:
    """Every moving joint of ``model`` at ``qpos``. ``feet``: for a robot that stands, the links
    of each foot (the ground pushes on the lowest frame of each); empty: it does not stand.
    ``upright``: how the root frame is turned in the world, gravity pulling along the world's
    -z (a description written y-up stands turned: ``RobotAnalysis.upright``)."""
    placed = model.at(qpos)
    poses = {link: _turned(upright, pose) for link, pose in placed.links.items()}
    children: dict[str, list[str]] = {}
    for joint in model.joints:
        children.setdefault(joint.parent, []).append(joint.child)
    world: dict[str, tuple[float, Vector, Matrix]] = {}
    for link, pose in poses.items():
        found = inertials.get(link)
        if found is not None:
            world[link] = (
                found.mass,
                _apply(pose.rotation, found.com, pose.translation),
                turned(pose.rotation, found.inertia),
            )
    support = _support(poses, world, feet)
    total_mass = sum(m for m, _, _ in world.values())
    total_moment = tuple(sum(m * c[i] for m, c, _ in world.values()) for i in range(3))
    armature = armature or {}
    out: dict[str, JointLoad] = {}
    for joint in model.joints:
        if joint.type not in ("revolute", "continuous", "prismatic"):
            continue
        placed_axis = placed.axes.get(joint.name)
        if placed_axis is None:
            continue
        axis = _apply(upright, tuple(placed_axis.direction.tolist()))
        pivot = _apply(upright, tuple(placed_axis.anchor.tolist()))
        beyond = _subtree(joint.child, children)
        inertia = armature.get(joint.name, 0.0)
        torque = 0.0
        for link in beyond:
            if link not in world:
                continue
            mass, com, about_com = world[link]
            arm = (com[0] - pivot[0], com[1] - pivot[1], com[2] - pivot[2])
            weight = (0.0, 0.0, -GRAVITY * mass)
            if joint.type == "prismatic":
                inertia += mass
                torque += dot(axis, weight)
            else:
                inertia += _quadratic(about_com, axis)
                inertia += mass * sum(c * c for c in cross(axis, arm))
                torque += dot(axis, cross(arm, weight))
        standing = None
        topple = 0.0
        if support:
            standing = torque
            carried = 0.0  # the weight on the feet beyond this joint
            for point, force in support:
                if point[1] not in beyond:
                    continue
                carried += force
                push = (0.0, 0.0, force)
                if joint.type == "prismatic":
                    standing += dot(axis, push)
                else:
                    arm = (point[0][0] - pivot[0], point[0][1] - pivot[1], point[0][2] - pivot[2])
                    standing += dot(axis, cross(arm, push))
            if carried > 0 and joint.type != "prismatic":
                topple = _topple(world, beyond, total_mass, total_moment, axis, pivot)
                topple *= carried / (GRAVITY * total_mass)
        out[joint.name] = JointLoad(inertia, torque, standing, topple)
    return out


def _topple(
    world: Mapping[str, tuple[float, Vector, Matrix]],
    beyond: set[str],
    total_mass: float,
    total_moment: Sequence[float],
    axis: Vector,
    pivot: Vector,
) -> float:
    """How fast gravity's torque about a revolute joint grows as it turns (N m/rad), the links
    ``beyond`` it (a foot) held on the ground and the rest of the robot tipping about it;
    0 where turning it raises the rest (it hangs below the axis) or the axis is vertical."""
    mass = total_mass - sum(world[link][0] for link in beyond if link in world)
    if mass <= 0:
        return 0.0
    moment = [
        total_moment[i] - sum(world[k][0] * world[k][1][i] for k in beyond if k in world)
        for i in range(3)
    ]
    arm = (moment[0] / mass - pivot[0], moment[1] / mass - pivot[1], moment[2] / mass - pivot[2])

    height = arm[2] - dot(axis, arm) * axis[2]  # the arm's part across the axis, upward
    return max(GRAVITY * mass * height, 0.0)


def _turned(upright: Matrix, pose: np.ndarray) -> Frame:
    """A link's pose (4x4, root frame) in the world, the root frame turned by ``upright``."""
    rows = pose[:3, :3].tolist()
    rotation = tuple(
        tuple(sum(upright[i][k] * rows[k][j] for k in range(3)) for j in range(3)) for i in range(3)
    )
    return Frame(rotation, _apply(upright, tuple(pose[:3, 3].tolist())))  # type: ignore[arg-type]


def _apply(r: Matrix, v: Sequence[float], shift: Sequence[float] = ZERO) -> Vector:
    """``r @ v + shift``."""
    return tuple(sum(r[i][k] * v[k] for k in range(3)) + shift[i] for i in range(3))  # type: ignore[return-value]


def _subtree(link: str, children: Mapping[str, list[str]]) -> set[str]:
    found = {link}
    queue = [link]
    while queue:
        for child in children.get(queue.pop(), []):
            if child not in found:
                found.add(child)
                queue.append(child)
    return found


def _quadratic(matrix: Matrix, v: Vector) -> float:
    return sum(v[i] * matrix[i][j] * v[j] for i in range(3) for j in range(3))


def _support(
    poses: Mapping[str, Frame],
    world: Mapping[str, tuple[float, Vector, Matrix]],
    feet: Sequence[Sequence[str]],
) -> list[tuple[tuple[Vector, str], float]]:
    """Each foot's contact point (the lowest frame of its links, and that link) and the
    upward force the ground gives it: the least-squares split of the robot's weight whose
    moments balance about the centre of mass (no foot pulls)."""
    points: list[tuple[Vector, str]] = []
    for foot in feet:
        frames = [(poses[link].translation, link) for link in foot if link in poses]
        if frames:
            points.append(min(frames, key=lambda item: item[0][2]))
    mass = sum(m for m, _, _ in world.values())
    if not points or mass <= 0:
        return []
    com = tuple(sum(m * c[i] for m, c, _ in world.values()) / mass for i in range(3))
    weight = GRAVITY * mass
    forces = _balanced_split([(p[0][0], p[0][1]) for p in points], (com[0], com[1]), weight)
    return list(zip(points, forces, strict=True))


def _balanced_split(
    points: Sequence[tuple[float, float]], centre: tuple[float, float], weight: float
) -> list[float]:
    """Forces ``f`` (>= 0) at ``points`` with ``sum f = weight`` and ``sum f p = weight *
    centre`` in the least-squares sense (the minimum-norm solution, with a little ridge where
    the points lie on a line, then negative forces dropped and the rest rescaled)."""
    n = len(points)
    rows = [[1.0] * n, [p[0] for p in points], [p[1] for p in points]]
    target = [weight, weight * centre[0], weight * centre[1]]
    gram = [[sum(a * b for a, b in zip(r, s, strict=True)) for s in rows] for r in rows]
    scale = max(abs(gram[i][i]) for i in range(3)) or 1.0
    for i in range(3):
        gram[i][i] += 1e-9 * scale
    solved = _solve3(gram, target)
    if solved is None:
        return [weight / n] * n
    forces = [max(sum(rows[k][i] * solved[k] for k in range(3)), 0.0) for i in range(n)]
    total = sum(forces)
    return [f * weight / total for f in forces] if total > 0 else [weight / n] * n


def _solve3(a: list[list[float]], b: list[float]) -> list[float] | None:
    """Gaussian elimination with partial pivoting on a 3x3 system."""
    m = [[*row, b[i]] for i, row in enumerate(a)]
    for col in range(3):
        pivot = max(range(col, 3), key=lambda r: abs(m[r][col]))
        if abs(m[pivot][col]) < 1e-300:
            return None
        m[col], m[pivot] = m[pivot], m[col]
        for r in range(3):
            if r != col:
                factor = m[r][col] / m[col][col]
                for c in range(col, 4):
                    m[r][c] -= factor * m[col][c]
    return [m[i][3] / m[i][i] for i in range(3)]
