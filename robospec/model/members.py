"""Task-facing helpers as data: what ManiSkill tasks call on an agent beyond its controllers.

ManiSkill's hand-written agents define ``tcp``, ``tcp_pos``/``tcp_pose``, ``is_grasping``,
``is_static``, ``is_standing``/``is_fallen``, extra proprioception and link attributes such as
``finger1_link`` in Python. Each model here declares one of them; the emitter writes the same
arithmetic ManiSkill's versions do, so tasks get the same numbers.
"""

from __future__ import annotations

import keyword
from typing import Annotated, Literal

from pydantic import AfterValidator, Field, model_validator

from robospec.model import rules
from robospec.model.common import GroupSelection, Number, Pose, StrictModel
from robospec.model.refs import KeyframeName, LinkName, LinkOrNamed
from robospec.model.rules import _not_a_keyword

# an attribute or method name the generated class defines
MEMBER_PATTERN = r"^[A-Za-z_][A-Za-z0-9_]{0,63}$"
# "package.module:attribute" or "package.module:Class.attribute"
_DOTTED = r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*"
PYTHON_REF_PATTERN = rf"^{_DOTTED}:{_DOTTED}$"


# for editors too: the schema says which names are out
NOT_A_KEYWORD_SCHEMA = {"not": {"enum": sorted(keyword.kwlist)}}

# a name the generated class defines (a member, the class itself)
PythonName = Annotated[
    str,
    Field(pattern=MEMBER_PATTERN, json_schema_extra=NOT_A_KEYWORD_SCHEMA),
    AfterValidator(_not_a_keyword),
]
Member = PythonName
PythonRef = Annotated[str, Field(pattern=PYTHON_REF_PATTERN)]

PairOfLinks = Annotated[list[LinkOrNamed], Field(min_length=2, max_length=2)]
Interval = Annotated[list[Number], Field(min_length=2, max_length=2)]


class Tcp(StrictModel):
    """The tool centre point: `self.tcp` and the `tcp_pos`/`tcp_pose` properties.

    With `midpoint`, `tcp_pos` is the midpoint of two links' positions (so100, fetch) and
    `tcp_pose` takes its orientation from `orientation`: a link's, or `midpoint` for the
    mean of the two links' quaternions (as fetch does). Without it, both come from `link`.
    """

    link: LinkOrNamed | None = Field(
        default=None,
        description="The link bound to `self.tcp` (a link or a `named_links` attribute).",
        examples=["gripper_link"],
    )
    midpoint: PairOfLinks | None = Field(
        default=None,
        description="Two links whose midpoint is `tcp_pos`, e.g. the two fingertips.",
        examples=[["l_gripper_finger_link", "r_gripper_finger_link"]],
    )
    orientation: Literal["midpoint"] | LinkOrNamed | None = Field(
        default=None,
        description="With a midpoint: the link whose orientation `tcp_pose` takes, or "
        "`midpoint` for the mean of the two links' orientations.",
        examples=["midpoint", "finger1_link"],
    )

    _complete = model_validator(mode="after")(rules.tcp_complete)


Axis = Literal["+x", "-x", "+y", "-y", "+z", "-z"]


class Finger(StrictModel):
    """One finger of a two-finger grasp check."""

    link: LinkOrNamed = Field(
        description="The finger link, or a `named_links` attribute bound to it.",
        examples=["finger1_link", "panda_leftfinger"],
    )
    opening: Axis = Field(
        description="The axis, in the finger link's frame, along which the finger opens.",
        examples=["+y"],
    )


class Grasping(StrictModel):
    """A two-finger grasp check `is_grasping(object, min_force, max_angle)`: both fingers
    touch the object with at least `min_force` newtons, each contact force within
    `max_angle` degrees of the finger's opening direction."""

    fingers: Annotated[list[Finger], Field(min_length=2, max_length=2)] = Field(
        description="The two fingers, each with its link and opening axis.",
        examples=[
            [{"link": "finger1_link", "opening": "+y"}, {"link": "finger2_link", "opening": "-y"}]
        ],
    )
    min_force: Number = Field(
        default=0.5,
        description="The least contact force that counts, in newtons (the method's default "
        "argument).",
        examples=[0.5],
    )
    max_angle: Number = Field(
        default=85.0,
        description="The largest angle between a contact force and the opening direction, in "
        "degrees (the method's default argument).",
        examples=[85],
    )


