"""The optimized spec: the user's spec as written, with only what optimize changes changed — its
uid, its description (now the optimized URDF beside it), the never_collide entries added and,
for a profile that changes how the robot simulates, its ``simulation`` section.

A YAML spec goes through ruamel's round trip, so comments, key order and flow style stay; a TOML
spec through tomlkit, likewise, when the output is TOML too, else it is written as YAML. Paths
the spec gives relative to itself (a controller's ``urdf_path``) are rewritten relative to the
output's folder.
"""

from __future__ import annotations

import io
import os
import re
from pathlib import Path
from typing import Any

# keys of description: that name the old description and its files, or say how an MJCF is read
# (the optimized URDF is written from the robot as loaded: an MJCF's compiled and mended model,
# its listed sites links already)
_DESCRIPTION_KEYS = ("urdf", "xacro", "mjcf", "args", "packages", "download", "loader", "sites")
TOML_SUFFIXES = (".toml",)
MODELINE = re.compile(r"^(#\s*yaml-language-server:\s*\$schema=)(\S+)", re.M)


def rewrite_spec(
    spec: Path,
    out: Path,
    *,
    uid: str,
    urdf: str,
    never_collide: list[list[str]],
    header: str,
    simulation: dict[str, Any] | None = None,
) -> str:
    text = spec.read_text(encoding="utf-8")
    if spec.suffix in TOML_SUFFIXES and out.suffix in TOML_SUFFIXES:
        import tomlkit

        document: Any = tomlkit.parse(text)
        _change(document, spec, out, uid, urdf, never_collide, table=tomlkit.inline_table)
        _set_simulation(document, simulation, tomlkit.table)
        return f"{header}\n{tomlkit.dumps(document)}"
    from ruamel.yaml import YAML

    yaml = YAML(typ="rt")
    yaml.preserve_quotes = True
    yaml.width = 4096  # an entry on one line: a wrapped flow list leaves trailing spaces
    if spec.suffix in TOML_SUFFIXES:
        from robospec.load.toml_parser import tomllib

        document = tomllib.loads(text)
    else:
        document = yaml.load(text)
    _change(document, spec, out, uid, urdf, never_collide, table=None)
    _set_simulation(document, simulation, None)
    stream = io.StringIO()
    yaml.dump(document, stream)
    return f"{header}\n{_moved_schema_modeline(stream.getvalue(), spec, out)}"


def _moved_schema_modeline(text: str, spec: Path, out: Path) -> str:
    """The editors' ``$schema=`` modeline, still reaching the schema from the output's folder."""

    def moved(match: re.Match[str]) -> str:
        target = match.group(2)
        if "://" in target or os.path.isabs(target):
            return match.group(0)
        relative = os.path.relpath((spec.parent / target).resolve(), out.parent.resolve())
        return match.group(1) + Path(relative).as_posix()

    return MODELINE.sub(moved, text, count=1)


def _change(
    document: Any,
    spec: Path,
    out: Path,
    uid: str,
    urdf: str,
    never_collide: list[list[str]],
    table: Any,
) -> None:
    document["uid"] = uid
    description = document.get("description")
    if hasattr(description, "keys"):
        if "mjcf" in description:  # an MJCF's mends are in the URDF written from it
            description.pop("mend", None)
        for key in _DESCRIPTION_KEYS:
            if key in description:
                del description[key]
        description["urdf"] = urdf
    else:
        document["description"] = {"urdf": urdf}
    for controller in (document.get("controllers") or {}).values():
        path = controller.get("urdf_path") if hasattr(controller, "get") else None
        if isinstance(path, str) and not path.startswith("{") and not os.path.isabs(path):
            moved = os.path.relpath(spec.parent / path, out.parent)
            controller["urdf_path"] = Path(moved).as_posix()
    if never_collide:
        entries = document.get("never_collide")
        if entries is None:
            document["never_collide"] = entries = []
        for entry in never_collide:
            entries.append(_flow(list(entry)))


def _set_simulation(document: Any, simulation: dict[str, Any] | None, table: Any) -> None:
    """The profile's ``simulation`` keys, over whatever the spec had there (its other keys
    stay)."""
    if not simulation:
        return
    section = document.get("simulation")
    if not hasattr(section, "keys"):
        document["simulation"] = section = table() if table is not None else {}
    for key, value in simulation.items():
        section[key] = value


def _flow(items: list[str]) -> Any:
    """A list written on one line in YAML, as people write a pair."""
    from ruamel.yaml.comments import CommentedSeq

    seq = CommentedSeq(items)
    seq.fa.set_flow_style()
    return seq
