"""The parts of a spec as the resolve stage holds them: each part's own compilation
(:class:`PartInput`: :mod:`robospec.pipeline` and :mod:`robospec.resolve.parts` fill it), and
each part renamed into the robot (:class:`CarriedPart`: :mod:`robospec.resolve.part_renaming`).
Plain data."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Location
from robospec.load.source_map import KeyPath
from robospec.resolve.resolved import FileRef, ResolvedPart, ResolvedRobot

# where a spec wrote a key path: its key's position (True) or its value's (False)
Locator = Callable[[KeyPath, bool], Location]


@dataclass(frozen=True)
class PartInput:
    """One part as its own compilation left it (or, for a bare description, as it loaded)."""

    name: str
    robot: ResolvedRobot | None  # None: a bare description, or a spec with errors
    description: RobotDescription | None
    shown: str  # its description, as diagnostics name it
    spec_shown: str | None = None  # its spec file, as diagnostics name it (None: bare)
    spec_path: str | None = None  # its spec file, absolute
    locate: Locator | None = None  # where its spec wrote a key path (key or value)
    fix_root_link: bool = True
    passive_joints: tuple[str, ...] = ()
    carried_not: tuple[str, ...] = ()  # what it declares that does not come along (hooks, ...)
    ref: FileRef | None = None  # a bare description's file (a spec's is its robot's)
    failed: bool = False  # its spec has errors
    errors: tuple[str, ...] = ()  # them, each as a line of text
    cycle: bool = False  # its spec mounts, directly or not, the spec that mounts it


@dataclass(frozen=True)
class CarriedPart:
    """A part as the robot takes it: its own robot, resolved on its own and renamed into the
    robot's names (:meth:`ResolvedRobot.renamed`), and what its mounting adds beside."""

    part: ResolvedPart  # where it is mounted, and its links and joints there
    joints: tuple[str, ...]  # the active joints it brings, in its qpos order (named here)
    robot: ResolvedRobot | None  # its spec's robot, renamed; None for a bare description
    # the (key, controller) entries its chosen mode adds to each of the robot's modes
    mode: tuple[tuple[str, str], ...] = ()
    passive_joints: tuple[str, ...] = ()
    # the link sets of the SRDF SAPIEN would have read beside its URDF: kept apart here
    loader_pairs: tuple[tuple[str, ...], ...] = ()
    locate: Locator | None = None  # where its spec wrote a key path (key or value)