class Reset(StrictModel):
    """Where every episode starts: the agent's `reset()` puts the joints at a keyframe.

    ManiSkill's tasks set the joints only of the robots their scene builders know (the Panda,
    Fetch, ...) and leave any other robot where the last episode ended. The noise is drawn as
    those scene builders draw theirs: from the resetting environment's episode RNG, for every
    joint, then kept only on `noise_joints`, so a seeded reset repeats it.
    """

    keyframe: KeyframeName | None = Field(
        default=None,
        description="The keyframe every episode starts at; default: the first keyframe.",
        examples=["rest"],
    )
    qpos_noise: Annotated[Number, Field(ge=0)] = Field(
        default=0.0,
        description="The standard deviation of the Gaussian noise added to the keyframe's "
        "joint positions at each reset, in rad (or m); ManiSkill's tabletop scenes give their "
        "own robots 0.02.",
        examples=[0.02],
    )
    noise_joints: GroupSelection | None = Field(
        default=None,
        description="The joints the noise is added to (the others start exactly at the "
        "keyframe); default: all.",
        examples=["arm"],
    )


class StaticJoints(StrictModel):
    """A second set of joints for `is_static`, with its own threshold (`base_threshold`)."""

    joints: GroupSelection = Field(
        description="The joints, groups or `{all_but: ...}` checked against this threshold.",
        examples=["base"],
    )
    threshold: Number = Field(
        description="The default of the `base_threshold` argument, in rad/s (or m/s).",
        examples=[0.05],
    )


class IsStatic(StrictModel):
    """`is_static(threshold)`: every selected joint's velocity is within `threshold`.

    `base` adds a second threshold argument `base_threshold` for a mobile base (fetch).
    `absolute: false` compares signed velocities, reproducing fetch's upstream check.
    """

    joints: GroupSelection = Field(
        description="The joints whose velocities are checked: joints, groups, globs or "
        "`{all_but: ...}`.",
        examples=["arm", {"all_but": ["base", "gripper"]}],
    )
    threshold: Number = Field(
        default=0.2,
        description="The default of the `threshold` argument, in rad/s (or m/s).",
        examples=[0.2],
    )
    base: StaticJoints | None = Field(
        default=None,
        description="A mobile base checked against its own threshold (`base_threshold`).",
        examples=[{"joints": "base", "threshold": 0.05}],
    )
    absolute: bool = Field(
        default=True,
        description="Compare the velocities' magnitudes; false compares signed velocities, "
        "as fetch's upstream check does.",
        examples=[True],
    )


class HeightBand(StrictModel):
    """A band of root-link heights over the ground, in metres."""

    above: Number | None = Field(
        default=None, description="The root must be higher than this.", examples=[0.5]
    )
    below: Number | None = Field(
        default=None, description="The root must be lower than this.", examples=[1.0]
    )

    _some_bound = model_validator(mode="after")(rules.some_bound)


class IsStanding(StrictModel):
    """`is_standing(ground_height=0)`: the root is within a height band over the ground and,
    with `upright_within`, tilted less than that many radians from upright."""

    height: HeightBand = Field(
        description="The band the root's height must be in.",
        examples=[{"above": 0.5, "below": 1.0}],
    )
    upright_within: Number | None = Field(
        default=None,
        description="The largest tilt from upright, in radians; default: not checked.",
        examples=["pi/6"],
    )


class ContactRule(StrictModel):
    """Links whose contact with anything means the robot has fallen."""

    links: Annotated[list[LinkName], Field(min_length=1)] = Field(
        description="The links that must not touch anything (e.g. a torso).",
        examples=[["torso_link"]],
    )
    force_above: Number = Field(
        description="The contact force that counts as touching, in newtons.", examples=[1.0]
    )


class IsFallen(StrictModel):
    """`is_fallen()`: the root is low (`height`) or links touch something (`contact`)."""

    height: HeightBand | None = Field(
        default=None,
        description="Fallen when the root's height is in this band.",
        examples=[{"below": 0.3}],
    )
    contact: ContactRule | None = Field(
        default=None,
        description="Fallen when these links touch something.",
        examples=[{"links": ["torso_link"], "force_above": 1.0}],
    )

    _exactly_one = model_validator(mode="after")(rules.height_or_contact)


