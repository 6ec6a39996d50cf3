"""The resolved robot: a spec with every reference bound to the description, ready to emit.

Everything here is plain, frozen data in ManiSkill's own terms (joint-name lists, ordered qpos
arrays, ``urdf_config`` dicts). The emitter reads only this.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal


@dataclass(frozen=True)
class FileRef:
    """A file the generated agent names: in ManiSkill's assets, or a file on disk."""

    kind: Literal["maniskill_assets", "file"]
    relative: str  # for maniskill_assets: the path below the asset folder
    absolute: Path  # where it is on this machine
    # a xacro expansion: the URDF text the generated package must carry as a file
    generated_text: str | None = None


@dataclass(frozen=True)
class ResolvedController:
    name: str
    type: str
    # ManiSkill config keyword arguments, in emission order; FileRef values name files
    kwargs: tuple[tuple[str, Any], ...]
    # the spec group its joints were given as, when exactly one group
    joints_group: str | None = None

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(dict(self.kwargs)["joint_names"])


@dataclass(frozen=True)
class ResolvedMode:
    name: str
    # group -> controller name; None for a single-controller mode
    groups: tuple[tuple[str, str], ...] | None
    controller: str | None = None
    balance_passive_force: bool | None = None


@dataclass(frozen=True)
class ResolvedKeyframe:
    name: str
    p: tuple[float, float, float]
    q: tuple[float, float, float, float]
    qpos: tuple[float, ...] | None
    qvel: tuple[float, ...] | None


@dataclass(frozen=True)
class ResolvedCamera:
    uid: str
    mount: str
    p: tuple[float, float, float]
    q: tuple[float, float, float, float]
    width: int
    height: int
    fov: float | None
    intrinsic: tuple[tuple[float, ...], ...] | None
    near: float
    far: float
    shader_pack: str


@dataclass(frozen=True)
class ResolvedCollisionRule:
    links: tuple[str, ...]
    group: int
    bit: int
    value: int


@dataclass(frozen=True)
class ResolvedRobot:
    uid: str
    class_name: str
    spec_path: str
    description_kind: Literal["urdf", "mjcf"]
    description: FileRef
    fix_root_link: bool
    load_multiple_collisions: bool
    disable_self_collisions: bool
    # ManiSkill's urdf_config: {"_materials": {...}, "link": {...}}; empty when there are none
    urdf_config: dict[str, Any]
    keyframes: tuple[ResolvedKeyframe, ...]
    controllers: tuple[ResolvedController, ...]
    modes: tuple[ResolvedMode, ...]
    cameras: tuple[ResolvedCamera, ...]
    collision_rules: tuple[ResolvedCollisionRule, ...]
    tcp: str | None
    active_joints: tuple[str, ...] = field(default=())
