"""What every check reads: the spec, what it resolved to, and where each key was written."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Location
from robospec.load.source_map import KeyPath
from robospec.model.frozen import Spec
from robospec.resolve.description_loading import EXPANDED
from robospec.resolve.resolved import Bindings, ResolvedRobot

if TYPE_CHECKING:
    from robospec.compose import Origins


@dataclass(frozen=True)
class CheckContext:
    spec: Spec
    robot: ResolvedRobot
    description: RobotDescription
    description_file: str  # as shown in diagnostics
    bindings: Bindings
    locate_value: Callable[[KeyPath], Location]
    locate_key: Callable[[KeyPath], Location]
    # a description robospec composed from several (parts): where each of its lines came from
    description_origins: Origins | None = None
    # active joints whose keyframe values the parts give (a keyframe need not name them)
    filled_by_parts: frozenset[str] = frozenset()
    # the parts' passive joints (no control mode needs to drive them)
    part_passive_joints: frozenset[str] = frozenset()

    def value(self, path: KeyPath) -> Location:
        return self.locate_value(path)

    def key(self, path: KeyPath) -> Location:
        return self.locate_key(path)

    def joints_at(self, path: KeyPath) -> tuple[str, ...] | None:
        """The joints the selection written at ``path`` bound to; None when it did not bind."""
        return self.bindings.joints.get(path)

    def links_at(self, path: KeyPath) -> tuple[str, ...] | None:
        """The links the selection written at ``path`` bound to; None when it did not bind."""
        return self.bindings.links.get(path)

    def at_description(self, line: int) -> Location:
        """Line ``line`` of the description, in the file it came from (a part's, when the
        description was composed); a xacro's lines are those of its expansion, named as
        validate names it (``FILE (expanded)``), not lines of the file the spec names."""
        if self.description_origins is not None:
            found = self.description_origins.locate(line)
            if found is not None:
                return Location(found[0], found[1], 1)
        shown = self.description_file
        if self.spec.description is not None and self.spec.description.kind == "xacro":
            shown += EXPANDED
        return Location(shown, line, 1)

    @property
    def passive_joints_bound(self) -> tuple[str, ...]:
        """The spec's own passive joints, as they bound."""
        return tuple(self.bindings.joints.get(("passive_joints",), ()))

    @property
    def passive_joints(self) -> frozenset[str]:
        return frozenset(self.passive_joints_bound) | self.part_passive_joints
