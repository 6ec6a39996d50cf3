"""The parts of a spec as the resolve stage holds them: each part's own compilation
(:class:`PartInput`) and what comes along from them into the robot (:class:`Plan`). Plain data;
:mod:`robospec.resolve.parts` fills it."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Location
from robospec.load.source_map import KeyPath
from robospec.resolve.resolved import (
    FileRef,
    ResolvedCamera,
    ResolvedCollisionRule,
    ResolvedController,
    ResolvedDrive,
    ResolvedGrasping,
    ResolvedLinkState,
    ResolvedPart,
    ResolvedRobot,
    ResolvedTcp,
)

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


@dataclass
class Plan:
    """What comes along from the parts' specs, under its name in the robot."""

    controllers: list[ResolvedController] = field(default_factory=list)
    # part -> the (key, controller) entries its default mode adds to each of the robot's modes
    modes: dict[str, tuple[tuple[str, str], ...]] = field(default_factory=dict)
    # part -> the active joints it brings (named as in the combined description)
    joints: dict[str, frozenset[str]] = field(default_factory=dict)
    named_links: list[tuple[str, str | tuple[str, ...]]] = field(default_factory=list)
    grasping: list[ResolvedGrasping] = field(default_factory=list)
    link_states: list[ResolvedLinkState] = field(default_factory=list)
    proprioception: list[str] = field(default_factory=list)
    cameras: list[ResolvedCamera] = field(default_factory=list)
    drives: list[ResolvedDrive] = field(default_factory=list)
    disable_gravity: list[str] = field(default_factory=list)
    collision_rules: list[ResolvedCollisionRule] = field(default_factory=list)
    never_collide: list[tuple[str, ...]] = field(default_factory=list)
    materials: dict[str, dict[str, Any]] = field(default_factory=dict)
    link_rules: dict[str, dict[str, Any]] = field(default_factory=dict)
    tcp: ResolvedTcp | None = None
    passive_joints: list[str] = field(default_factory=list)
    parts: list[ResolvedPart] = field(default_factory=list)
