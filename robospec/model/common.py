"""Value types shared by the spec models: numbers as safe arithmetic, poses, joint selections."""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, WithJsonSchema
from pydantic_core import PydanticCustomError

from robospec.expr import ExpressionError, evaluate
from robospec.model.refs import JointPattern, LinkPattern

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


def _to_number(value: Any) -> float:
    if isinstance(value, bool):
        raise PydanticCustomError("number", "expected a number, got a boolean")
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, str):
        try:
            return evaluate(value)
        except ExpressionError as exc:
            raise PydanticCustomError("expression", str(exc)) from None
    raise PydanticCustomError("number", "expected a number or arithmetic over pi")


Number = Annotated[float, BeforeValidator(_to_number), WithJsonSchema(NUMBER_SCHEMA)]
"""A float, also accepted as safe arithmetic text such as ``pi/2`` or ``-5*pi/8``."""

PerJoint = Number | list[Number] | dict[JointPattern, Number]
"""One value for every joint, one per joint in order, or by joint/group name."""

JointSelection = JointPattern | list[JointPattern]
"""A joint name, a glob over active joints (``panda_joint[1-7]``, ``*``), a group, or a list."""

LinkPatterns = LinkPattern | list[LinkPattern]
"""A link name or a glob over links (``panda_*finger``), or a list of them."""


class StrictModel(BaseModel):
    """Every spec model: unknown keys are errors, instances are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class Pose(StrictModel):
    """A pose: position ``p`` and orientation as a wxyz quaternion ``q`` or as ``rpy``."""

    p: Annotated[list[Number], Field(min_length=3, max_length=3)] = Field(
        default_factory=lambda: [0.0, 0.0, 0.0], description="position [x, y, z] in metres"
    )
    q: Annotated[list[Number], Field(min_length=4, max_length=4)] | None = Field(
        default=None, description="orientation as a quaternion [w, x, y, z]"
    )
    rpy: Annotated[list[Number], Field(min_length=3, max_length=3)] | None = Field(
        default=None, description="orientation as roll, pitch, yaw (fixed axes x, y, z) in radians"
    )


class AllBut(StrictModel):
    """Every active joint except the ones selected."""

    all_but: JointSelection = Field(description="joints, globs or groups to leave out")


class AllLinksBut(AllBut):
    """Every link except the ones selected."""

    all_but: LinkPatterns = Field(description="links or globs to leave out")  # type: ignore[assignment]


GroupSelection = JointSelection | AllBut
LinkSelection = LinkPatterns | AllLinksBut
