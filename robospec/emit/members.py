"""Generate the task-facing members of an agent class: tcp, is_grasping, is_static, ...

Each member is written from a template of ordinary Python, parsed with :mod:`ast`; its holes
(upper-case names such as ``FINGER1``) are replaced by constant expressions built from the
resolved robot. Spec text therefore only ever enters as constants, and the arithmetic is
ManiSkill's own, line for line, so tasks get the same numbers from either agent.
"""

from __future__ import annotations

import ast
import textwrap
from typing import Any

from robospec.emit.python_refs import PythonNames
from robospec.emit.values import NO_TYPE_PARAMS, safe_identifier
from robospec.emit.values import const as constant
from robospec.resolve.resolved import (
    ResolvedFallen,
    ResolvedGrasping,
    ResolvedHeight,
    ResolvedLinkState,
    ResolvedRobot,
    ResolvedStanding,
    ResolvedStatic,
)


class _Fill(ast.NodeTransformer):
    def __init__(self, holes: dict[str, ast.expr]) -> None:
        self.holes = holes

    def visit_Name(self, node: ast.Name) -> ast.expr:
        return self.holes.get(node.id, node)


def template(source: str, **holes: ast.expr) -> list[ast.stmt]:
    """Statements of ``source`` with every hole name replaced by its expression."""
    tree = ast.parse(textwrap.dedent(source))
    tree = _Fill(holes).visit(tree)
    return tree.body


def function(name: str, source: str, **holes: ast.expr) -> ast.FunctionDef:
    """A ``def`` from a template, renamed to ``name`` (checked: it may come from a spec)."""
    (node,) = template(source, **holes)
    assert isinstance(node, ast.FunctionDef)
    node.name = identifier(name)
    return node


def identifier(name: str) -> str:
    """``name`` if it is a plain Python identifier, else :class:`UnsafeIdentifier`.

    Every identifier that comes from a spec (class, member and attribute names) passes here:
    the model's patterns allow keywords such as ``class`` or ``None``, which would not parse."""
    return safe_identifier(name)


def self_attribute(name: str) -> ast.Attribute:
    """``self.<name>`` for a member name from a spec."""
    return ast.Attribute(ast.Name("self", ast.Load()), identifier(name), ast.Load())


def link_expr(name: str, robot: ResolvedRobot | None) -> ast.expr:
    """A link by name: ``self.<attribute>`` for one of ``robot``'s named links, else
    ``links_map[name]`` (always, with no robot: before the named links are bound)."""
    if robot is not None and any(attribute == name for attribute, _ in robot.named_links):
        return self_attribute(name)
    (expr,) = template("self.robot.links_map[NAME]", NAME=ast.Constant(name))
    assert isinstance(expr, ast.Expr)
    return expr.value


def links_expr(links: tuple[str, ...] | str, robot: ResolvedRobot) -> ast.expr:
    if isinstance(links, str):  # a named link holding a list
        return self_attribute(links)
    return ast.List([link_expr(n, robot) for n in links], ast.Load())


# -- members -----------------------------------------------------------------------------------


def generate_tcp_members(robot: ResolvedRobot) -> list[ast.stmt]:
    tcp = robot.tcp
    if tcp is None:
        return []
    if tcp.midpoint is None:
        assert tcp.link is not None
        return [
            as_property(
                function(
                    "tcp_pos",
                    """
                    def tcp_pos(self):
                        return self.tcp.pose.p
                    """,
                )
            ),
            as_property(
                function(
                    "tcp_pose",
                    """
                    def tcp_pose(self):
                        return self.tcp.pose
                    """,
                )
            ),
        ]
    first, second = (link_expr(n, robot) for n in tcp.midpoint)
    pos = function(
        "tcp_pos",
        """
        def tcp_pos(self):
            return (FIRST.pose.p + SECOND.pose.p) / 2
        """,
        FIRST=first,
        SECOND=second,
    )
    if tcp.orientation == "midpoint":
        pose = function(
            "tcp_pose",
            """
            def tcp_pose(self):
                p = (FIRST.pose.p + SECOND.pose.p) / 2
                q = (FIRST.pose.q + SECOND.pose.q) / 2
                return Pose.create_from_pq(p=p, q=q)
            """,
            FIRST=first,
            SECOND=second,
        )
    else:
        assert tcp.orientation is not None
        pose = function(
            "tcp_pose",
            """
            def tcp_pose(self):
                return Pose.create_from_pq(self.tcp_pos, ORIENTATION.pose.q)
            """,
            ORIENTATION=link_expr(tcp.orientation, robot),
        )
    return [as_property(pos), as_property(pose)]


