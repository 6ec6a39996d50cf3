"""``robospec schema --for SPEC``: the spec schema narrowed to one compiled robot.

Every place where a spec names a joint, link, group, controller, ... carries an
``x-robospec-ref`` marker in the generic schema (see :mod:`robospec.model.refs`). This pass
replaces each marked string by a reference to a ``$defs/robot-<kind>`` enum of the names the
robot really has, so an editor completes them and flags a misspelled one. Places that accept
globs keep accepting any string with a glob character. A marked dictionary key becomes one
``properties`` entry per name (so editors complete keys too) and ``additionalProperties:
false``. Examples are narrowed too: the generic ones name the Panda's links.
"""

from __future__ import annotations

import copy
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from robospec.model.names import GLOB_PATTERN
from robospec.model.refs import GLOB_KINDS, REF_KEY

if TYPE_CHECKING:
    from robospec.pipeline import CompiledSpec

KEYS_KEY = "x-robospec-keys"
NARROWED_ID = "https://robospec.dev/schemas/robots/{uid}.schema.json"


@dataclass(frozen=True)
class RobotNames:
    """The names one compiled robot offers, by reference kind."""

    uid: str
    by_kind: Mapping[str, Sequence[str]]

    def names(self, kind: str) -> list[str]:
        if kind not in self.by_kind:
            raise KeyError(f"no names for reference kind {kind!r}")
        return list(dict.fromkeys(self.by_kind[kind]))


def robot_names(compiled: CompiledSpec) -> RobotNames:
    """The names of a successfully compiled spec."""
    assert compiled.context is not None and compiled.description is not None
    spec = compiled.context.spec
    description = compiled.description
    joints = list(description.active_joint_names)
    links = list(description.link_names)
    # a part mounts at a link of the robot as written: one that `fold_frames` then left out of
    # the combined description (a flange frame) is still where the spec says it sits
    composed = compiled.composed
    folded = [name for part in composed.parts for name in part.folded] if composed else []
    return RobotNames(
        uid=spec.uid,
        by_kind={
            "joint": joints,
            "joint-selection": [*joints, *spec.groups],
            "link": links,
            "link-pattern": links,
            "link-or-named": [*links, *spec.named_links],
            "mount-link": [*links, *folded],
            "material": list(spec.materials),
            "controller": list(spec.controllers),
            "control-mode": list(spec.control_modes),
            "link-state": list(spec.link_states),
            "keyframe": list(spec.keyframes),
        },
    )


def narrow_schema(schema: dict[str, Any], robot: RobotNames) -> dict[str, Any]:
    """A copy of ``schema`` with every marked place limited to ``robot``'s names."""
    narrowed = _narrow(copy.deepcopy(schema), robot)
    _ExampleFilter(narrowed, robot).apply(narrowed)
    for kind in robot.by_kind:
        names = robot.names(kind)
        # no names (no materials, or control modes inherited through `extends`): any string,
        # and the compiler has the last word, rather than a schema that rejects everything
        listed: dict[str, Any] = {"enum": names} if names else {}
        narrowed["$defs"][names_def(kind)] = {
            "type": "string",
            "description": f"{_KIND_WORDS[kind]} of '{robot.uid}'",
            **listed,
        }
    narrowed["$id"] = NARROWED_ID.format(uid=robot.uid)
    narrowed["title"] = f"robospec spec for {robot.uid}"
    narrowed["description"] = (
        f"{narrowed.get('description', '')} Narrowed to the joints, links and names of "
        f"'{robot.uid}' (robospec schema --for)."
    ).strip()
    return narrowed


_KIND_WORDS = {
    "joint": "an active joint",
    "joint-selection": "an active joint or a group",
    "link": "a link",
    "link-pattern": "a link",
    "link-or-named": "a link or a named_links attribute",
    "mount-link": "a link (or a frame a part's fold_frames leaves out)",
    "material": "a material",
    "controller": "a controller",
    "control-mode": "a control mode",
    "link-state": "a link_states property",
    "keyframe": "a keyframe",
}


def names_def(kind: str) -> str:
    """The ``$defs`` entry listing the names of one reference kind (``robot-joint``, ...)."""
    return f"robot-{kind}"


def _narrow(node: Any, robot: RobotNames) -> Any:
    if isinstance(node, list):
        return [_narrow(item, robot) for item in node]
    if not isinstance(node, dict):
        return node
    keys = node.get("propertyNames")
    out = {key: _narrow(value, robot) for key, value in node.items() if key != "propertyNames"}
    if REF_KEY in out:
        return _name_schema(out, robot)
    if isinstance(keys, dict) and REF_KEY in keys:
        return _keyed_object(out, keys[REF_KEY], robot)
    if keys is not None:
        out["propertyNames"] = _narrow(keys, robot)
    return out


