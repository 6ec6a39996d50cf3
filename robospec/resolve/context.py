"""What one spec's resolution reads, and what it records for the checks.

Every module of the resolve stage takes one :class:`ResolveContext`: the validated spec and
where each of its keys was written, the robot description once it is loaded, the diagnostics
so far, and the bindings — each joint or link selection as the names it bound to — that the
checks stage (:mod:`robospec.checks`) judges afterwards.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from robospec.description.facts import RobotDescription
from robospec.diagnostics import Diagnostic, Location, error, warning
from robospec.load.source_map import KeyPath, LoadedSpec
from robospec.model.frozen import Spec
from robospec.model.validate import SpecModelResult
from robospec.resolve.resolved import Bindings, ResolvedRobot

if TYPE_CHECKING:
    # the parts' types (and what makes them) are imported for a spec that mounts parts alone
    from robospec.compose.model import Composed
    from robospec.resolve.part_types import CarriedPart, Locator, PartInput


@dataclass
class ResolveContext:
    loaded: LoadedSpec
    model: SpecModelResult
    spec_file: Path
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # set once the description is loaded (or assumed, when it is not downloaded yet)
    loaded_description: RobotDescription | None = None
    # the description is not downloaded: names are taken as written (description/assumed.py)
    assumed: bool = False
    bindings: Bindings = field(default_factory=Bindings)
    # the result: None when the description (or the extended class) could not be loaded
    robot: ResolvedRobot | None = None
    # group name -> its joints, each group expanded once
    group_joints: dict[str, list[str]] = field(default_factory=dict)
    # the parts the spec mounts, compiled (robospec.resolve.parts), by name
    parts: dict[str, PartInput] = field(default_factory=dict)
    # the combined description, once the parts are mounted
    composed: Composed | None = None
    # the parts in the robot's names, once the combined description is loaded
    carried: tuple[CarriedPart, ...] = ()
    # paths of what came along from a part's spec -> where that part's spec wrote it
    origins: dict[KeyPath, tuple[Locator, KeyPath]] = field(default_factory=dict)

    @property
    def spec(self) -> Spec:
        assert self.model.spec is not None
        return self.model.spec

    @property
    def description(self) -> RobotDescription:
        """The description; only asked for once it is loaded."""
        assert self.loaded_description is not None
        return self.loaded_description

    # -- where things were written -----------------------------------------------------------

    def at_value(self, path: KeyPath) -> Location:
        found = self._in_part(path, key=False)
        return found or self.loaded.source.value(self.model.origin(path))

    def at_key(self, path: KeyPath) -> Location:
        found = self._in_part(path, key=True)
        return found or self.loaded.source.key(self.model.origin(path))

    def _in_part(self, path: KeyPath, *, key: bool) -> Location | None:
        """Where a part's spec wrote what ``path`` names, for what came along from a part."""
        for length in range(len(path), 0, -1):
            found = self.origins.get(path[:length])
            if found is not None:
                locate, there = found
                return locate((*there, *path[length:]), key)
        return None

    def err(self, path: KeyPath, code: str, message: str, hint: str | None = None) -> None:
        self.diagnostics.append(error(self.at_value(path), code, message, hint))

    def warn(self, path: KeyPath, code: str, message: str, hint: str | None = None) -> None:
        self.diagnostics.append(warning(self.at_value(path), code, message, hint))
