"""What `robospec import` reads off an agent class: plain, frozen records, no ManiSkill types.

Values inside records are Python scalars, tuples (for sequences) and dicts (only for a
controller's ``mimic`` and ``delta_solver_config``), so the later stages need neither numpy nor
torch nor ManiSkill.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, Literal

from robospec.geometry import Quaternion, Vector
from robospec.model.controller_kinds import ControllerKind, controller_kind

ALL_JOINTS = "*"
"""Stands for "every active joint" when the description is not installed, so the joints an
agent takes from ``self.robot.active_joints`` cannot be named."""


@dataclass(frozen=True)
class SourceRef:
    """A place in the agent's Python source, shown relative to its package root."""

    file: str
    line: int = 1
    column: int = 1


@dataclass(frozen=True)
class ControllerRecord:
    type: str  # the spec's type name, e.g. "pd_joint_pos"
    joints: tuple[str, ...]
    # every other init field of the ManiSkill config, in dataclass order
    fields: tuple[tuple[str, Any], ...]
    # the fields whose value equals the config class's default
    defaults: frozenset[str] = frozenset()

    def get(self, name: str) -> Any:
        return dict(self.fields).get(name)

    @property
    def kind(self) -> ControllerKind:
        """What its ``type`` is (:mod:`robospec.model.controller_kinds`)."""
        return controller_kind(self.type)

    @property
    def key(self) -> str:
        """Identity for de-duplication: equal records are one spec controller."""
        return repr((self.type, self.joints, self.fields))


@dataclass(frozen=True)
class ModeRecord:
    name: str
    # (mode-dict key, controller); the key is None for a mode that is a single config
    entries: tuple[tuple[str | None, ControllerRecord], ...]
    balance_passive_force: bool | None = None

    @property
    def single(self) -> bool:
        return len(self.entries) == 1 and self.entries[0][0] is None


@dataclass(frozen=True)
class KeyframeRecord:
    name: str
    p: Vector
    q: Quaternion
    qpos: tuple[float, ...] | None
    qvel: tuple[float, ...] | None


@dataclass(frozen=True)
class CameraRecord:
    uid: str
    mount: str | None
    p: Vector
    q: Quaternion
    width: int
    height: int
    fov: float | None
    intrinsic: tuple[tuple[float, ...], ...] | None
    near: float
    far: float
    shader_pack: str


@dataclass(frozen=True)
class JointFacts:
    """What the installed description says about one active joint."""

    name: str
    lower: float | None
    upper: float | None
    mimic: bool = False  # a URDF mimic joint (it follows another; no controller drives it)


# -- what _after_init / _after_loading_articulation do (robospec.importer.afterinit) ---------


@dataclass(frozen=True)
class CollisionRecord:
    links: tuple[str, ...]
    group: int
    bit: int
    value: int


@dataclass(frozen=True)
class FingerRecord:
    attribute: str  # the named link (agent attribute) of the finger
    opening: str  # "+y", "-x", ...


@dataclass(frozen=True)
class GraspingRecord:
    method: str
    fingers: tuple[FingerRecord, FingerRecord]
    min_force: float
    max_angle: float


@dataclass(frozen=True)
class TcpRecord:
    link: str | None  # the link bound to self.tcp
    midpoint: tuple[str, str] | None = None  # named-link attributes
    orientation: str | None = None  # "midpoint" or a named-link attribute


@dataclass(frozen=True)
class HookFacts:
    """What the hooks do that a spec can say, and what they do that it cannot."""

    named_links: tuple[tuple[str, str | tuple[str, ...]], ...] = ()
    tcp: TcpRecord | None = None
    collision_rules: tuple[CollisionRecord, ...] = ()
    grasping: tuple[GraspingRecord, ...] = ()
    # members whose every statement the spec reproduces
    reproduced: frozenset[str] = frozenset()
    # hook name → the statements left out (shown briefly)
    left_out: tuple[tuple[str, tuple[str, ...]], ...] = ()


@dataclass(frozen=True)
class AgentRecord:
    module: str
    class_name: str
    uid: str
    source: SourceRef
    description_kind: Literal["urdf", "mjcf"]
    description_path: str  # the file ManiSkill loads, as an absolute path
    description_file: str | None  # the file on this machine, when it is installed
    fix_root_link: bool
    load_multiple_collisions: bool
    disable_self_collisions: bool
    materials: tuple[tuple[str, tuple[tuple[str, Any], ...]], ...]
    link_rules: tuple[tuple[str, tuple[tuple[str, Any], ...]], ...]
    keyframes: tuple[KeyframeRecord, ...]
    modes: tuple[ModeRecord, ...]
    cameras: tuple[CameraRecord, ...]
    asset_download_ids: tuple[str, ...]
    # methods and properties of the class (below BaseAgent) that a spec does not reproduce
    unreproduced: tuple[str, ...]
    # what could not be read or expressed (already reported as diagnostics), for the header
    not_imported: tuple[str, ...] = ()
    # spec placeholders and the absolute folders they stand for
    asset_roots: tuple[tuple[str, str], ...] = ()
    # facts from the installed description; None when it is not installed
    active_joints: tuple[JointFacts, ...] | None = None
    link_names: tuple[str, ...] | None = None
    # where things are defined in the agent's source, for diagnostics
    controllers_at: SourceRef | None = None
    urdf_config_at: SourceRef | None = None
    # the source files of the class and its bases below BaseAgent: (shown path, lines)
    sources: tuple[tuple[str, tuple[str, ...]], ...] = field(default=(), compare=False)
    # what the class's hooks do that the spec reproduces (named links, tcp, collision bits)
    hooks: HookFacts = field(default_factory=HookFacts)

    def locate(self, literal: str, default: SourceRef | None = None) -> SourceRef:
        """Where ``literal`` first appears in the agent's source: quoted (``"ee_align"``) or
        as a keyword (``thumnb_L2=dict(...)``)."""
        pattern = re.compile(
            r"""(["'])""" + re.escape(literal) + r"\1|\b" + re.escape(literal) + r"\s*=(?!=)"
        )
        for file, lines in self.sources:
            for number, line in enumerate(lines, start=1):
                match = pattern.search(line)
                if match is not None:
                    return SourceRef(file, number, match.start() + 1)
        return default or self.source

    @property
    def active_joint_names(self) -> tuple[str, ...] | None:
        if self.active_joints is None:
            return None
        return tuple(j.name for j in self.active_joints)
