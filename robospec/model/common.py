"""Value types shared by the spec models: numbers as safe arithmetic, poses, joint selections."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    PlainSerializer,
    PlainValidator,
    WithJsonSchema,
)

from robospec.model.refs import JointPattern, LinkPattern
from robospec.model.rules import _to_number, origin

NUMBER_SCHEMA: dict[str, Any] = {
    "anyOf": [
        {"type": "number"},
        {
            "type": "string",
            "pattern": r"^[0-9pitauPIe+\-*/(). ]+$",
            "description": "arithmetic over numbers and pi, e.g. '-5*pi/8'",
        },
    ]
}


# a plain validator: it does all of a float's validation itself, since pydantic's would turn
# the WrittenNumber it returns (the float with the spec's text) into a plain float; dumped,
# it is the float (pydantic's float serializer warns on a subclass)
_VALIDATE, _DUMP = PlainValidator(_to_number), PlainSerializer(float, return_type=float)
Number = Annotated[float, _VALIDATE, _DUMP, WithJsonSchema(NUMBER_SCHEMA)]
"""A float, also accepted as safe arithmetic text such as ``pi/2`` or ``-5*pi/8``."""

# Number's schema is fixed by WithJsonSchema, so a described variant needs its own
ValueByName = Annotated[
    float,
    _VALIDATE,
    _DUMP,
    WithJsonSchema({**NUMBER_SCHEMA, "description": "The value for the joints this name selects."}),
]
# the map first, as JointValues (robospec.model.spec) says why
PerJoint = dict[JointPattern, ValueByName] | Number | list[Number]
"""One value for every joint, one per joint in order, or by joint/group name."""

JointSelection = JointPattern | list[JointPattern]
"""A joint name, a glob over active joints (``panda_joint[1-7]``, ``*``), a group, or a list."""

LinkPatterns = LinkPattern | list[LinkPattern]
"""A link name or a glob over links (``panda_*finger``), or a list of them."""


class StrictModel(BaseModel):
    """Every spec model: unknown keys are errors, instances are immutable."""

    # defer_build: `validate` runs the frozen schema (robospec.model.frozen); these models
    # build theirs only when asked (the JSON Schema, the freezer, the importer)
    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)


Vector3 = Annotated[list[Number], Field(min_length=3, max_length=3)]
Quaternion = Annotated[list[Number], Field(min_length=4, max_length=4)]


class Pose(StrictModel):
    """A pose: a position `p` and an orientation, given either as a wxyz quaternion `q` or
    as roll-pitch-yaw angles `rpy` (neither: no rotation)."""

    p: Vector3 = Field(
        default_factory=origin,
        description="Position [x, y, z] in metres.",
        examples=[[0.0, 0.0, 0.04]],
    )
    q: Quaternion | None = Field(
        default=None,
        description="Orientation as a unit quaternion [w, x, y, z]; leave out for no rotation.",
        examples=[[1, 0, 0, 0]],
    )
    rpy: Vector3 | None = Field(
        default=None,
        description="Orientation as roll, pitch and yaw about the fixed x, y and z axes, in "
        "radians; an alternative to `q`.",
        examples=[[0, "pi/2", 0]],
    )


class AllBut(StrictModel):
    """Every active joint except the ones selected: `{all_but: gripper}`."""

    all_but: JointSelection = Field(
        description="The joints, globs or groups to leave out.",
        examples=["gripper", ["panda_finger_joint1", "panda_finger_joint2"]],
    )


class AllLinksBut(AllBut):
    """Every link except the ones selected: `{all_but: base_link}`."""

    all_but: LinkPatterns = Field(
        description="The links or link globs to leave out.",
        examples=["panda_link0", ["root", "*_base"]],
    )


GroupSelection = JointSelection | AllBut
"""A joint selection, or ``{all_but: ...}`` for every active joint except some."""

LinkSelection = LinkPatterns | AllLinksBut
"""Link names or globs, or ``{all_but: ...}`` for every link except some."""
