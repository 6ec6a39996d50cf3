"""The spec's URDF as ``robospec optimize`` condenses it: its text with every mesh named by
absolute path, the SRDF beside it, and the links kept.

The links kept are every link the spec names — wherever: groups' links, camera mounts, tcp,
ee_link and root_link_name, named links, link and collision rules, never_collide, grasping and
the other members' links, drives (``Bindings.link_names`` of the resolve stage) — the links of
the SRDF's pairs, the root, and those ``--keep`` pins.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import NAMED_LINK_MERGED, UNKNOWN_LINK

if TYPE_CHECKING:
    from lxml import etree

    from robospec.description import RobotDescription
    from robospec.pipeline import CompiledSpec
    from robospec.resolve.resolved import FileRef


def absolute_meshes(text: str, description: RobotDescription) -> etree._Element:
    """The URDF's <robot> with every mesh and texture robospec found named by absolute path."""
    from lxml import etree

    root = etree.fromstring(text.encode())
    found = {m.uri: m.path for m in description.mesh_files if m.path is not None}
    for element in root.iter("mesh", "texture"):
        filename = element.get("filename")
        if filename in found:
            element.set("filename", str(Path(found[filename]).resolve()))
    return root


def srdf_of(ref: FileRef) -> str | None:
    """The SRDF SAPIEN reads beside the spec's URDF (never beside a xacro expansion)."""
    if not ref.has_srdf_beside:
        return None
    from robospec.description.srdf import srdf_path

    srdf = Path(srdf_path(str(ref.absolute)))
    return srdf.read_text() if srdf.is_file() else None


def child(joint: etree._Element) -> str | None:
    """The name of a URDF joint's child link."""
    found = joint.find("child")
    return found.get("link") if found is not None else None


def links_to_keep(compiled: CompiledSpec, keep: Sequence[str]) -> set[str]:
    """The links the spec names, those ``keep`` pins and those of the SRDF's pairs."""
    assert compiled.robot is not None and compiled.context is not None  # refused otherwise
    kept = {name for _, name in compiled.context.bindings.link_names}
    kept.update(keep)
    srdf = srdf_of(compiled.robot.description)
    if srdf is not None:
        from lxml import etree

        for pair in etree.fromstring(srdf.encode()).iter("disable_collisions"):
            kept.update(filter(None, (pair.get("link1"), pair.get("link2"))))
    return kept


def unknown_keep(description: RobotDescription, keep: Sequence[str]) -> list[Diagnostic]:
    """RS202 for each ``--keep`` link the description lacks."""
    return [
        error(Location("<command line>"), UNKNOWN_LINK, f"--keep: unknown link '{name}'")
        for name in keep
        if description.link(name) is None
    ]


def named_links_merged_away(compiled: CompiledSpec, condensed: etree._Element) -> list[Diagnostic]:
    """RS673 for each link the spec names that the condensed description lacks, where the
    spec names it: optimize keeps every link the spec names, so this is a link named where
    the keep list did not look, and the optimized spec would not compile."""
    assert compiled.context is not None  # compiled
    present = {link.get("name") for link in condensed.findall("link")}
    problems = []
    seen: set[str] = set()
    for path, name in compiled.context.bindings.link_names:
        if name in present or name in seen:
            continue
        seen.add(name)
        problems.append(
            error(
                compiled.context.value(path),
                NAMED_LINK_MERGED,
                f"link '{name}' would be merged away by robospec optimize, and the spec names it",
                f"keep it with --keep {name}",
            )
        )
    return problems


def kept_on_fixed_joints(urdf: etree._Element, keep: set[str]) -> list[str]:
    """The links of ``keep`` that hang on a fixed joint of ``urdf``: kept, not merged."""
    return sorted(
        name
        for name in keep
        if any(j.get("type") == "fixed" and child(j) == name for j in urdf.findall("joint"))
    )


def unmerged(condensed: etree._Element, keep: set[str]) -> list[str]:
    """The links on fixed joints that condensing left although ``keep`` does not pin them."""
    return sorted(
        name
        for joint in condensed.findall("joint")
        if joint.get("type") == "fixed" and (name := child(joint)) is not None
        if name not in keep
    )
