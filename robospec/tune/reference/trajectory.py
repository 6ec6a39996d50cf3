"""A recorded trajectory: commanded joint targets and measured joint positions over time.

Two file formats, both plain (see docs/tune.md, "Matching a reference"):

- CSV: a header row naming the columns, then one row per sample. ``t`` (seconds), and per joint
  ``target:<joint>`` and ``qpos:<joint>`` (rad, or m for a prismatic joint). Lines starting with
  ``#`` are comments. Cells are plain numbers (no quoting).
- NPZ (``numpy.savez``): arrays ``t`` (T), ``target`` (T x J), ``qpos`` (T x J) and ``joints``
  (J strings, the columns' joint names).

Everything wrong with a file is a located diagnostic (RS640-RS644), never an exception: the CSV
header cell or the row and cell of a bad value; for NPZ the file and the array's name.
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import (
    REFERENCE_MALFORMED,
    REFERENCE_NOT_FINITE,
    REFERENCE_TIME_ORDER,
    REFERENCE_UNREADABLE,
)

TIME_COLUMNS = ("t", "time")
MIN_SAMPLES = 10  # fewer samples cannot show a response


@dataclass(frozen=True)
class Reference:
    """``target`` and ``qpos`` are (T, J) in the order of ``joints``; ``t`` starts anywhere
    and increases strictly."""

    t: np.ndarray
    target: np.ndarray
    qpos: np.ndarray
    joints: tuple[str, ...]
    source: str  # the file, as shown in diagnostics ("mujoco" for a MuJoCo-made one)
    # where each joint's qpos column is written (CSV header cell), for diagnostics about a joint
    joint_locations: tuple[Location, ...] = ()

    def location(self, joint: str) -> Location:
        index = self.joints.index(joint)
        if index < len(self.joint_locations):
            return self.joint_locations[index]
        return Location(self.source)

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])

    def save(self, path: Path) -> None:
        np.savez(path, t=self.t, target=self.target, qpos=self.qpos, joints=np.array(self.joints))


Read = tuple[Reference | None, list[Diagnostic]]


def read_reference(path: Path, display: str | None = None) -> Read:
    """The trajectory in ``path`` (by suffix: ``.csv`` or ``.npz``), or None and why not."""
    shown = display or str(path)
    suffix = path.suffix.lower()
    if suffix not in (".csv", ".npz"):
        return None, [
            error(
                Location(shown),
                REFERENCE_UNREADABLE,
                f"reference '{shown}' is neither a .csv nor a .npz file",
                "write the trajectory as CSV (t, target:<joint>, qpos:<joint> columns) or NPZ "
                "(arrays t, target, qpos, joints), or pass --reference mujoco",
            )
        ]
    if not path.is_file():
        return None, [
            error(
                Location(shown), REFERENCE_UNREADABLE, f"reference file '{shown}' not found", None
            )
        ]
    try:
        if suffix == ".csv":
            reference, problems = _read_csv(path.read_text(encoding="utf-8"), shown)
        else:
            reference, problems = _read_npz(path, shown)
    except (OSError, UnicodeDecodeError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        return None, [
            error(
                Location(shown),
                REFERENCE_UNREADABLE,
                f"reference '{shown}' cannot be read: {exc}",
                None,
            )
        ]
    if reference is None or problems:
        return None, problems
    return reference, _check_times(reference)


Cells = list[tuple[int, str]]  # (column, cell) of one CSV line


@dataclass(frozen=True)
class _Columns:
    """Which header column holds the time, and each joint's target and measured position."""

    time: int
    targets: dict[str, int]
    measured: dict[str, int]
    joints: tuple[str, ...]  # those with both, in the order of their qpos columns


def _read_csv(text: str, shown: str) -> Read:
    rows = _csv_rows(text)
    if not rows:
        return None, [
            error(Location(shown), REFERENCE_MALFORMED, f"reference '{shown}' has no header row")
        ]
    header_line, header = rows[0]
    columns, problems = _csv_columns(header_line, header, shown)
    if columns is None:
        return None, problems
    values, problems = _csv_values(rows[1:], [name for _, name in header], shown)
    if problems:
        return None, problems
    joints, measured = columns.joints, columns.measured
    return Reference(
        t=values[:, columns.time],
        target=values[:, [columns.targets[j] for j in joints]],
        qpos=values[:, [measured[j] for j in joints]],
        joints=joints,
        source=shown,
        joint_locations=tuple(Location(shown, header_line, header[measured[j]][0]) for j in joints),
    ), []


