"""Materials and link rules become ManiSkill's ``urdf_config``: rules by link name or glob,
applied in the description's link order, later rules refining earlier ones."""

from __future__ import annotations

import fnmatch
from typing import Any

from robospec.diagnostics import error
from robospec.diagnostics.codes import LINK_RULE_MATCHES_NONE, UNKNOWN_LINK, UNKNOWN_MATERIAL
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath
from robospec.model.names import GLOB
from robospec.resolve.context import ResolveContext


def resolve_urdf_config(context: ResolveContext) -> dict[str, Any]:
    spec = context.spec
    links: dict[str, dict[str, Any]] = {}
    for pattern, rule in spec.links.items():
        path: KeyPath = ("links", pattern)
        if rule.material is not None and rule.material not in spec.materials:
            context.err(
                (*path, "material"),
                UNKNOWN_MATERIAL,
                f"unknown material '{rule.material}'",
                did_you_mean(rule.material, spec.materials),
            )
        settings = rule.model_dump(exclude_none=True)
        for link in _links_for_rule(context, pattern, path):
            links.setdefault(link, {}).update(settings)
    config: dict[str, Any] = {}
    if spec.materials:
        config["_materials"] = {name: m.model_dump() for name, m in spec.materials.items()}
    if links:
        order = {name: i for i, name in enumerate(context.description.link_names)}
        config["link"] = {name: links[name] for name in sorted(links, key=order.__getitem__)}
    return config


def _links_for_rule(context: ResolveContext, pattern: str, path: KeyPath) -> list[str]:
    """The links a rule's key names; a rule that matches none is reported at its key."""
    description = context.description
    if description.link(pattern) is not None:
        context.bindings.link_names.append((path, pattern))
        return [pattern]
    matched = [n for n in description.link_names if fnmatch.fnmatchcase(n, pattern)]
    context.bindings.link_names.extend((path, n) for n in matched)
    if not matched:
        code = LINK_RULE_MATCHES_NONE if GLOB.search(pattern) else UNKNOWN_LINK
        message = (
            f"link rule '{pattern}' matches no link"
            if code == LINK_RULE_MATCHES_NONE
            else f"unknown link '{pattern}'"
        )
        context.diagnostics.append(
            error(
                context.at_key(path), code, message, did_you_mean(pattern, description.link_names)
            )
        )
    return matched
