"""Everything the spec models run while validating, and the behaviour their instances carry.

The pydantic models (:mod:`robospec.model.spec` and its neighbours) use these functions as
their validators and these mixins as bases; the frozen validator
(:mod:`robospec.model.frozen`) calls the very same functions from its pydantic-core schema.
So this module must not import pydantic (only pydantic-core, for its error types): `robospec
validate` runs it without loading pydantic at all.
"""

from __future__ import annotations

import keyword
import math
from typing import Any, Literal

from pydantic_core import PydanticCustomError, PydanticKnownError

from robospec.load.source_map import WrittenNumber
from robospec.model.expressions import ExpressionError, evaluate

# -- field values -------------------------------------------------------------------------


def _to_number(value: Any) -> float:
    """A Number field's whole validation (the name shows in pydantic's error locations,
    ``function-plain[_to_number()]``). It returns the float itself, a :class:`WrittenNumber`
    when the spec's text of the number is known: pydantic's own float validation would turn
    it into a plain float, so this validator does that work and keeps it. ±inf is a number
    (an unbounded limit, as ManiSkill writes them); NaN is not."""
    number = _number(value)
    if math.isnan(number):  # YAML's .nan, TOML's nan, inf - inf
        raise PydanticCustomError("number", "expected a number, got NaN")
    return number


def _number(value: Any) -> float:
    if isinstance(value, bool):
        raise PydanticCustomError("number", "expected a number, got a boolean")
    if isinstance(value, WrittenNumber):
        return value
    if isinstance(value, int):
        return WrittenNumber(float(value), str(value))
    if isinstance(value, float):
        return float(value)
    if isinstance(value, str):
        try:
            return evaluate(value)
        except ExpressionError as exc:
            raise PydanticCustomError("expression", str(exc)) from None
    raise PydanticCustomError("number", "expected a number or arithmetic over pi")


def _not_a_keyword(name: str) -> str:
    # the pattern admits `class` or `None`, which are no names in Python: the generated class
    # could not define them
    if keyword.iskeyword(name):
        raise PydanticCustomError(
            "python_keyword",
            "'{name}' is a Python keyword, not a name",
            {"name": name},
        )
    return name


def greater_than(value: Any, gt: float) -> Any:
    """``Field(gt=...)`` on a value a function made (a Number): the check pydantic would run,
    with its error type, so messages are pydantic's own."""
    if not value > gt:
        raise PydanticKnownError("greater_than", {"gt": gt})
    return value


def greater_than_or_equal(value: Any, ge: float) -> Any:
    """``Field(ge=...)`` on a value a function made, as :func:`greater_than`."""
    if not value >= ge:
        raise PydanticKnownError("greater_than_equal", {"ge": ge})
    return value


def origin() -> list[float]:
    """The default position of a pose."""
    return [0.0, 0.0, 0.0]


# -- whole models (mode="after": they get the validated instance) ---------------------------


def tcp_complete(tcp: Any) -> Any:
    if tcp.link is None and tcp.midpoint is None:
        raise ValueError("give a link, a midpoint, or both")
    if tcp.midpoint is not None and tcp.orientation is None:
        raise ValueError("a midpoint tcp needs an orientation: a link name or 'midpoint'")
    if tcp.midpoint is None and tcp.orientation is not None:
        raise ValueError("orientation is only for a midpoint tcp")
    return tcp


def some_bound(band: Any) -> Any:
    if band.above is None and band.below is None:
        raise ValueError("give above, below, or both")
    return band


def height_or_contact(fallen: Any) -> Any:
    if (fallen.height is None) == (fallen.contact is None):
        raise ValueError("give exactly one of height and contact")
    return fallen


def link_or_links(state: Any) -> Any:
    if (state.link is None) == (state.links is None):
        raise ValueError("give exactly one of link and links")
    return state


def one_description(description: Any) -> Any:
    given = [k for k in ("urdf", "mjcf", "xacro") if getattr(description, k) is not None]
    if len(given) != 1:
        raise ValueError("give exactly one of urdf, mjcf or xacro")
    if description.args and description.xacro is None:
        raise ValueError("args are only for xacro descriptions")
    if getattr(description, "loader", None) is not None and description.mjcf is None:
        raise ValueError("loader is only for mjcf descriptions")
    if getattr(description, "sites", None) and getattr(description, "loader", None) != "mujoco":
        raise ValueError(
            "sites are written as links only when MuJoCo compiles the MJCF: add loader: mujoco"
        )
    return description


def one_part_source(part: Any) -> Any:
    if (part.spec is None) == (part.description is None):
        raise ValueError("give exactly one of spec and description")
    return part


def description_or_base(spec: Any) -> Any:
    if spec.extends is None and spec.description is None:
        raise ValueError("give a description (or extend a Python agent class)")
    # a mobile base brings a mode of its own: a platform with nothing else to control drives
    if spec.extends is None and not spec.control_modes and spec.mobile_base is None:
        raise ValueError("give at least one control mode")
    return spec


# -- behaviour of instances -----------------------------------------------------------------


class DescriptionBehaviour:
    """Which kind of file a description names, and its path.

    (Mixins declare no annotations: pydantic would take them for fields.)"""

    __slots__ = ()

    @property
    def kind(self: Any) -> Literal["urdf", "mjcf", "xacro"]:
        if self.urdf is not None:
            return "urdf"
        return "mjcf" if self.mjcf is not None else "xacro"

    @property
    def path(self: Any) -> str:
        return str(self.urdf or self.mjcf or self.xacro or "")

    @property
    def compiled(self: Any) -> bool:
        """Whether MuJoCo compiles the MJCF into the URDF ManiSkill loads (``loader:
        mujoco``): the robot is then a URDF robot."""
        return self.mjcf is not None and getattr(self, "loader", None) == "mujoco"

    @property
    def loaded_kind(self: Any) -> Literal["urdf", "mjcf"]:
        """The kind of description ManiSkill loads: a xacro's expansion and a compiled MJCF
        are URDFs."""
        return "mjcf" if self.mjcf is not None and not self.compiled else "urdf"


class PartBehaviour:
    """The names a part's defaults give it."""

    __slots__ = ()

    def joint_name(self: Any, name: str) -> str:
        """The fixed joint that mounts part ``name``."""
        return str(self.joint or f"{name}_mount")

    def name_prefix(self: Any, name: str) -> str:
        """What goes before a clashing name of part ``name``."""
        return str(self.prefix or f"{name}_")


class StepResponseBehaviour:
    """Step-response settings for one controller."""

    __slots__ = ()

    def for_controller(self: Any, name: str) -> Any:
        """These settings with ``controllers[name]``'s fields in place of the spec-wide ones."""
        limits = self.controllers.get(name)
        if limits is None:
            return self
        update = {k: getattr(limits, k) for k in limits.model_fields_set}
        return self.model_copy(update=update)