def generate_grasping(check: ResolvedGrasping, robot: ResolvedRobot) -> ast.FunctionDef:
    left, right = check.fingers

    def direction(finger: Any) -> ast.expr:
        (stmt,) = template(
            "LINK.pose.to_transformation_matrix()[..., :3, AXIS]",
            LINK=link_expr(finger.link, robot),
            AXIS=ast.Constant(finger.axis),
        )
        assert isinstance(stmt, ast.Expr)
        return stmt.value if finger.sign > 0 else ast.UnaryOp(ast.USub(), stmt.value)

    return function(
        check.method,
        '''
        def is_grasping(self, object, min_force=MIN_FORCE, max_angle=MAX_ANGLE):
            """Both fingers touch the object, with forces along their opening directions."""
            l_contact_forces = self.scene.get_pairwise_contact_forces(LEFT, object)
            r_contact_forces = self.scene.get_pairwise_contact_forces(RIGHT, object)
            lforce = torch.linalg.norm(l_contact_forces, axis=1)
            rforce = torch.linalg.norm(r_contact_forces, axis=1)
            # direction to open the gripper
            ldirection = LEFT_DIRECTION
            rdirection = RIGHT_DIRECTION
            langle = common.compute_angle_between(ldirection, l_contact_forces)
            rangle = common.compute_angle_between(rdirection, r_contact_forces)
            lflag = torch.logical_and(lforce >= min_force, torch.rad2deg(langle) <= max_angle)
            rflag = torch.logical_and(rforce >= min_force, torch.rad2deg(rangle) <= max_angle)
            return torch.logical_and(lflag, rflag)
        ''',
        MIN_FORCE=constant(check.min_force),
        MAX_ANGLE=constant(check.max_angle),
        LEFT=link_expr(left.link, robot),
        RIGHT=link_expr(right.link, robot),
        LEFT_DIRECTION=direction(left),
        RIGHT_DIRECTION=direction(right),
    )


def _columns(indices: tuple[int, ...]) -> ast.expr:
    """``qvel[..., a:b]`` when the columns are contiguous, else ``qvel[..., [i, j]]``."""
    if indices and list(indices) == list(range(indices[0], indices[-1] + 1)):
        index: ast.expr = ast.Slice(ast.Constant(indices[0]), ast.Constant(indices[-1] + 1))
    else:
        index = ast.List([ast.Constant(i) for i in indices], ast.Load())
    return ast.Tuple([ast.Constant(...), index], ast.Load())


def generate_is_static(rule: ResolvedStatic) -> ast.FunctionDef:
    if rule.base_indices is None:
        if rule.absolute:
            return function(
                "is_static",
                """
                def is_static(self, threshold=THRESHOLD):
                    qvel = self.robot.get_qvel()[COLUMNS]
                    return torch.max(torch.abs(qvel), 1)[0] <= threshold
                """,
                THRESHOLD=constant(rule.threshold),
                COLUMNS=_columns(rule.indices),
            )
        return function(
            "is_static",
            """
            def is_static(self, threshold=THRESHOLD):
                qvel = self.robot.get_qvel()[COLUMNS]
                return torch.all(qvel <= threshold, dim=1)
            """,
            THRESHOLD=constant(rule.threshold),
            COLUMNS=_columns(rule.indices),
        )
    body = "body_qvel" if rule.absolute is False else "torch.abs(body_qvel)"
    base = "base_qvel" if rule.absolute is False else "torch.abs(base_qvel)"
    return function(
        "is_static",
        f"""
        def is_static(self, threshold=THRESHOLD, base_threshold=BASE):
            body_qvel = self.robot.get_qvel()[COLUMNS]
            base_qvel = self.robot.get_qvel()[BASE_COLUMNS]
            return torch.all({body} <= threshold, dim=1) & torch.all(
                {base} <= base_threshold, dim=1
            )
        """,
        THRESHOLD=constant(rule.threshold),
        BASE=constant(rule.base_threshold),
        COLUMNS=_columns(rule.indices),
        BASE_COLUMNS=_columns(rule.base_indices),
    )


