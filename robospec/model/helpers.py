"""Task-facing helpers as data: what ManiSkill tasks call on an agent beyond its controllers.

ManiSkill's hand-written agents define ``tcp``, ``tcp_pos``/``tcp_pose``, ``is_grasping``,
``is_static``, ``is_standing``/``is_fallen``, extra proprioception and link attributes such as
``finger1_link`` in Python. Each model here declares one of them; the emitter writes the same
arithmetic ManiSkill's versions do, so tasks get the same numbers.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from robospec.model.common import GroupSelection, Number, Pose, StrictModel
from robospec.model.refs import LinkName, LinkOrNamed

# an attribute or method name the generated class defines
MEMBER_PATTERN = r"^[A-Za-z_][A-Za-z0-9_]{0,63}$"
# "package.module:attribute" or "package.module:Class.attribute"
_DOTTED = r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*"
PYTHON_REF_PATTERN = rf"^{_DOTTED}:{_DOTTED}$"

Member = Annotated[str, Field(pattern=MEMBER_PATTERN)]
PythonRef = Annotated[
    str, Field(pattern=PYTHON_REF_PATTERN, examples=["my_robots.hooks:after_init"])
]


class Tcp(StrictModel):
    """The tool centre point: ``self.tcp`` and the ``tcp_pos``/``tcp_pose`` properties.

    With ``midpoint``, ``tcp_pos`` is the midpoint of two links' positions (so100, fetch) and
    ``tcp_pose`` takes its orientation from ``orientation``: a link's, or ``midpoint`` for the
    mean of the two links' quaternions (as fetch does). Without it, both come from ``link``.
    """

    link: LinkOrNamed | None = Field(default=None, description="the link bound to `self.tcp`")
    midpoint: Annotated[list[LinkOrNamed], Field(min_length=2, max_length=2)] | None = Field(
        default=None, description="two links whose midpoint is tcp_pos"
    )
    orientation: Literal["midpoint"] | LinkOrNamed | None = Field(
        default=None,
        description="tcp_pose orientation with a midpoint: a link, or 'midpoint' for the mean "
        "of the two links' quaternions",
    )

    @model_validator(mode="after")
    def _complete(self) -> Tcp:
        if self.link is None and self.midpoint is None:
            raise ValueError("give a link, a midpoint, or both")
        if self.midpoint is not None and self.orientation is None:
            raise ValueError("a midpoint tcp needs an orientation: a link name or 'midpoint'")
        if self.midpoint is None and self.orientation is not None:
            raise ValueError("orientation is only for a midpoint tcp")
        return self


Axis = Literal["+x", "-x", "+y", "-y", "+z", "-z"]


class Finger(StrictModel):
    """One finger of a two-finger grasp check."""

    link: LinkOrNamed = Field(description="the finger link, or a name from `named_links`")
    opening: Axis = Field(description="the axis in the finger link's frame it opens along")


class Grasping(StrictModel):
    """A two-finger grasp check ``is_grasping(object, min_force, max_angle)``: both fingers
    touch the object with at least ``min_force`` newtons, each contact force within
    ``max_angle`` degrees of the finger's opening direction."""

    fingers: Annotated[list[Finger], Field(min_length=2, max_length=2)]
    min_force: Number = Field(default=0.5, description="newtons; the method's default argument")
    max_angle: Number = Field(default=85.0, description="degrees; the method's default argument")


class StaticJoints(StrictModel):
    joints: GroupSelection
    threshold: Number = Field(description="the keyword argument's default")


class IsStatic(StrictModel):
    """``is_static(threshold)``: every selected joint's velocity is within ``threshold``.

    ``base`` adds a second threshold argument ``base_threshold`` for a mobile base (fetch).
    ``absolute: false`` compares signed velocities, reproducing fetch's upstream check.
    """

    joints: GroupSelection = Field(description="joints, groups or {all_but: ...}")
    threshold: Number = 0.2
    base: StaticJoints | None = None
    absolute: bool = True


class HeightBand(StrictModel):
    above: Number | None = Field(default=None, description="root height must be above this")
    below: Number | None = Field(default=None, description="root height must be below this")

    @model_validator(mode="after")
    def _some_bound(self) -> HeightBand:
        if self.above is None and self.below is None:
            raise ValueError("give above, below, or both")
        return self


class IsStanding(StrictModel):
    """``is_standing(ground_height=0)``: the root is within a height band over the ground and,
    with ``upright_within``, tilted less than that many radians from upright."""

    height: HeightBand
    upright_within: Number | None = Field(default=None, description="radians from upright")


class ContactRule(StrictModel):
    links: Annotated[list[LinkName], Field(min_length=1)]
    force_above: Number = Field(description="newtons")


class IsFallen(StrictModel):
    """``is_fallen()``: the root is low (``height``) or links touch something (``contact``)."""

    height: HeightBand | None = None
    contact: ContactRule | None = None

    @model_validator(mode="after")
    def _exactly_one(self) -> IsFallen:
        if (self.height is None) == (self.contact is None):
            raise ValueError("give exactly one of height and contact")
        return self


class LinkState(StrictModel):
    """A property reading links' poses (7 numbers: p, q) or linear velocities (3 numbers).

    ``links`` stacks several links along ``stack_dim`` (ManiSkill's hands use -2, the
    trifinger -1); ``link`` reads one link.
    """

    link: LinkOrNamed | None = None
    links: list[LinkOrNamed] | LinkOrNamed | None = Field(
        default=None, description="link names, or a name from `named_links` holding a list"
    )
    quantity: Literal["pose", "linear_velocity"] = "pose"
    stack_dim: Literal[-1, -2] = -2
    method: bool = Field(
        default=False, description="a method called with () rather than a property"
    )

    @model_validator(mode="after")
    def _exactly_one(self) -> LinkState:
        if (self.link is None) == (self.links is None):
            raise ValueError("give exactly one of link and links")
        return self


class AxisLimit(StrictModel):
    x: Annotated[list[Number], Field(min_length=2, max_length=2)] | None = None
    y: Annotated[list[Number], Field(min_length=2, max_length=2)] | None = None
    z: Annotated[list[Number], Field(min_length=2, max_length=2)] | None = None


class Drive(StrictModel):
    """A closed kinematic loop: a SAPIEN drive between two links (as the Robotiq gripper
    needs), created after the articulation loads, with its x/y/z motion limited."""

    parent: LinkName = Field(description="first link")
    parent_pose: Pose = Field(default_factory=Pose, description="drive frame on the first link")
    child: LinkName = Field(description="second link")
    child_pose: Pose = Field(default_factory=Pose, description="drive frame on the second link")
    limit: AxisLimit = Field(
        default_factory=lambda: AxisLimit(x=[0.0, 0.0], y=[0.0, 0.0], z=[0.0, 0.0]),
        description="lower/upper translation per axis; axes not named are free. "
        "Default: all three locked at 0",
    )


class Hooks(StrictModel):
    """Python for what no declaration covers, named as ``module:function``.

    Hook functions take the agent as their only argument and run after what the spec
    declares. ``methods`` adds members to the class (functions become methods; properties,
    staticmethods and other attributes are used as they are).
    """

    after_loading_articulation: PythonRef | None = None
    after_init: PythonRef | None = None
    methods: dict[Member, PythonRef] = Field(default_factory=dict)


NamedLink = LinkName | list[LinkName]
"""A link, or a list of links, bound to an agent attribute."""