def _name_schema(node: dict[str, Any], robot: RobotNames) -> dict[str, Any]:
    """A marked string: its annotations stay, its type becomes the robot's names."""
    kind = node[REF_KEY]
    kept = {k: v for k, v in node.items() if k not in (REF_KEY, "type", "pattern")}
    exact = {"$ref": f"#/$defs/{names_def(kind)}"}
    if kind in GLOB_KINDS:
        glob = {"type": "string", "pattern": GLOB_PATTERN, "description": "a glob"}
        return {**kept, "anyOf": [exact, glob]}
    return {**kept, **exact}


def _keyed_object(node: dict[str, Any], kind: str, robot: RobotNames) -> dict[str, Any]:
    """A dictionary keyed by names: one property per name, globs by pattern, nothing else."""
    if not robot.names(kind):
        return node  # no names to list: any key, and the compiler has the last word
    value = node.get("additionalProperties", {})
    out = {k: v for k, v in node.items() if k != "additionalProperties"}
    out["properties"] = {name: copy.deepcopy(value) for name in robot.names(kind)}
    if kind in GLOB_KINDS:
        out["patternProperties"] = {GLOB_PATTERN: copy.deepcopy(value)}
    out["additionalProperties"] = False
    out[KEYS_KEY] = kind  # an annotation: which names the keys are (read by _ExampleFilter)
    return out


class _ExampleFilter:
    """The generic schema's examples name the Panda's joints and links; an editor offering
    them for another robot would suggest errors. Wherever a schema can hold names, keep only
    the string examples that are this robot's names (or globs where globs are allowed), else
    its first name where the place is one name; drop structured examples there, which would
    need a validator to check."""

    def __init__(self, schema: dict[str, Any], robot: RobotNames) -> None:
        self.defs: dict[str, Any] = schema.get("$defs", {})
        self.robot = robot
        self._def_kinds: dict[str, frozenset[str]] = {}

    def apply(self, node: Any) -> None:
        if isinstance(node, list):
            for item in node:
                self.apply(item)
            return
        if not isinstance(node, dict):
            return
        if "examples" in node:
            kinds = self.kinds(node)
            if kinds:
                own = self.own_examples(node["examples"], kinds)
                if not own and self.names_directly(node):
                    own = [n for kind in sorted(kinds) for n in self.robot.names(kind)][:1]
                node["examples"] = own
                if not node["examples"]:
                    del node["examples"]
        for key, value in node.items():
            if key != "examples":
                self.apply(value)

    def kinds(self, node: Any) -> frozenset[str]:
        """The kinds of names anywhere under ``node``, following references."""
        if isinstance(node, list):
            return frozenset().union(*(self.kinds(item) for item in node))
        if not isinstance(node, dict):
            return frozenset()
        found: set[str] = {node[KEYS_KEY]} if KEYS_KEY in node else set()
        ref = node.get("$ref")
        if isinstance(ref, str) and ref.startswith("#/$defs/"):
            found |= self.def_kinds(ref[len("#/$defs/") :])
        for key, value in node.items():
            if key not in ("examples", "default"):
                found |= self.kinds(value)
        return frozenset(found)

    def def_kinds(self, name: str) -> frozenset[str]:
        for kind in self.robot.by_kind:
            if name == names_def(kind):
                return frozenset({kind})
        if name not in self._def_kinds:
            self._def_kinds[name] = frozenset()  # a recursive model stops here
            self._def_kinds[name] = self.kinds(self.defs.get(name, {}))
        return self._def_kinds[name]

    def own_examples(self, examples: list[Any], kinds: frozenset[str]) -> list[Any]:
        names = [n for kind in sorted(kinds) for n in self.robot.names(kind)]
        globs = bool(kinds & GLOB_KINDS)
        return [
            e
            for e in examples
            if isinstance(e, str) and (e in names or (globs and re.search(GLOB_PATTERN, e)))
        ]

    @staticmethod
    def names_directly(node: dict[str, Any]) -> bool:
        """Whether ``node`` is a single name (or a glob, or null), not a structure of them."""
        alternatives = [node, *node.get("anyOf", [])]
        refs = [a.get("$ref", "") for a in alternatives]
        return any(r.startswith("#/$defs/robot-") for r in refs) and all(
            r.startswith("#/$defs/robot-") or a.get("type") in ("string", "null")
            for a, r in zip(alternatives[1:], refs[1:], strict=True)
        )
