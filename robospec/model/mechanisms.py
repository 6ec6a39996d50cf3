"""Mechanisms as they are built: closed linkages, a drivable planar base, touch sensors.

A PhysX articulation is a tree, and ManiSkill's agents add in Python what a tree cannot say:
the Robotiq agents close each four-bar with a drive between two links (``scene.create_drive``,
all limits zero) and leave the linkage's other joints passive; the guide's mobile base is three
joints added above the base link and driven by ``pd_base_vel``, the wheels kept off the floor;
the tactile Allegro hand reads its force-sensing links through contact queries. Each model here
declares one of them as data.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from robospec.model.common import LinkPatterns, Number, Pose, StrictModel, Vector3
from robospec.model.names import NAME_PATTERN
from robospec.model.refs import LinkName

# -- closed loops ----------------------------------------------------------------------------

Meeting = Annotated[
    Vector3 | Pose,
    Field(
        description="Where the loop closes on this link, in the link's frame: a point "
        "[x, y, z] (the links turn freely about it, a pin) or a frame {p, q} (with `weld`).",
        examples=[[0, 0.0376, 0.043]],
    ),
]


class Loop(StrictModel):
    """A closed kinematic loop (a four-bar linkage, an MJCF `connect` or `weld`): two links
    that meet at a point. The agent closes it after loading with a drive between the two
    links whose translation limits are all zero (as ManiSkill's Robotiq agents do, on the CPU
    and the GPU), and the loop's joints that no controller drives are passive: they follow
    the linkage."""

    links: Annotated[list[LinkName], Field(min_length=2, max_length=2)] = Field(
        description="The two links the loop joins (neither the other's parent or child).",
        examples=[["left_inner_knuckle", "left_inner_finger"]],
    )
    at: Annotated[list[Meeting], Field(min_length=2, max_length=2)] = Field(
        description="Where they meet: the same point written in each link's frame, the first "
        "link's first. `robospec new` computes them from the description.",
        examples=[[[0, 0.0376, 0.043], [0, -0.0179, 0.0065]]],
    )
    weld: bool = Field(
        default=False,
        description="Also lock the two frames' relative rotation (an MJCF `weld`); default: "
        "the links turn freely about the point (an MJCF `connect`, a four-bar's pin).",
        examples=[False],
    )


# -- a planar mobile base ----------------------------------------------------------------------

JointNameText = Annotated[str, Field(pattern=NAME_PATTERN)]
VelocityBounds = Annotated[list[Number], Field(min_length=3, max_length=3)]


class MobileBase(StrictModel):
    """A drivable planar base, as ManiSkill's guide builds one: robospec adds to a derived copy
    of the description a slide along x, a slide along y and a hinge about z above the base
    link (replacing a URDF `planar` or `floating` root joint, or an MJCF free joint), drives
    them with one `pd_base_vel` controller joined to every control mode (the action: forward
    and sideways speed in the base's frame, and turning speed), and takes the wheels out of
    the floor's collisions (collision group 2, bit 30, which ManiSkill's scenes set on the
    ground). The wheels' own joints are then passive, or fixed."""

    link: LinkName | None = Field(
        default=None,
        description="The base link the joints are added above; default: the robot's root, "
        "or the link the root moves by its only joint when that is `planar` or `floating`.",
        examples=["base_link"],
    )
    height: Number = Field(
        default=0.0,
        description="How high above the floor the base link rides (m): where the slides lie. "
        "ManiSkill's scenes load a fixed-root robot at the origin, so a robot whose base link "
        "is above its wheels rides at the base link's height (`robospec new` measures it).",
        examples=[0.48],
    )
    wheels: LinkPatterns = Field(
        default_factory=list,
        description="Links that touch the floor (wheels, casters), names or globs: they stop "
        "colliding with it.",
        examples=[["*_wheel_link", "caster_*"]],
    )
    wheel_joints: Literal["passive", "fixed"] = Field(
        default="passive",
        description="What becomes of the joints that move only wheels: `passive` (they turn "
        "freely, no controller needed) or `fixed` (welded in the derived copy: fewer joints "
        "to simulate). Ball joints are always fixed (ManiSkill loads none).",
        examples=["fixed"],
    )
    joints: Annotated[list[JointNameText], Field(min_length=3, max_length=3)] = Field(
        default=["base_x_joint", "base_y_joint", "base_yaw_joint"],
        description="Names of the three joints added: the x slide, the y slide, the z hinge.",
        examples=[["root_x_axis_joint", "root_y_axis_joint", "root_z_rotation_joint"]],
    )
    controller: Annotated[str, Field(pattern=NAME_PATTERN)] = Field(
        default="base",
        description="The name of the `pd_base_vel` controller, and of its entry in every "
        "control mode.",
        examples=["base"],
    )
    lower: VelocityBounds = Field(
        default=[-1.0, -1.0, -3.14],
        description="Lowest commands: forward and sideways speed (m/s), turning speed (rad/s).",
        examples=[[-1, -1, -3.14]],
    )
    upper: VelocityBounds = Field(
        default=[1.0, 1.0, 3.14],
        description="Highest commands, as `lower`.",
        examples=[[1, 1, 3.14]],
    )
    damping: Number = Field(
        default=1000.0,
        description="The velocity drives' damping (ManiSkill's Fetch: 1000).",
        examples=[1000],
    )
    force_limit: Number = Field(
        default=500.0,
        description="The velocity drives' force limit (ManiSkill's Fetch: 500).",
        examples=[500],
    )


# -- touch sensors ---------------------------------------------------------------------------


class Touch(StrictModel):
    """Force-sensing links whose contact impulses the agent reads, as ManiSkill's tactile
    Allegro hand does: `get_fsr_impulse()` (each link's total contact impulse, shape
    [envs, links, 3]) and `get_fsr_obj_impulse(obj)` (the impulse between each link and one
    object), through the CPU's contact list or the GPU's contact queries."""

    links: Annotated[list[LinkName], Field(min_length=1)] = Field(
        description="The sensing links, in the order their readings come.",
        examples=[["link_base_fsr", "link_0.0_fsr", "link_14.0_fsr"]],
    )
    proprioception: bool = Field(
        default=False,
        description="Add the readings' magnitudes to the robot's proprioception as "
        "`fsr_impulse` (one number per link), as ManiSkill's tactile hand does.",
        examples=[True],
    )