class LinkState(StrictModel):
    """A property reading links' poses (7 numbers: p, q) or linear velocities (3 numbers).

    `links` stacks several links along `stack_dim` (ManiSkill's hands use -2, the
    trifinger -1); `link` reads one link.
    """

    link: LinkOrNamed | None = Field(
        default=None,
        description="The one link to read (or a `named_links` attribute bound to it).",
        examples=["palm_link"],
    )
    links: list[LinkOrNamed] | LinkOrNamed | None = Field(
        default=None,
        description="Several links to read and stack, or a `named_links` attribute holding a list.",
        examples=["tip_links", ["link_3.0_tip", "link_7.0_tip"]],
    )
    quantity: Literal["pose", "linear_velocity"] = Field(
        default="pose",
        description="What to read: the `pose` (position and wxyz quaternion) or the "
        "`linear_velocity`.",
        examples=["pose"],
    )
    stack_dim: Literal[-1, -2] = Field(
        default=-2,
        description="The axis along which several links are stacked.",
        examples=[-2],
    )
    method: bool = Field(
        default=False,
        description="Define a method called with () rather than a property.",
        examples=[True],
    )

    _exactly_one = model_validator(mode="after")(rules.link_or_links)


class AxisLimit(StrictModel):
    """Translation limits of a drive per axis: [lower, upper] in metres; an axis left out
    moves freely."""

    x: Interval | None = Field(
        default=None, description="[lower, upper] along x, in metres.", examples=[[0, 0]]
    )
    y: Interval | None = Field(
        default=None, description="[lower, upper] along y, in metres.", examples=[[0, 0]]
    )
    z: Interval | None = Field(
        default=None, description="[lower, upper] along z, in metres.", examples=[[0, 0]]
    )


class Drive(StrictModel):
    """A closed kinematic loop: a SAPIEN drive between two links (as the Robotiq gripper
    needs), created after the articulation loads, with its x/y/z motion limited."""

    parent: LinkName = Field(
        description="The first link of the drive.", examples=["left_outer_finger"]
    )
    parent_pose: Pose = Field(
        default_factory=Pose,
        description="The drive frame on the first link.",
        examples=[{"p": [0, -0.0189, 0.0441]}],
    )
    child: LinkName = Field(
        description="The second link of the drive.", examples=["left_inner_finger_pad"]
    )
    child_pose: Pose = Field(
        default_factory=Pose,
        description="The drive frame on the second link.",
        examples=[{"p": [0, 0.0103, 0.0141]}],
    )
    limit: AxisLimit = Field(
        # a default the validator builds (as data, not a factory): a frozen schema can hold it
        default={"x": [0.0, 0.0], "y": [0.0, 0.0], "z": [0.0, 0.0]},
        validate_default=True,
        description="Lower/upper translation per axis; axes not named are free. Default: "
        "all three locked at 0.",
        examples=[{"x": [0, 0], "y": [0, 0], "z": [0, 0]}],
    )


class Hooks(StrictModel):
    """Python for what no declaration covers, named as `module:function`.

    Hook functions take the agent as their only argument and run after what the spec
    declares. `methods` adds members to the class (functions become methods; properties,
    staticmethods and other attributes are used as they are).
    """

    after_loading_articulation: PythonRef | None = Field(
        default=None,
        description="A function run after ManiSkill loads the articulation.",
        examples=["my_robots.hooks:after_loading"],
    )
    after_init: PythonRef | None = Field(
        default=None,
        description="A function run at the end of the agent's initialisation.",
        examples=["my_robots.hooks:after_init"],
    )
    methods: dict[
        Member,
        Annotated[
            PythonRef,
            Field(
                description="The Python object that becomes this member of the class.",
                examples=["my_robots.hooks:tcp_height"],
            ),
        ],
    ] = Field(
        default_factory=dict,
        description="Members added to the agent class, by name: functions become methods; "
        "properties and other attributes are used as they are.",
        examples=[{"tcp_height": "my_robots.hooks:tcp_height"}],
    )


NamedLink = LinkName | list[LinkName]
"""A link, or a list of links, bound to an agent attribute."""
