"""What every check reads: the spec, what it resolved to, and where each key was written."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Location
from robospec.load.source_map import KeyPath
from robospec.model.frozen import Spec
from robospec.resolve.resolved import Bindings, ResolvedRobot

EXPANDED = " (expanded)"  # how diagnostics name a xacro's expansion (resolve.description_files)


@dataclass(frozen=True)
class CheckContext:
    spec: Spec
    robot: ResolvedRobot
    description: RobotDescription
    description_file: str  # as shown in diagnostics
    bindings: Bindings
    locate_value: Callable[[KeyPath], Location]
    locate_key: Callable[[KeyPath], Location]

    def value(self, path: KeyPath) -> Location:
        return self.locate_value(path)

    def key(self, path: KeyPath) -> Location:
        return self.locate_key(path)

    def described_at(self, line: int) -> Location:
        """Line ``line`` of the robot description, named as validate names it: a xacro's lines
        are those of its expansion (``FILE (expanded)``), not of the file the spec names."""
        shown = self.description_file
        if self.spec.description is not None and self.spec.description.kind == "xacro":
            shown += EXPANDED
        return Location(shown, line, 1)

    def joints_at(self, path: KeyPath) -> tuple[str, ...] | None:
        """The joints the selection written at ``path`` bound to; None when it did not bind."""
        return self.bindings.joints.get(path)

    def links_at(self, path: KeyPath) -> tuple[str, ...] | None:
        """The links the selection written at ``path`` bound to; None when it did not bind."""
        return self.bindings.links.get(path)

    @property
    def passive_joints(self) -> frozenset[str]:
        return frozenset(self.bindings.joints.get(("passive_joints",), ()))
