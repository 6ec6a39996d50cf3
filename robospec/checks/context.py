from __future__ import annotations

from dataclasses import dataclass

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Location
from robospec.load.source_map import KeyPath
from robospec.model.frozen import Spec
from robospec.resolve.resolved import ResolvedRobot


@dataclass(frozen=True)
class CheckContext:
    spec: Spec
    robot: ResolvedRobot
    description: RobotDescription
    description_file: str  # as shown in diagnostics
    passive_joints: frozenset[str]
    locate_value: object  # Callable[[KeyPath], Location]
    locate_key: object

    def value(self, path: KeyPath) -> Location:
        return self.locate_value(path)  # type: ignore[operator]

    def key(self, path: KeyPath) -> Location:
        return self.locate_key(path)  # type: ignore[operator]