def _csv_rows(text: str) -> list[tuple[int, Cells]]:
    """Each line that is not blank or a comment: its number and its stripped cells."""
    rows: list[tuple[int, Cells]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        cells, column = [], 1
        for cell in line.split(","):
            stripped = cell.strip()
            cells.append((column + len(cell) - len(cell.lstrip()), stripped))
            column += len(cell) + 1
        rows.append((number, cells))
    return rows


def _csv_columns(
    header_line: int, header: Cells, shown: str
) -> tuple[_Columns | None, list[Diagnostic]]:
    """The header's columns, or what is wrong with them (RS641)."""
    names = [name for _, name in header]
    problems: list[Diagnostic] = []
    time_index = next((i for i, name in enumerate(names) if name in TIME_COLUMNS), None)
    if time_index is None:
        problems.append(
            error(
                Location(shown, header_line, 1),
                REFERENCE_MALFORMED,
                "the reference's header has no time column 't'",
                "name the time column (seconds) 't'",
            )
        )
    targets: dict[str, int] = {}
    measured: dict[str, int] = {}
    for index, (column, name) in enumerate(header):
        if index == time_index:
            continue
        prefix, _, joint = name.partition(":")
        into = {"target": targets, "qpos": measured}.get(prefix)
        if into is None or not joint:
            problems.append(
                error(
                    Location(shown, header_line, column),
                    REFERENCE_MALFORMED,
                    f"unknown reference column '{name}'",
                    "columns are t, target:<joint> and qpos:<joint>",
                )
            )
        elif joint in into:
            problems.append(
                error(
                    Location(shown, header_line, column),
                    REFERENCE_MALFORMED,
                    f"column '{name}' twice",
                )
            )
        else:
            into[joint] = index
    for joint in [*targets, *measured]:
        other, have = ("qpos", measured) if joint in targets else ("target", targets)
        if joint not in have:
            index = targets.get(joint, measured.get(joint, 0))
            problems.append(
                error(
                    Location(shown, header_line, header[index][0]),
                    REFERENCE_MALFORMED,
                    f"joint '{joint}' has no '{other}:{joint}' column",
                    "each joint needs its commanded target and its measured position",
                )
            )
    joints = [j for j in measured if j in targets]
    if not joints and not problems:
        problems.append(
            error(
                Location(shown, header_line, 1), REFERENCE_MALFORMED, "the reference names no joint"
            )
        )
    if problems or time_index is None:
        return None, problems
    return _Columns(time_index, targets, measured, tuple(joints)), []


def _csv_values(
    rows: list[tuple[int, Cells]], names: list[str], shown: str
) -> tuple[np.ndarray, list[Diagnostic]]:
    """The samples as numbers (one row each, in the header's columns), and the cells that are
    not finite numbers (RS641, RS642)."""
    problems: list[Diagnostic] = []
    values = np.empty((len(rows), len(names)))
    for r, (line, cells) in enumerate(rows):
        if len(cells) != len(names):
            problems.append(
                error(
                    Location(shown, line, 1),
                    REFERENCE_MALFORMED,
                    f"row has {len(cells)} cells, the header {len(names)}",
                )
            )
            continue
        for c, (column, cell) in enumerate(cells):
            try:
                values[r, c] = float(cell)
            except ValueError:
                problems.append(
                    error(
                        Location(shown, line, column),
                        REFERENCE_MALFORMED,
                        f"'{cell}' is not a number",
                    )
                )
                continue
            if not np.isfinite(values[r, c]):
                problems.append(
                    error(
                        Location(shown, line, column),
                        REFERENCE_NOT_FINITE,
                        f"{names[c]} is {cell} (not a finite number)",
                        "drop or fill the samples where the recording has no value",
                    )
                )
        if len(problems) >= 20:  # a broken file: the first ones say enough
            break
    return values, problems


def _read_npz(path: Path, shown: str) -> Read:
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    missing = [name for name in ("t", "target", "qpos", "joints") if name not in arrays]
    if missing:
        return None, [
            error(
                Location(shown),
                REFERENCE_MALFORMED,
                f"reference '{shown}' lacks the array(s) {', '.join(missing)}",
                "save t (T), target (T x J), qpos (T x J) and joints (J names) with numpy.savez",
            )
        ]
    t, target, qpos, joints = (arrays[n] for n in ("t", "target", "qpos", "joints"))
    problems = []
    names = [str(j) for j in np.atleast_1d(joints)]
    shape = (t.shape[0] if t.ndim == 1 else -1, len(names))
    if t.ndim != 1:
        problems.append(f"t has shape {t.shape}, not (T,)")
    for name, array in (("target", target), ("qpos", qpos)):
        if array.shape != shape:
            problems.append(f"{name} has shape {array.shape}, not (T, J) = {shape}")
    if not names or joints.dtype.kind not in "US":
        problems.append("joints must be a non-empty array of joint names")
    elif len(set(names)) != len(names):
        problems.append("joints names a joint twice")
    if problems:
        return None, [
            error(Location(shown), REFERENCE_MALFORMED, f"reference '{shown}': {p}")
            for p in problems
        ]
    try:
        t, target, qpos = (np.asarray(a, dtype=np.float64) for a in (t, target, qpos))
    except (TypeError, ValueError):
        return None, [
            error(Location(shown), REFERENCE_MALFORMED, "t, target and qpos must be numbers")
        ]
    for name, array in (("t", t), ("target", target), ("qpos", qpos)):
        bad = np.argwhere(~np.isfinite(array))
        if bad.size:
            where = bad[0]
            column = f", joint '{names[where[1]]}'" if array.ndim == 2 else ""
            return None, [
                error(
                    Location(shown),
                    REFERENCE_NOT_FINITE,
                    f"reference '{shown}': {name}[{', '.join(map(str, where))}] is "
                    f"{array[tuple(where)]} (sample {where[0]}{column}); {len(bad)} such value(s)",
                    "drop or fill the samples where the recording has no value",
                )
            ]
    return Reference(t, target, qpos, tuple(names), shown), []


def _check_times(reference: Reference) -> list[Diagnostic]:
    where = Location(reference.source)
    if reference.t.size < MIN_SAMPLES:
        return [
            error(
                where,
                REFERENCE_TIME_ORDER,
                f"reference '{reference.source}' has {reference.t.size} samples; at least "
                f"{MIN_SAMPLES} are needed",
            )
        ]
    steps = np.diff(reference.t)
    if np.any(steps <= 0):
        sample = int(np.argmax(steps <= 0)) + 1
        return [
            error(
                where,
                REFERENCE_TIME_ORDER,
                f"reference time does not increase at sample {sample} "
                f"(t = {reference.t[sample - 1]:g} then {reference.t[sample]:g})",
                "samples must be in time order, each at a later time",
            )
        ]
    return []