def _height_test(height: ResolvedHeight, ground: bool) -> ast.expr:
    """``(z > above) & (z < below)`` over the root height, optionally over ``ground_height``."""
    tests: list[ast.expr] = []
    for bound, op in ((height.above, ">"), (height.below, "<")):
        if bound is None:
            continue
        limit = "(BOUND + ground_height)" if ground else "BOUND"
        (stmt,) = template(f"self.robot.pose.p[:, 2] {op} {limit}", BOUND=constant(bound))
        assert isinstance(stmt, ast.Expr)
        tests.append(stmt.value)
    result = tests[0]
    for test in tests[1:]:
        result = ast.BinOp(result, ast.BitAnd(), test)
    return result


def generate_is_standing(rule: ResolvedStanding) -> ast.FunctionDef:
    if rule.upright_within is None:
        return function(
            "is_standing",
            '''
            def is_standing(self, ground_height=0):
                """The root is within the standing height band."""
                return HEIGHT
            ''',
            HEIGHT=_height_test(rule.height, True),
        )
    return function(
        "is_standing",
        '''
        def is_standing(self, ground_height=0):
            """The root is face up (within UPRIGHT radians) and within the height band."""
            target_q = torch.tensor([1, 0, 0, 0], device=self.device)
            inner_prod = (self.robot.pose.q * target_q).sum(axis=1)
            # the angle between the two quaternions
            angle_diff = torch.arccos(2 * (inner_prod**2) - 1)
            aligned = angle_diff < UPRIGHT
            high_enough = HEIGHT
            return aligned & high_enough
        ''',
        UPRIGHT=constant(rule.upright_within),
        HEIGHT=_height_test(rule.height, True),
    )


def generate_is_fallen(rule: ResolvedFallen) -> ast.FunctionDef:
    if rule.height is not None:
        return function(
            "is_fallen",
            '''
            def is_fallen(self):
                """The root is outside the height band of a robot still up."""
                return HEIGHT
            ''',
            HEIGHT=_height_test(rule.height, False),
        )
    return function(
        "is_fallen",
        '''
        def is_fallen(self):
            """One of the links touches something with more than the force limit."""
            forces = self.robot.get_net_contact_forces(LINKS)
            return torch.norm(forces, dim=-1).max(-1).values > FORCE
        ''',
        LINKS=constant(list(rule.contact_links)),
        FORCE=constant(rule.force_above),
    )


def generate_link_state(state: ResolvedLinkState, robot: ResolvedRobot) -> ast.FunctionDef:
    if state.quantity == "pose":
        read = "vectorize_pose(link.pose, device=self.device)"
    else:
        read = "link.linear_velocity"
    if state.single:
        node = function(
            state.name,
            f"""
            def state(self):
                link = LINK
                return {read}
            """,
            LINK=link_expr(state.links[0], robot),
        )
    else:
        node = function(
            state.name,
            f"""
            def state(self):
                return torch.stack([{read} for link in LINKS], dim=DIM)
            """,
            LINKS=links_expr(state.links, robot),
            DIM=constant(state.stack_dim),
        )
    return node if state.method else as_property(node)


def generate_proprioception(
    robot: ResolvedRobot, touch: tuple[ast.expr, ast.expr] | None = None
) -> ast.FunctionDef | None:
    """``get_proprioception`` with the declared link states and the ``touch`` reading
    (key, value)."""
    if not robot.proprioception and touch is None:
        return None
    states = {s.name: s for s in robot.link_states}
    keys: list[ast.expr | None] = []
    values: list[ast.expr] = []
    for name in robot.proprioception:
        state = states[name]
        value: ast.expr = self_attribute(name)
        if state.method:
            value = ast.Call(value, [], [])
        if not state.single:
            count = (
                ast.Call(
                    ast.Name("len", ast.Load()),
                    [links_expr(state.links, robot)],
                    [],
                )
                if isinstance(state.links, str)
                else ast.Constant(len(state.links))
            )
            width = ast.BinOp(count, ast.Mult(), ast.Constant(state.width))
            (stmt,) = template("VALUE.reshape(-1, WIDTH)", VALUE=value, WIDTH=width)
            assert isinstance(stmt, ast.Expr)
            value = stmt.value
        keys.append(ast.Constant(name))
        values.append(value)
    if touch is not None:
        keys.append(touch[0])
        values.append(touch[1])
    return function(
        "get_proprioception",
        '''
        def get_proprioception(self):
            """The default proprioception plus the declared link states and touch readings."""
            obs = super().get_proprioception()
            obs.update(STATES)
            return obs
        ''',
        STATES=ast.Dict(keys, values),
    )


