"""The files ``robospec optimize`` writes beside OUT, and the rule that keeps it from
overwriting a file it did not write.

``OUT.yaml`` (the spec), ``<stem>.urdf``, ``<stem>.srdf`` and ``<stem>_collision/`` each carry
:data:`MARK` (the folder in a ``.robospec-optimize`` file inside it); a target that exists
without it is RS604 and nothing is written. Everything is staged in a temporary folder beside
OUT and renamed into place at the end (:func:`move_into_place`), the spec last.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import WOULD_OVERWRITE

if TYPE_CHECKING:
    from lxml import etree

# the first line of every file robospec optimize writes: what it may overwrite
MARK = "written by robospec optimize"
FINAL_URDF = ".final.urdf"  # in the staging folder: the URDF as it is named from OUT's folder
COLLISION_MARK = ".robospec-optimize"  # the file that marks a collision folder as ours


@dataclass(frozen=True)
class Targets:
    """Where each output goes, all beside OUT."""

    spec: Path
    urdf: Path
    srdf: Path
    collision: Path

    @classmethod
    def beside(cls, out: Path) -> Targets:
        stem = out.name.split(".")[0]
        return cls(
            out,
            out.with_name(f"{stem}.urdf"),
            out.with_name(f"{stem}.srdf"),
            out.with_name(f"{stem}_collision"),
        )

    def __iter__(self) -> Iterator[Path]:
        return iter((self.spec, self.urdf, self.srdf, self.collision))


def not_ours(targets: Targets) -> list[Diagnostic]:
    """RS604 for each target that exists and robospec optimize did not write."""
    return [d for path in targets if (d := _not_ours(path, targets.spec)) is not None]


def _not_ours(path: Path, out: Path) -> Diagnostic | None:
    if not path.exists() and not path.is_symlink():
        return None
    marked = path / COLLISION_MARK if path.is_dir() else path
    try:
        with open(marked, encoding="utf-8", errors="replace") as stream:
            head = stream.read(200)
    except OSError:
        head = ""
    if MARK in head:
        return None
    return error(
        Location(str(path)),
        WOULD_OVERWRITE,
        f"{path} exists and robospec optimize did not write it; it is not overwritten",
        f"move it away, or write the optimized spec elsewhere than {out}",
    )


def make_collision_folder(folder: Path) -> None:
    folder.mkdir()
    (folder / COLLISION_MARK).write_text(MARK + "\n")


def drop_if_empty(folder: Path) -> None:
    """Remove a collision folder nothing was written into: no folder, then."""
    if all(p.name == COLLISION_MARK for p in folder.iterdir()):
        shutil.rmtree(folder)


def write_urdf(
    robot: etree._Element,
    path: Path,
    relative_to: Path,
    staging: Path,
    source: str,
    final_dir: Path | None = None,
) -> None:
    """The optimized URDF, its meshes named relative to ``relative_to``; meshes written under
    ``staging`` are named where they will be under ``final_dir`` (when given)."""
    from lxml import etree

    robot = etree.fromstring(etree.tostring(robot))
    for element in robot.iter("mesh", "texture"):
        filename = element.get("filename") or ""
        if os.path.isabs(filename):
            target = Path(filename)
            if final_dir is not None and staging in target.parents:
                target = final_dir / target.relative_to(staging)
            element.set("filename", Path(os.path.relpath(target, relative_to)).as_posix())
    robot.addprevious(etree.Comment(f" {MARK} from {source}: do not edit "))
    text = etree.tostring(robot.getroottree(), encoding="unicode", pretty_print=True)
    path.write_text(text if text.endswith("\n") else text + "\n", encoding="utf-8")


def write_srdf(srdf: str, path: Path) -> None:
    """The SRDF as it was, marked (after the XML declaration, where it has one)."""
    path.write_text(
        srdf.replace("?>", f"?>\n<!-- {MARK} -->", 1)
        if srdf.startswith("<?xml")
        else f"<!-- {MARK} -->\n{srdf}"
    )


def move_into_place(staging: Path, targets: Targets) -> None:
    """Rename each staged output over its target; the spec last, so that it never names a
    description that is not there yet."""
    os.replace(staging / FINAL_URDF, staging / targets.urdf.name)
    for key, final in (
        ("collision", targets.collision),
        ("urdf", targets.urdf),
        ("srdf", targets.srdf),
        ("spec", targets.spec),
    ):
        staged = staging / final.name
        if key == "collision" and final.is_dir():
            shutil.rmtree(final)
        elif not staged.exists() and final.exists() and key in ("srdf", "collision"):
            # an output of an earlier run that this one does not make
            shutil.rmtree(final) if final.is_dir() else final.unlink()
        if staged.exists():
            os.replace(staged, final)
