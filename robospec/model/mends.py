"""What a spec may ask robospec to mend in a copy of its robot description (``description.mend``).

Each field is one mend class and the policies it takes; the derive stage
(:mod:`robospec.derive`) has one module per class that applies it. Declarative only: what to
change is decided by the class, where by the description (only the elements the loaders would
stop at, or read wrongly, are touched), and every change is reported where it was made.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from robospec.model.common import Number, StrictModel

InertiaPolicy = Literal["diagonal", "bound", "balance", "shapes"]
LimitRange = Annotated[list[Number], Field(min_length=2, max_length=2)]


class Mends(StrictModel):
    """Mends robospec applies to a derived copy of the description, which everything
    downstream loads (`register`, `build`, `check`, ...); the file itself is never written.
    Each applied change is reported as a note at the element it changed, and a mend that
    changes nothing is a warning. `robospec new` writes the mends a robot needs. See
    docs/mends.md."""

    xml: Literal["repair"] | None = Field(
        default=None,
        description='`repair`: drop an XML declaration lxml and SAPIEN reject (`version="0.0"`) '
        "and whatever follows the root element (stray text, NUL bytes).",
        examples=["repair"],
    )
    namespaces: Literal["declare"] | None = Field(
        default=None,
        description="`declare`: declare every XML namespace prefix the file uses without "
        "declaring it (`xacro:`, `gazebo:`), which makes the file unreadable as XML.",
        examples=["declare"],
    )
    substitutions: Literal["defaults"] | None = Field(
        default=None,
        description="`defaults`: write each xacro/roslaunch substitution nobody expanded as its "
        "value: `$(optenv NAME default)` as its default, `$(find NAME)` as `package://NAME`.",
        examples=["defaults"],
    )
    packages: Literal["resolve"] | None = Field(
        default=None,
        description="`resolve`: name each mesh and texture by the file robospec found for it "
        "where its URI names no package (`package:///...`) or SAPIEN would find another file.",
        examples=["resolve"],
    )
    mirrors: Literal["copies"] | None = Field(
        default=None,
        description='`copies`: collision meshes mirrored by a negative scale (`scale="1 -1 '
        '1"`), which PhysX cannot build and crashes on at the first contact, are named by a '
        "mirrored copy of the file (written in robospec's cache) with a positive scale.",
        examples=["copies"],
    )
    textures: Literal["drop"] | None = Field(
        default=None,
        description="`drop`: remove `<texture/>` elements without a filename, at which SAPIEN's "
        "URDF parser stops.",
        examples=["drop"],
    )
    transmissions: Literal["drop"] | None = Field(
        default=None,
        description="`drop`: remove the `<transmission>`s SAPIEN's URDF parser cannot read "
        "(SAPIEN never uses a transmission once read).",
        examples=["drop"],
    )
    inertia: InertiaPolicy | list[InertiaPolicy] | None = Field(
        default=None,
        description="How to mend inertias SAPIEN rejects or no rigid body has, tried in order "
        "on each: `diagonal` sets the products of inertia to 0 (when the diagonal alone is "
        "valid); `bound` raises each principal moment to at least m·(2 mm)², a radius of "
        "gyration below any real link's (MuJoCo's boundinertia), keeping the axes; `balance` "
        "sets principal moments that break the triangle inequality to their mean (MuJoCo's "
        "balanceinertia); "
        "`shapes` writes the inertia of a solid box around the link's collision shapes, at "
        "its mass, where the file's is rejected, far too small or missing (MuJoCo's "
        "inertiafromgeom).",
        examples=["diagonal", ["diagonal", "bound"]],
    )
    mass: Literal["bound"] | None = Field(
        default=None,
        description="`bound`: raise every mass below 1 g that SAPIEN would use or replace "
        "(negative, zero beside an inertia, tiny) to 1 g (MuJoCo's boundmass).",
        examples=["bound"],
    )
    separators: Literal["spaces"] | None = Field(
        default=None,
        description='`spaces`: write lists of numbers separated by commas (`rpy="1.57, 0 '
        "0\"`), at which SAPIEN's URDF parser stops, separated by spaces, the numbers as "
        "written (origins, axes, box sizes, mesh scales, colours).",
        examples=["spaces"],
    )
    integers: Literal["round"] | None = Field(
        default=None,
        description='`round`: write whole numbers written as decimals (`width="640.0"`) where '
        "SAPIEN's loader wants an integer.",
        examples=["round"],
    )
    limits: Literal["continuous"] | LimitRange | None = Field(
        default=None,
        description="Revolute and prismatic joints whose `<limit>` lacks lower/upper (SAPIEN "
        "makes such a limit NaN): `continuous` makes such revolute joints continuous; "
        "`[lower, upper]` writes that range for every such joint.",
        examples=["continuous", ["-pi", "pi"]],
    )
    spherical: Literal["hinges"] | None = Field(
        default=None,
        description='`hinges`: write each ball joint (`type="spherical"`, which SAPIEN '
        "cannot load) as three continuous joints about x, y and z, `J_x`, `J_y` and `J_z`, "
        "chained by two massless links.",
        examples=["hinges"],
    )
    mimic: Literal["controller"] | None = Field(
        default=None,
        description="`controller`: remove the URDF's `<mimic>` tags, which PhysX turns into "
        "joints that go NaN within a few steps; drive those joints with a `pd_joint_pos_mimic` "
        "controller instead (`robospec new` writes one).",
        examples=["controller"],
    )
    includes: Literal["inline"] | None = Field(
        default=None,
        description="MJCF. `inline`: write the contents of each `<include>` in its place, "
        "wherever it stands (ManiSkill's loader reads only those directly under `<mujoco>`).",
        examples=["inline"],
    )
    geoms: Literal["drop"] | None = Field(
        default=None,
        description="MJCF. `drop`: remove geoms of types ManiSkill's loader raises on (hfield, "
        "sdf); ManiSkill's scenes bring their own ground.",
        examples=["drop"],
    )
    mesh_names: Literal["mujoco"] | None = Field(
        default=None,
        description="MJCF. `mujoco`: name each unnamed `<mesh>` as MuJoCo does, after its "
        "file without folders (ManiSkill's loader keeps the folders, and its geoms' `mesh=` "
        "names are then unknown to it).",
        examples=["mujoco"],
    )
    asset_names: Literal["first", "last"] | None = Field(
        default=None,
        description="MJCF. Assets (meshes, textures, materials) defined twice under one name, "
        "which MuJoCo refuses: `first` keeps each name's first definition, `last` its last "
        "(what ManiSkill's loader does without a word).",
        examples=["first"],
    )
    angles: Literal["radian"] | None = Field(
        default=None,
        description="MJCF. `radian`: read the model's angles (hinge ranges, `euler`, "
        "`axisangle`) as radians where it gives no `<compiler angle>` (MJCF's default is "
        "degrees): a fragment of a larger model that says radian, as robosuite's grippers.",
        examples=["radian"],
    )
    geom_meshes: Literal["defaults"] | None = Field(
        default=None,
        description="MJCF. `defaults`: write on each geom the `mesh` its `<default>` class "
        "gives it in MuJoCo where ManiSkill's loader reads no such mesh (a root class spelled "
        '`<default class="main">`: the loader raises KeyError, or loads a sphere).',
        examples=["defaults"],
    )
    mesh_scale: Literal["defaults"] | None = Field(
        default=None,
        description="MJCF. `defaults`: write on each `<mesh>` the `scale` its `<default>` "
        "class gives it, which ManiSkill's loader does not read (meshes drawn in millimetres "
        "load a thousand times too large).",
        examples=["defaults"],
    )
    axes: Literal["mujoco"] | None = Field(
        default=None,
        description="MJCF. `mujoco`: write on each hinge and slide joint that writes no `axis` "
        "the axis MuJoCo turns it about (its class's, else `0 0 1`) where ManiSkill's loader "
        "reads none and turns it about x.",
        examples=["mujoco"],
    )
    contype: Literal["conaffinity"] | None = Field(
        default=None,
        description='MJCF. `conaffinity`: geoms with `contype="0"` that MuJoCo still collides '
        "(their conaffinity matches other geoms' contype: the floor) get their conaffinity "
        "as contype, so that ManiSkill's loader, which reads contype only, gives them a "
        "collision shape.",
        examples=["conaffinity"],
    )
    freejoint: Literal["root"] | None = Field(
        default=None,
        description='MJCF. `root`: the robot\'s floating root written as `<joint type="free">` '
        "becomes the `<freejoint/>` ManiSkill's loader reads.",
        examples=["root"],
    )
    bodies: Literal["merge"] | None = Field(
        default=None,
        description="MJCF. `merge`: merge each body without a joint below the robot's root "
        "into its parent (what it holds moves up, posed as it was; inertials combined), so "
        "that a robot of more than 30 bodies fits the collision bits ManiSkill's loader "
        "gives each body.",
        examples=["merge"],
    )
    orientations: Literal["quat"] | None = Field(
        default=None,
        description="MJCF. `quat`: write each body and geom frame ManiSkill's loader reads "
        "turned otherwise than MuJoCo (`euler`, `xyaxes`, `zaxis`) as the `quat` MuJoCo "
        "computes for it.",
        examples=["quat"],
    )
