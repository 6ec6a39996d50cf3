"""Joint and link selections — names, globs, groups, ``all_but`` — bound to the description.

A name that binds to nothing is an error here (RS201 unknown joint, RS202 unknown link, RS206 and
RS207 a glob matching nothing, RS209 a circular group). What the names bound to is recorded in
the context's :class:`~robospec.resolve.resolved.Bindings` for the checks, which judge it (a
fixed joint selected, a joint listed twice, ...).
"""

from __future__ import annotations

import fnmatch
from typing import Any

from robospec.diagnostics.codes import (
    CIRCULAR_GROUP,
    JOINT_PATTERN_MATCHES_NONE,
    LINK_RULE_MATCHES_NONE,
    UNKNOWN_JOINT,
    UNKNOWN_LINK,
)
from robospec.diagnostics.suggest import did_you_mean
from robospec.load.source_map import KeyPath
from robospec.model.frozen import AllBut
from robospec.model.names import GLOB
from robospec.resolve.context import ResolveContext


def select_joints(context: ResolveContext, selection: Any, path: KeyPath) -> list[str]:
    """The active joints ``selection`` names, in the order written (a glob: in qpos order)."""
    joints, whole = _joints(context, selection, path, ())
    if whole:
        context.bindings.joints[path] = tuple(joints)
    return joints


def bound_joints(context: ResolveContext, path: KeyPath) -> tuple[str, ...] | None:
    """What the selection at ``path`` bound to; None when a name in it did not bind."""
    return context.bindings.joints.get(path)


def group_joints(context: ResolveContext, name: str) -> list[str]:
    """The joints of the spec's group ``name`` (expanded once, then remembered)."""
    return _group(context, name, ())[0]


def _joints(
    context: ResolveContext, selection: Any, path: KeyPath, stack: tuple[str, ...]
) -> tuple[list[str], bool]:
    description = context.description
    if isinstance(selection, AllBut):
        excluded, whole = _joints(context, selection.all_but, (*path, "all_but"), stack)
        return [j for j in description.active_joint_names if j not in set(excluded)], whole
    if isinstance(selection, list):
        out: list[str] = []
        whole = True
        for index, item in enumerate(selection):
            joints, item_whole = _joints(context, item, (*path, index), stack)
            out.extend(joints)
            whole = whole and item_whole
        return out, whole
    name = str(selection)
    joint = description.joint(name)
    if joint is None and name in context.spec.groups:
        return _group(context, name, stack)
    if joint is not None:
        context.bindings.joint_names.append((path, name))
        # a fixed joint selects nothing; the checks say so (RS311)
        return ([name], True) if joint.is_active else ([], False)
    if GLOB.search(name):
        matched = [j for j in description.active_joint_names if fnmatch.fnmatchcase(j, name)]
        if not matched:
            context.err(
                path, JOINT_PATTERN_MATCHES_NONE, f"pattern '{name}' matches no active joint"
            )
        return matched, bool(matched)
    candidates = [*description.joint_names, *context.spec.groups]
    context.err(path, UNKNOWN_JOINT, f"unknown joint '{name}'", did_you_mean(name, candidates))
    return [], False


def _group(context: ResolveContext, name: str, stack: tuple[str, ...]) -> tuple[list[str], bool]:
    if name in stack:
        cycle = " -> ".join((*stack[stack.index(name) :], name))
        context.err(("groups", name), CIRCULAR_GROUP, f"group definition is circular: {cycle}")
        return [], False
    if name not in context.group_joints:
        path: KeyPath = ("groups", name)
        joints, whole = _joints(context, context.spec.groups[name], path, (*stack, name))
        context.group_joints[name] = joints
        if whole:
            context.bindings.joints[path] = tuple(joints)
    return context.group_joints[name], ("groups", name) in context.bindings.joints


def select_links(context: ResolveContext, selection: Any, path: KeyPath) -> list[str]:
    """The links a name, a glob, a list of them or ``{all_but: ...}`` selects (``all_but``: in
    the description's link order)."""
    if isinstance(selection, AllBut):
        excluded = set(select_links(context, selection.all_but, (*path, "all_but")))
        links = [n for n in context.description.link_names if n not in excluded]
        whole = (*path, "all_but") in context.bindings.links
    else:
        items = selection if isinstance(selection, list) else [selection]
        links = []
        whole = True
        for index, item in enumerate(items):
            item_path = (*path, index) if isinstance(selection, list) else path
            matched = links_matching(context, item, item_path)
            links.extend(matched)
            whole = whole and bool(matched)
    if whole:
        context.bindings.links[path] = tuple(links)
    return links


def links_matching(context: ResolveContext, pattern: str, path: KeyPath) -> list[str]:
    description = context.description
    if description.link(pattern) is not None:
        context.bindings.link_names.append((path, pattern))
        return [pattern]
    if GLOB.search(pattern):
        matched = [n for n in description.link_names if fnmatch.fnmatchcase(n, pattern)]
        if not matched:
            context.err(path, LINK_RULE_MATCHES_NONE, f"pattern '{pattern}' matches no link")
        context.bindings.link_names.extend((path, n) for n in matched)
        return matched
    context.err(
        path,
        UNKNOWN_LINK,
        f"unknown link '{pattern}'",
        did_you_mean(pattern, description.link_names),
    )
    return []


def link(context: ResolveContext, name: str, path: KeyPath) -> str | None:
    """``name`` when the description has that link; else RS202 and None."""
    if context.description.link(name) is None:
        context.err(
            path,
            UNKNOWN_LINK,
            f"unknown link '{name}'",
            did_you_mean(name, context.description.link_names),
        )
        return None
    context.bindings.link_names.append((path, name))
    return name
