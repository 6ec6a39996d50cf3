"""Stage 3, continued: bind the task-facing helpers and Python references of a spec.

Kept apart from :mod:`robospec.resolve` (controllers, keyframes, cameras) because these are
the members tasks call — tcp, is_grasping, is_static, ... — rather than what ManiSkill's
``BaseAgent`` reads. Every link and joint name is checked here, once.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from robospec.diagnostics import error
from robospec.diagnostics.suggest import did_you_mean
from robospec.model.frozen import AllBut, HeightBand, Spec
from robospec.resolve.python_refs import check_ref
from robospec.resolve.resolved import (
    PythonRef,
    ResolvedDrive,
    ResolvedFallen,
    ResolvedFinger,
    ResolvedGrasping,
    ResolvedHeight,
    ResolvedHooks,
    ResolvedLinkState,
    ResolvedStanding,
    ResolvedStatic,
    ResolvedTcp,
)

if TYPE_CHECKING:
    from robospec.load.source_map import KeyPath
    from robospec.resolve import Resolver

AXES = {"x": 0, "y": 1, "z": 2}
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


class HelperResolver:
    """Resolves the helper sections of ``resolver.spec`` against ``resolver.description``."""

    def __init__(self, resolver: Resolver) -> None:
        self.r = resolver
        self.spec: Spec = resolver.spec

    # -- names ------------------------------------------------------------------------------

    def link_or_named(self, name: str, path: KeyPath) -> str:
        """A link name, or a `named_links` attribute bound to one link."""
        named = self.spec.named_links.get(name)
        if isinstance(named, str):
            return name
        if named is not None:
            self.r.err(path, "RS316", f"named link '{name}' is a list; one link is needed here")
            return name
        assert self.r.description is not None
        if self.r.description.link(name) is None:
            candidates = [*self.r.description.link_names, *self.spec.named_links]
            self.r.err(path, "RS202", f"unknown link '{name}'", did_you_mean(name, candidates))
        return name

    def named_links(self) -> tuple[tuple[str, str | tuple[str, ...]], ...]:
        out: list[tuple[str, str | tuple[str, ...]]] = []
        for attribute, value in self.spec.named_links.items():
            path: KeyPath = ("named_links", attribute)
            if isinstance(value, str):
                self.r.link(value, path)
                out.append((attribute, value))
            else:
                for index, link in enumerate(value):
                    self.r.link(link, (*path, index))
                out.append((attribute, tuple(value)))
        return tuple(out)

    def link_list(self, value: Any) -> list[str]:
        """Links of a selection with globs and ``all_but``, in the description's link order."""
        assert self.r.description is not None
        path: KeyPath = ("disable_gravity",)
        if isinstance(value, AllBut):
            excluded = set(self.r.select_links(value.all_but, (*path, "all_but")))
            return [n for n in self.r.description.link_names if n not in excluded]
        return self.r.select_links(value, path)

    # -- sections ---------------------------------------------------------------------------

    def tcp(self) -> ResolvedTcp | None:
        tcp = self.spec.tcp
        if tcp is None:
            return None
        if isinstance(tcp, str):
            return ResolvedTcp(self.link_or_named(tcp, ("tcp",)))
        link = self.link_or_named(tcp.link, ("tcp", "link")) if tcp.link else None
        midpoint = None
        if tcp.midpoint is not None:
            first, second = (
                self.link_or_named(n, ("tcp", "midpoint", i)) for i, n in enumerate(tcp.midpoint)
            )
            midpoint = (first, second)
        orientation = tcp.orientation
        if orientation is not None and orientation != "midpoint":
            self.link_or_named(orientation, ("tcp", "orientation"))
        return ResolvedTcp(link, midpoint, orientation)

    def grasping(self) -> tuple[ResolvedGrasping, ...]:
        out = []
        for method, check in self.spec.grasping.items():
            fingers = []
            for index, finger in enumerate(check.fingers):
                path: KeyPath = ("grasping", method, "fingers", index, "link")
                link = self.link_or_named(finger.link, path)
                sign = -1 if finger.opening.startswith("-") else 1
                fingers.append(ResolvedFinger(link, AXES[finger.opening[1]], sign))
            out.append(
                ResolvedGrasping(method, (fingers[0], fingers[1]), check.min_force, check.max_angle)
            )
        return tuple(out)

    def qvel_columns(self, selection: Any, path: KeyPath) -> tuple[int, ...]:
        assert self.r.description is not None
        order = {name: i for i, name in enumerate(self.r.description.active_joint_names)}
        return tuple(order[j] for j in self.r.select(selection, path) if j in order)

    def is_static(self) -> ResolvedStatic | None:
        rule = self.spec.is_static
        if rule is None:
            return None
        if self.r.assumed:  # qvel columns follow the description's joint order
            from robospec.resolve import NEEDS_DOWNLOAD

            self.r.err(("is_static",), "RS055", *NEEDS_DOWNLOAD)
            return None
        columns = self.qvel_columns(rule.joints, ("is_static", "joints"))
        base = None
        if rule.base is not None:
            base = self.qvel_columns(rule.base.joints, ("is_static", "base", "joints"))
        return ResolvedStatic(
            columns,
            rule.threshold,
            base,
            rule.base.threshold if rule.base is not None else None,
            rule.absolute,
        )

    def is_standing(self) -> ResolvedStanding | None:
        rule = self.spec.is_standing
        if rule is None:
            return None
        return ResolvedStanding(_height(rule.height), rule.upright_within)

    def is_fallen(self) -> ResolvedFallen | None:
        rule = self.spec.is_fallen
        if rule is None:
            return None
        if rule.height is not None:
            return ResolvedFallen(_height(rule.height))
        assert rule.contact is not None
        links = tuple(
            self.r.link(n, ("is_fallen", "contact", "links", i)) or n
            for i, n in enumerate(rule.contact.links)
        )
        return ResolvedFallen(None, links, rule.contact.force_above)

    def link_states(self) -> tuple[ResolvedLinkState, ...]:
        out = []
        for name, state in self.spec.link_states.items():
            path: KeyPath = ("link_states", name)
            links: tuple[str, ...] | str
            if state.link is not None:
                links, single = (self.link_or_named(state.link, (*path, "link")),), True
            elif isinstance(state.links, str):
                single = False
                links = state.links
                if not isinstance(self.spec.named_links.get(links), list):
                    self.r.err(
                        (*path, "links"),
                        "RS316",
                        f"'{links}' is not a list in named_links",
                        "give a list of links, or name a named_links entry holding a list",
                    )
            else:
                single = False
                links = tuple(
                    self.link_or_named(n, (*path, "links", i))
                    for i, n in enumerate(state.links or [])
                )
            out.append(
                ResolvedLinkState(
                    name, links, single, state.quantity, state.stack_dim, state.method
                )
            )
        return tuple(out)

    def proprioception(self) -> tuple[str, ...]:
        for index, name in enumerate(self.spec.proprioception):
            if name not in self.spec.link_states:
                self.r.err(
                    ("proprioception", index),
                    "RS316",
                    f"'{name}' is not a link_states entry",
                    did_you_mean(name, self.spec.link_states),
                )
        return tuple(self.spec.proprioception)

    def disable_gravity(self) -> tuple[str, ...]:
        if self.spec.disable_gravity is None:
            return ()
        return tuple(self.link_list(self.spec.disable_gravity))

    def drives(self) -> tuple[ResolvedDrive, ...]:
        from robospec.resolve import _pose

        out = []
        for index, drive in enumerate(self.spec.drives):
            path: KeyPath = ("drives", index)
            self.r.link(drive.parent, (*path, "parent"))
            self.r.link(drive.child, (*path, "child"))
            limits = tuple(
                (axis, bounds[0], bounds[1])
                for axis in ("x", "y", "z")
                if (bounds := getattr(drive.limit, axis)) is not None
            )
            out.append(
                ResolvedDrive(
                    drive.parent,
                    _pose(drive.parent_pose),
                    drive.child,
                    _pose(drive.child_pose),
                    limits,
                )
            )
        return tuple(out)

    # -- python -----------------------------------------------------------------------------

    def python_ref(self, text: str, path: KeyPath, kind: Any) -> PythonRef | None:
        checked = check_ref(text, kind)
        if checked.problem is not None:
            self.r.err(path, "RS220", checked.problem, checked.hint)
        return checked.ref

    def base_class(self) -> tuple[PythonRef | None, Any]:
        if self.spec.extends is None:
            return None, None
        checked = check_ref(self.spec.extends, "agent_class")
        if checked.problem is not None:
            self.r.err(("extends",), "RS220", checked.problem, checked.hint)
        return checked.ref, checked.value if checked.ref is not None else None

    def hooks(self) -> ResolvedHooks:
        hooks = self.spec.hooks
        loading = after_init = None
        if hooks.after_loading_articulation is not None:
            loading = self.python_ref(
                hooks.after_loading_articulation,
                ("hooks", "after_loading_articulation"),
                "hook",
            )
        if hooks.after_init is not None:
            after_init = self.python_ref(hooks.after_init, ("hooks", "after_init"), "hook")
        methods = []
        for name, text in hooks.methods.items():
            ref = self.python_ref(text, ("hooks", "methods", name), "member")
            if ref is not None:
                methods.append((name, ref))
        return ResolvedHooks(loading, after_init, tuple(methods))

    def check_members(self) -> None:
        """Each generated member is defined once: two sections must not both define it."""
        spec = self.spec
        sources: dict[str, KeyPath] = {}

        def claim(name: str, path: KeyPath) -> None:
            at = self.r.at_key(path)
            if name in BASE_AGENT_MEMBERS and path[0] != "hooks":
                message = (
                    f"'{name}' is a member of ManiSkill's BaseAgent; a helper cannot replace it"
                )
                self.r.diagnostics.append(error(at, "RS317", message, "choose another name"))
            elif name in sources:
                first = ".".join(str(p) for p in sources[name])
                message = f"agent member '{name}' is also defined by {first}"
                self.r.diagnostics.append(error(at, "RS317", message))
            else:
                sources[name] = path

        for name in spec.named_links:
            claim(name, ("named_links", name))
        if spec.tcp is not None:
            for name in ("tcp", "tcp_pos", "tcp_pose"):
                claim(name, ("tcp",))
        for name in spec.grasping:
            claim(name, ("grasping", name))
        for section in ("is_static", "is_standing", "is_fallen"):
            if getattr(spec, section) is not None:
                claim(section, (section,))
        for name in spec.link_states:
            claim(name, ("link_states", name))
        for name in spec.hooks.methods:
            claim(name, ("hooks", "methods", name))


def _height(band: HeightBand) -> ResolvedHeight:
    return ResolvedHeight(band.above, band.below)
