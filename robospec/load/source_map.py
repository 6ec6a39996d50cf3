"""Where each piece of a loaded spec came from: key paths mapped to 1-based line:column, and
numbers that remember how the spec wrote them."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from robospec.diagnostics import Location

KeyPath = tuple[str | int, ...]
Position = tuple[int, int]


@dataclass
class SourceMap:
    """Positions of keys and values by key path (``("controllers", "arm", "stiffness")``).

    For a sequence item the key position is the item's own position. Lookups fall back to the
    nearest ancestor that has a position, so every diagnostic has a line.
    """

    file: str
    keys: dict[KeyPath, Position] = field(default_factory=dict)
    values: dict[KeyPath, Position] = field(default_factory=dict)

    def key(self, path: KeyPath) -> Location:
        return self._lookup(path, self.keys, self.values)

    def value(self, path: KeyPath) -> Location:
        return self._lookup(path, self.values, self.keys)

    def _lookup(
        self, path: KeyPath, first: dict[KeyPath, Position], second: dict[KeyPath, Position]
    ) -> Location:
        path = tuple(path)
        while True:
            for table in (first, second):
                if path in table:
                    line, column = table[path]
                    return Location(self.file, line, column)
            if not path:
                return Location(self.file, 1, 1)
            path = path[:-1]


@dataclass
class LoadedSpec:
    """A spec file read from disk: plain data (dicts, lists, scalars) plus its source map."""

    path: str  # the path as given by the user, used in every diagnostic
    data: Any
    source: SourceMap
    raw: bytes
    format: str  # "yaml" or "toml"


class WrittenNumber(float):
    """A number that remembers how the spec wrote it: ``pi/8``, ``1e3``, ``100``.

    It is a float (it compares, hashes and computes as one, and arithmetic on it gives plain
    floats), so checks, physics and cards use it as the value it is; the emitter writes the
    text back (``np.pi / 8``) where it gives exactly that value."""

    __slots__ = ("text",)
    text: str

    def __new__(cls, value: float, text: str) -> WrittenNumber:
        number = super().__new__(cls, value)
        number.text = text
        return number

    # pickle and copy keep the text (float's own gives the value alone)
    def __getnewargs__(self) -> tuple[float, str]:  # type: ignore[override]
        return (float(self), self.text)
