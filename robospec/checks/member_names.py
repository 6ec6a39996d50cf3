"""RS317: each member the generated agent defines is defined once, and replaces none of
ManiSkill's ``BaseAgent``.

Passing::

    tcp: panda_hand_tcp
    named_links:
      hand_link: panda_hand

Failing (RS317: tcp already defines the agent's tcp_pos)::

    tcp: panda_hand_tcp
    named_links:
      tcp_pos: panda_hand

Hooks' ``methods`` may replace a ``BaseAgent`` member on purpose; no other section may.
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import MEMBER_DEFINED_TWICE
from robospec.load.source_map import KeyPath

# BaseAgent's own members (mani-skill 3.0.1): a declared helper must not replace one of them.
# is_grasping and is_static are absent on purpose: BaseAgent leaves them for agents to define.
BASE_AGENT_MEMBERS = frozenset(
    """_after_init _after_loading_articulation _agent_idx _control_freq _control_mode
    _controller_configs _default_control_mode _load_articulation _sensor_configs action_space
    before_simulation_step build_separate control_mode controller controllers device
    disable_self_collisions fix_root_link get_controller_state get_proprioception get_state
    keyframes load_multiple_collisions mjcf_path reset robot robot_link_names scene sensors
    set_action set_control_mode set_controller_state set_state single_action_space
    supported_control_modes uid urdf_config urdf_path""".split()
)


def check(context: CheckContext) -> Iterator[Diagnostic]:
    defined: dict[str, KeyPath] = {}
    for name, path in defined_members(context):
        at = context.key(path)
        if name in BASE_AGENT_MEMBERS and path[0] != "hooks":
            message = f"'{name}' is a member of ManiSkill's BaseAgent; a helper cannot replace it"
            yield error(at, MEMBER_DEFINED_TWICE, message, "choose another name")
        elif name in defined:
            first = ".".join(str(p) for p in defined[name])
            yield error(
                at, MEMBER_DEFINED_TWICE, f"agent member '{name}' is also defined by {first}"
            )
        else:
            defined[name] = path


def defined_members(context: CheckContext) -> Iterator[tuple[str, KeyPath]]:
    """Each member a section of the spec defines, with the key that defines it."""
    spec = context.spec
    for name in spec.named_links:
        yield name, ("named_links", name)
    if spec.tcp is not None:
        # a midpoint tcp without a link binds no self.tcp
        linked = isinstance(spec.tcp, str) or getattr(spec.tcp, "link", None) is not None
        for name in ("tcp", "tcp_pos", "tcp_pose") if linked else ("tcp_pos", "tcp_pose"):
            yield name, ("tcp",)
    for name in spec.grasping:
        yield name, ("grasping", name)
    for section in ("is_static", "is_standing", "is_fallen"):
        if getattr(spec, section) is not None:
            yield section, (section,)
    for name in spec.link_states:
        yield name, ("link_states", name)
    for name in spec.hooks.methods:
        yield name, ("hooks", "methods", name)
