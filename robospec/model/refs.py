"""String types for the places where a spec names something: a joint, a link, a group, a
controller, a material, ...

Each type carries a ``x-robospec-ref`` marker into the JSON Schema. The markers are how
``robospec schema --for SPEC`` (:mod:`robospec.schema.narrow`) finds every such place without a
hand-kept list of paths: it replaces each marked string (or dictionary key) by the names the
compiled robot really has. In the generic schema the markers are inert annotations.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field

REF_KEY = "x-robospec-ref"

RefKind = Literal[
    "joint",  # an active joint, by its exact name
    "joint-selection",  # an active joint, a group, or a glob over active joints
    "link",  # a link, by its exact name
    "link-pattern",  # a link, or a glob over links
    "link-or-named",  # a link, or a `named_links` attribute
    "mount-link",  # a link, or an empty frame a part's `fold_frames` leaves out
    "material",  # a key of `materials`
    "controller",  # a key of `controllers`
    "control-mode",  # a key of `control_modes`
    "link-state",  # a key of `link_states`
    "keyframe",  # a key of `keyframes`
]

GLOB_KINDS: frozenset[str] = frozenset({"joint-selection", "link-pattern"})
"""Kinds whose places also accept fnmatch globs (``panda_joint[1-7]``, ``*finger``)."""


def _ref(kind: RefKind) -> Any:
    return Field(json_schema_extra={REF_KEY: kind})


JointName = Annotated[str, _ref("joint")]
JointPattern = Annotated[str, _ref("joint-selection")]
LinkName = Annotated[str, _ref("link")]
LinkPattern = Annotated[str, _ref("link-pattern")]
LinkOrNamed = Annotated[str, _ref("link-or-named")]
MountLink = Annotated[str, _ref("mount-link")]
MaterialName = Annotated[str, _ref("material")]
ControllerName = Annotated[str, _ref("controller")]
ControlModeName = Annotated[str, _ref("control-mode")]
LinkStateName = Annotated[str, _ref("link-state")]
KeyframeName = Annotated[str, _ref("keyframe")]
