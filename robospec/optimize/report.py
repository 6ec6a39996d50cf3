"""What ``robospec optimize`` did, and how it is shown: the report (text and JSON) and the one
result the command returns, which the CLI renders."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

from robospec.diagnostics import Diagnostic, has_errors

if TYPE_CHECKING:
    from robospec.optimize.shapes.collisions import ShapeChange


@dataclass
class OptimizeReport:
    spec: str
    out: str
    description: str  # the optimized description, relative to OUT's folder
    uid: str
    links_before: int = 0
    links_after: int = 0
    merged: list[tuple[str, str, str]] = field(default_factory=list)  # (link, into, joint)
    kept: list[str] = field(default_factory=list)  # links on fixed joints kept: named by the spec
    # links on fixed joints kept because SAPIEN takes their mass (or their parent's) from
    # collision shapes, or a <mimic> names their joint
    unmerged: list[str] = field(default_factory=list)
    shapes: list[dict[str, Any]] = field(default_factory=list)
    never_collide: list[list[str]] = field(default_factory=list)  # entries added
    samples: int = 0
    profile: str = "default"
    # the fast profile: the spec's simulation section as written, and what it measured
    simulation: dict[str, Any] = field(default_factory=dict)
    contacts: list[dict[str, Any]] = field(default_factory=list)  # before, after
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def to_json(self) -> dict[str, Any]:
        return {
            "spec": self.spec,
            "out": self.out,
            "description": self.description,
            "uid": self.uid,
            "links": {"before": self.links_before, "after": self.links_after},
            "merged": [{"link": a, "into": b, "joint": j} for a, b, j in self.merged],
            "kept": self.kept,
            "unmerged": self.unmerged,
            "collision_shapes": self.shapes,
            "never_collide": {"samples": self.samples, "entries": self.never_collide},
            "profile": self.profile,
            "simulation": self.simulation,
            "contacts": self.contacts,
            "diagnostics": [d.to_json() for d in self.diagnostics],
        }

    def to_text(self) -> str:
        lines = [
            f"{self.spec} -> {self.out} (uid {self.uid}, description {self.description})",
            f"  links: {self.links_before} -> {self.links_after} ({len(self.merged)} merged)",
        ]
        lines += [
            f"    {link} -> {into} (fixed joint {joint})" for link, into, joint in self.merged
        ]
        if self.kept:
            lines.append("  kept on fixed joints, named by the spec: " + ", ".join(self.kept))
        if self.unmerged:
            lines.append(
                "  kept on fixed joints, their mass (or their parent's) SAPIEN takes from their "
                "collision shapes, or a <mimic> names the joint: " + ", ".join(self.unmerged)
            )
        lines += _shapes_text(self.shapes)
        if self.samples:
            lines.append(
                f"  never_collide: {len(self.never_collide)} entr(ies) from {self.samples} "
                "sampled configurations and the keyframes"
            )
            lines += [f"    [{', '.join(entry)}]" for entry in self.never_collide]
        if self.profile != "default":
            lines += _profile_text(self.profile, self.simulation, self.contacts)
        return "\n".join(lines)


class OptimizeResult(NamedTuple):
    """What ``robospec optimize`` returns: the report, or None when nothing was written, and
    the diagnostics (those that stopped it, or the report's)."""

    report: OptimizeReport | None
    diagnostics: list[Diagnostic]

    @property
    def exit_code(self) -> int:
        """0 when the optimized spec was written without errors, else 1."""
        return 1 if self.report is None or has_errors(self.diagnostics) else 0

    def render(self, fmt: str) -> str:
        """The report and the diagnostics as text, or as one JSON document (``fmt`` json)."""
        if fmt == "json":
            data = self.report.to_json() if self.report is not None else {"diagnostics": []}
            if self.report is None:
                data["diagnostics"] = [d.to_json() for d in self.diagnostics]
            return json.dumps(data, indent=2)
        parts = [self.report.to_text()] if self.report is not None else []
        parts += [d.format_text() for d in self.diagnostics]
        return "\n".join(parts)


def shape_json(change: ShapeChange) -> dict[str, Any]:
    """A :class:`~robospec.optimize.shapes.ShapeChange` as the report gives it."""
    return {
        "link": change.link,
        "source": Path(change.source).name,
        "method": change.method,
        "shapes_before": change.shapes_before,
        "shapes_after": change.shapes_after,
        "vertices_before": change.vertices_before,
        "vertices_after": change.vertices_after,
        "fit": change.fit or None,
        "fit_error": change.fit_error,
        "reason": change.reason or None,
        "primitives": change.primitives,
    }


def _shapes_text(shapes: list[dict[str, Any]]) -> list[str]:
    if not shapes:
        return []
    before = sum(s["shapes_before"] for s in shapes)
    after = sum(s["shapes_after"] for s in shapes)
    v_before = sum(s["vertices_before"] for s in shapes)
    v_after = sum(s["vertices_after"] for s in shapes)
    lines = [f"  collision shapes: {before} -> {after}, vertices {v_before} -> {v_after}"]
    lines += [
        f"    {s['link']}: {s['method']} {s['shapes_before']} -> {s['shapes_after']} "
        f"shape(s), {s['vertices_before']} -> {s['vertices_after']} vertices" + _fit_text(s)
        for s in shapes
        if s["method"] != "kept" or s.get("reason")
    ]
    return lines


def _fit_text(shape: dict[str, Any]) -> str:
    if shape.get("fit_error") is None and not shape.get("reason"):
        return ""
    text = ""
    if shape.get("fit_error") is not None:
        text += f", {shape['fit']} within {shape['fit_error'] * 1000:.2f} mm"
    if shape.get("reason"):
        text += f" (kept: {shape['reason']})"
    return text


def _profile_text(
    profile: str, simulation: dict[str, Any], contacts: list[dict[str, Any]]
) -> list[str]:
    lines = [f"  profile {profile}: the robot collides differently, for speed"]
    if "contact_offset" in simulation:
        lines.append(
            f"    contact offset of the robot's shapes: {simulation['contact_offset']} m "
            "(ManiSkill's scenes: 0.02 m)"
        )
    if len(contacts) == 2:
        before, after = contacts
        lines.append(
            f"      pairs of its links making contacts, per sampled configuration: "
            f"{before['pairs_per_configuration']:.1f} -> {after['pairs_per_configuration']:.1f} "
            f"({before['configurations']} configurations); pairs that never touch making "
            f"contacts: {before['never_touching_pairs']} -> {after['never_touching_pairs']}"
        )
    if "solver_position_iterations" in simulation:
        lines.append(
            f"    recommended sim config ({simulation.get('category')}): solver iterations "
            f"{simulation['solver_position_iterations']} position, "
            f"{simulation['solver_velocity_iterations']} velocity "
            "(sim_config_for(uid); ManiSkill's default 15 and 1)"
        )
    return lines