def generate_after_loading_articulation(
    robot: ResolvedRobot, python: PythonNames, mechanisms: list[ast.stmt] | None = None
) -> ast.FunctionDef | None:
    """The method that sets what loading left to do: contact offsets, drives, the statements
    of the robot's ``mechanisms`` (its closed loops), the hook."""
    body: list[ast.stmt] = []
    offset = robot.simulation.contact_offset
    if offset is not None:
        # on the shapes themselves, before the scene is simulated (and, on the GPU, before
        # PhysX copies them): ManiSkill's scene config gives every shape its own 2 cm
        body += template(
            """
            for link in self.robot.links:
                for body in link._bodies:
                    for shape in body.get_collision_shapes():
                        shape.set_contact_offset(OFFSET)
            """,
            OFFSET=constant(offset),
        )
    if robot.armature:
        # the rotor inertia MuJoCo adds to each joint (an MJCF's armature), which a URDF
        # cannot say: on every sub-scene's joint, before the GPU copies them
        body += template(
            """
            for name, armature in ARMATURE.items():
                for joint in self.robot.joints_map[name]._objs:
                    joint.set_armature([armature])
            """,
            ARMATURE=constant(dict(robot.armature)),
        )
    for drive in robot.drives:
        body += template(
            """
            drive = self.scene.create_drive(
                PARENT, sapien.Pose(PARENT_P, PARENT_Q), CHILD, sapien.Pose(CHILD_P, CHILD_Q)
            )
            """,
            PARENT=link_expr(drive.parent, None),
            PARENT_P=constant(list(drive.parent_pose[0])),
            PARENT_Q=constant(list(drive.parent_pose[1])),
            CHILD=link_expr(drive.child, None),
            CHILD_P=constant(list(drive.child_pose[0])),
            CHILD_Q=constant(list(drive.child_pose[1])),
        )
        for axis, lower, upper in drive.limits:
            body += template(
                f"drive.set_limit_{axis}(LOWER, UPPER)",
                LOWER=constant(lower),
                UPPER=constant(upper),
            )
    body += mechanisms or []
    if robot.hooks.after_loading_articulation is not None:
        body += template("HOOK(self)", HOOK=python.expr(robot.hooks.after_loading_articulation))
    if not body:
        return None
    if robot.base is not None:
        body = [*template("super()._after_loading_articulation()"), *body]
    return method("_after_loading_articulation", body)


def generate_after_init_helpers(robot: ResolvedRobot) -> list[ast.stmt]:
    """``_after_init`` statements binding named links and the tcp, and disabling gravity."""
    body: list[ast.stmt] = []
    for attribute, value in robot.named_links:
        target = ast.Attribute(ast.Name("self", ast.Load()), identifier(attribute), ast.Store())
        bound = (
            link_expr(value, None)
            if isinstance(value, str)
            else ast.List([link_expr(v, None) for v in value], ast.Load())
        )
        body.append(ast.Assign([target], bound))
    if robot.tcp is not None and robot.tcp.link is not None:
        target = ast.Attribute(ast.Name("self", ast.Load()), "tcp", ast.Store())
        body.append(ast.Assign([target], link_expr(robot.tcp.link, robot)))
    if robot.disable_gravity:
        body += template(
            """
            for link_name in LINKS:
                self.robot.links_map[link_name].disable_gravity = True
            """,
            LINKS=constant(list(robot.disable_gravity)),
        )
    return body


def method(name: str, body: list[ast.stmt]) -> ast.FunctionDef:
    """``def name(self): body``."""
    args = ast.arguments([], [ast.arg("self")], None, [], [], None, [])
    return ast.FunctionDef(name, args, body, [], None, **NO_TYPE_PARAMS)


def as_property(node: ast.FunctionDef) -> ast.FunctionDef:
    node.decorator_list = [ast.Name("property", ast.Load())]
    return node
