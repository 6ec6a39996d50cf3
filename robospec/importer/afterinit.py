"""What an agent's ``_after_init`` (and ``_after_loading_articulation``) does, read as data.

ManiSkill's agents bind links to attributes and set collision-group bits in these hooks, in a
few set patterns. The hooks' source (the class's and, through ``super()`` calls, its bases'
within ``mani_skill``) is read with :mod:`ast` and run by a small interpreter that knows only
those patterns:

- ``self.X = sapien_utils.get_obj_by_name(self.robot.get_links(), "name")``,
  ``self.robot.links_map["name"]``, ``get_objs_by_names(self.robot.get_links(), names)`` (names
  may be constants, f-strings, class attributes such as ``self.ee_link_name`` or module
  constants) → a named link (``self.tcp``: the spec's ``tcp``);
- ``LINK.set_collision_group_bit(group, bit_idx, bit)`` (positional or keyword arguments) on
  such a link, also inside ``for`` loops over lists of names or links, or over
  ``self.robot.get_links()`` → the spec's ``collision_rules``;
- local variables holding such values, docstrings, ``pass``, ``super()`` calls.

Every other statement is left out and named, so the import still says that the hook is only
partly reproduced. ``tcp_pos``/``tcp_pose`` and two-finger ``is_grasping`` methods written
exactly as ManiSkill's Panda, Fetch and SO100 write them become the spec's ``tcp`` and
``grasping``. Nothing here loads the robot.
"""

from __future__ import annotations

import ast
import inspect
import re
import sys
import textwrap
from dataclasses import dataclass, field
from typing import Any

from robospec.importer.records import (
    CollisionRecord,
    FingerRecord,
    GraspingRecord,
    HookFacts,
    TcpRecord,
)

HOOKS = ("_after_loading_articulation", "_after_init")
AXES = "xyz"


@dataclass(frozen=True)
class _Link:
    name: str


class _Unknown(Exception):
    """A statement or expression outside the patterns this module knows."""


@dataclass
class _State:
    cls: type
    obj: Any
    link_names: tuple[str, ...] | None
    named: dict[str, Any] = field(default_factory=dict)  # attribute → _Link | list[_Link]
    bits: list[tuple[str, int, int, int]] = field(default_factory=list)  # link, group, bit, value


def read_hooks(cls: type, obj: Any, link_names: tuple[str, ...] | None) -> HookFacts:
    """The hooks of ``cls`` (``obj`` an instance with its own ``__init__`` run, for class
    attributes such as ``self.ee_link_name``) as data; ``link_names``: the description's links
    (None when it is not installed: then a link is any name the hook writes)."""
    state = _State(cls, obj, link_names)
    reproduced: set[str] = set()
    left_out: list[tuple[str, tuple[str, ...]]] = []
    for hook in HOOKS:
        owner = _definer(cls, hook, 0)
        if owner is None:
            continue
        missing = _run_method(state, owner, hook)
        if missing is None:
            missing = [f"{hook} (its source cannot be read)"]
        if missing:
            left_out.append((hook, tuple(missing)))
        else:
            reproduced.add(hook)
    named = dict(state.named)
    tcp_link = named.pop("tcp", None)
    tcp, tcp_members = _tcp(cls, named, tcp_link)
    reproduced |= tcp_members
    grasping = tuple(g for g in (_grasping(cls, named, "is_grasping"),) if g is not None)
    reproduced |= {g.method for g in grasping}
    return HookFacts(
        named_links=tuple(
            (name, value.name if isinstance(value, _Link) else tuple(v.name for v in value))
            for name, value in named.items()
        ),
        tcp=tcp,
        collision_rules=_rules(state.bits),
        grasping=grasping,
        reproduced=frozenset(reproduced),
        left_out=tuple(left_out),
    )


# -- the classes and their sources ---------------------------------------------------------------


def _mro(cls: type) -> list[type]:
    from mani_skill.agents.base_agent import BaseAgent

    mro = list(cls.__mro__)
    return mro[: mro.index(BaseAgent)] if BaseAgent in mro else [cls]


def _definer(cls: type, name: str, start: int) -> type | None:
    """The first class from ``start`` in ``cls``'s MRO (below BaseAgent) defining ``name``."""
    for klass in _mro(cls)[start:]:
        if name in vars(klass):
            return klass
    return None


def _function(klass: type, name: str) -> ast.FunctionDef | None:
    member = vars(klass).get(name)
    if isinstance(member, property):
        member = member.fget
    if not inspect.isfunction(member):
        return None
    try:
        source = textwrap.dedent(inspect.getsource(member))
    except (OSError, TypeError):
        return None
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return None
    node = tree.body[0] if tree.body else None
    return node if isinstance(node, ast.FunctionDef) else None


def _body(function: ast.FunctionDef) -> list[ast.stmt]:
    body = list(function.body)
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]  # the docstring
    return body


# -- the interpreter -----------------------------------------------------------------------------


def _run_method(state: _State, klass: type, hook: str) -> list[str] | None:
    """Run ``klass.<hook>``; the statements it leaves out, or None without a source."""
    function = _function(klass, hook)
    if function is None:
        return None
    missing: list[str] = []
    env: dict[str, Any] = {}
    for stmt in _body(function):
        if _is_super_call(stmt, hook):
            index = _mro(state.cls).index(klass) + 1
            base = _definer(state.cls, hook, index)
            if base is not None:
                found = _run_method(state, base, hook)
                missing += found if found is not None else [f"super().{hook}()"]
            continue
        try:
            _transaction(state, env, [stmt])
        except _Unknown:
            missing.append(_brief(stmt))
    return missing


def _transaction(state: _State, env: dict[str, Any], stmts: list[ast.stmt]) -> None:
    """Run ``stmts``: all of their effects, or (raising _Unknown) none."""
    named, bits, scope = dict(state.named), list(state.bits), dict(env)
    try:
        for stmt in stmts:
            _run(state, env, stmt)
    except _Unknown:
        state.named, state.bits = named, bits
        env.clear()
        env.update(scope)
        raise


def _run(state: _State, env: dict[str, Any], stmt: ast.stmt) -> None:
    if isinstance(stmt, ast.Pass):
        return
    if isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Constant):
        return  # a string as a comment
    if isinstance(stmt, (ast.Assign, ast.AnnAssign)):
        targets = stmt.targets if isinstance(stmt, ast.Assign) else [stmt.target]
        if stmt.value is None or len(targets) != 1:
            raise _Unknown
        value = _eval(state, env, stmt.value)
        _assign(state, env, targets[0], value)
        return
    if isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Call):
        _collision_bit(state, env, stmt.value)
        return
    if isinstance(stmt, ast.For) and not stmt.orelse and isinstance(stmt.target, ast.Name):
        items = _eval(state, env, stmt.iter)
        if not isinstance(items, list):
            raise _Unknown
        for item in items:
            env[stmt.target.id] = item
            for inner in stmt.body:
                _run(state, env, inner)
        return
    raise _Unknown


def _assign(state: _State, env: dict[str, Any], target: ast.expr, value: Any) -> None:
    if isinstance(target, ast.Name):
        env[target.id] = value
        return
    if (
        isinstance(target, ast.Attribute)
        and isinstance(target.value, ast.Name)
        and target.value.id == "self"
    ):
        if isinstance(value, _Link) or (
            isinstance(value, list) and value and all(isinstance(v, _Link) for v in value)
        ):
            state.named[target.attr] = value
            return
    raise _Unknown


def _collision_bit(state: _State, env: dict[str, Any], call: ast.Call) -> None:
    func = call.func
    if not (isinstance(func, ast.Attribute) and func.attr == "set_collision_group_bit"):
        raise _Unknown
    link = _eval(state, env, func.value)
    if not isinstance(link, _Link):
        raise _Unknown
    names = ("group", "bit_idx", "bit")
    if len(call.args) > 3 or any(k.arg not in names for k in call.keywords):
        raise _Unknown
    values = dict(
        zip(names[: len(call.args)], (_eval(state, env, a) for a in call.args), strict=True)
    )
    for keyword in call.keywords:
        if keyword.arg in values:
            raise _Unknown
        values[str(keyword.arg)] = _eval(state, env, keyword.value)
    if set(values) != set(names):
        raise _Unknown
    group, bit, value = (values[n] for n in names)
    valid = (
        all(isinstance(v, int) for v in (group, bit, value))
        and 0 <= group <= 3
        and 0 <= bit <= 31
        and value in (0, 1)
    )
    if not valid:
        raise _Unknown
    state.bits.append((link.name, int(group), int(bit), int(value)))


def _eval(state: _State, env: dict[str, Any], node: ast.expr) -> Any:
    if isinstance(node, ast.Constant) and isinstance(node.value, (str, int, float)):
        return node.value
    if isinstance(node, (ast.List, ast.Tuple)):
        return [_eval(state, env, item) for item in node.elts]
    if isinstance(node, ast.JoinedStr):
        return "".join(_format(state, env, part) for part in node.values)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        left, right = _eval(state, env, node.left), _eval(state, env, node.right)
        if type(left) is type(right) and isinstance(left, (str, list)):
            return left + right
        raise _Unknown
    if isinstance(node, ast.Name):
        if node.id in env:
            return env[node.id]
        module = sys.modules.get(state.cls.__module__)
        return _plain(getattr(module, node.id, None)) if node.id != "self" else _fail()
    if _is_all_links(node):
        if state.link_names is None:
            raise _Unknown
        return [_Link(n) for n in state.link_names]
    if isinstance(node, ast.Attribute) and _is_self(node.value):
        if node.attr in state.named:
            return state.named[node.attr]
        if node.attr in ("robot", "scene", "tcp"):
            raise _Unknown
        return _plain(getattr(state.obj, node.attr, None))
    if isinstance(node, ast.Subscript) and _is_links_map(node.value):
        return _link(state, _eval(state, env, node.slice))
    if isinstance(node, ast.Call) and not node.keywords and len(node.args) == 2:
        name = _call_name(node.func)
        if name == "cast":  # typing.cast(T, value) is value (ManiSkill's nightly writes it)
            return _eval(state, env, node.args[1])
        if name in ("get_obj_by_name", "get_objs_by_names"):
            if not _is_all_links(node.args[0]):
                raise _Unknown
            names = _eval(state, env, node.args[1])
            if name == "get_obj_by_name":
                return _link(state, names)
            if not isinstance(names, list) or not names:
                raise _Unknown
            return [_link(state, n) for n in names]
    raise _Unknown


def _fail() -> Any:
    raise _Unknown


def _format(state: _State, env: dict[str, Any], part: ast.expr) -> str:
    if isinstance(part, ast.Constant) and isinstance(part.value, str):
        return part.value
    if isinstance(part, ast.FormattedValue) and part.conversion == -1 and part.format_spec is None:
        value = _eval(state, env, part.value)
        if isinstance(value, (str, int)) and not isinstance(value, bool):
            return str(value)
    raise _Unknown


def _plain(value: Any) -> Any:
    """A class attribute or module constant the patterns use: a string, an int, or a list or
    tuple of strings."""
    if isinstance(value, bool):
        raise _Unknown
    if isinstance(value, (str, int)):
        return value
    if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
        return list(value)
    raise _Unknown


def _link(state: _State, name: Any) -> _Link:
    if not isinstance(name, str):
        raise _Unknown
    if state.link_names is not None and name not in state.link_names:
        raise _Unknown  # upstream would bind None (get_obj_by_name) or raise (links_map)
    return _Link(name)


def _is_self(node: ast.expr) -> bool:
    return isinstance(node, ast.Name) and node.id == "self"


def _is_robot(node: ast.expr) -> bool:
    return isinstance(node, ast.Attribute) and node.attr == "robot" and _is_self(node.value)


def _is_links_map(node: ast.expr) -> bool:
    return isinstance(node, ast.Attribute) and node.attr == "links_map" and _is_robot(node.value)


def _is_all_links(node: ast.expr) -> bool:
    """``self.robot.get_links()`` or ``self.robot.links``."""
    if isinstance(node, ast.Attribute) and node.attr == "links":
        return _is_robot(node.value)
    return (
        isinstance(node, ast.Call)
        and not node.args
        and not node.keywords
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "get_links"
        and _is_robot(node.func.value)
    )


def _call_name(func: ast.expr) -> str | None:
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
        return func.attr if func.value.id in ("sapien_utils", "utils", "typing") else None
    return None


def _is_super_call(stmt: ast.stmt, hook: str) -> bool:
    if not (isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Call)):
        return False
    call = stmt.value
    return (
        not call.args
        and not call.keywords
        and isinstance(call.func, ast.Attribute)
        and call.func.attr == hook
        and isinstance(call.func.value, ast.Call)
        and _call_name(call.func.value.func) == "super"
        and not call.func.value.args
    )


def _brief(stmt: ast.stmt) -> str:
    """A statement as the import names it: an assignment by its target, else its code."""
    if isinstance(stmt, (ast.Assign, ast.AnnAssign)):
        targets = stmt.targets if isinstance(stmt, ast.Assign) else [stmt.target]
        return ", ".join(ast.unparse(t) for t in targets)
    text = ast.unparse(stmt).splitlines()[0]
    return text if len(text) <= 60 else text[:57] + "..."


def _rules(bits: list[tuple[str, int, int, int]]) -> tuple[CollisionRecord, ...]:
    """Calls → rules: one per (group, bit, value), links in call order. Merging reorders the
    calls, which is safe unless one bit is both set and cleared on a link: then the calls stay
    in order, merging only neighbours."""
    conflicting = {
        (group, bit)
        for _, group, bit, value in bits
        if any(g == group and b == bit and v != value for _, g, b, v in bits)
    }
    rules: list[tuple[tuple[int, int, int], list[str]]] = []
    for link, group, bit, value in bits:
        key = (group, bit, value)
        if (group, bit) in conflicting:
            target = rules[-1] if rules and rules[-1][0] == key else None
        else:
            target = next((rule for rule in rules if rule[0] == key), None)
        if target is None:
            rules.append((key, [link]))
        elif link not in target[1]:
            target[1].append(link)
    return tuple(CollisionRecord(tuple(links), *key) for key, links in rules)


# -- tcp_pos / tcp_pose / is_grasping as ManiSkill writes them -----------------------------------

_ATTR = r"self\.(\w+)"
_MIDPOINT = rf"\({_ATTR}\.pose\.p \+ {_ATTR}\.pose\.p\) / 2"


def _lines(cls: type, name: str) -> list[str] | None:
    """The statements of a member (a property's getter) as ``ast.unparse`` writes them."""
    owner = _definer(cls, name, 0)
    function = _function(owner, name) if owner is not None else None
    if function is None:
        return None
    return [ast.unparse(stmt) for stmt in _body(function)]


def _tcp(
    cls: type, named: dict[str, Any], tcp_link: Any
) -> tuple[TcpRecord | None, frozenset[str]]:
    link = tcp_link.name if isinstance(tcp_link, _Link) else None
    pos, pose = _lines(cls, "tcp_pos"), _lines(cls, "tcp_pose")
    if link is not None and pos == ["return self.tcp.pose.p"] and pose == ["return self.tcp.pose"]:
        return TcpRecord(link), frozenset({"tcp_pos", "tcp_pose"})
    match = re.fullmatch("return " + _MIDPOINT, pos[0]) if pos and len(pos) == 1 else None
    if match is not None and pose is not None:
        first, second = match.groups()
        if all(isinstance(named.get(a), _Link) for a in (first, second)):
            orientation = _orientation(pose, first, second)
            if orientation is not None and isinstance(named.get(orientation, _Link("")), _Link):
                record = TcpRecord(link, (first, second), orientation)
                return record, frozenset({"tcp_pos", "tcp_pose"})
    return (TcpRecord(link) if link is not None else None), frozenset()


def _orientation(pose: list[str], first: str, second: str) -> str | None:
    if len(pose) == 1:
        match = re.fullmatch(
            rf"return Pose\.create_from_pq\(self\.tcp_pos, {_ATTR}\.pose\.q\)", pose[0]
        )
        return match.group(1) if match is not None else None
    expected = [
        f"p = (self.{first}.pose.p + self.{second}.pose.p) / 2",
        f"q = (self.{first}.pose.q + self.{second}.pose.q) / 2",
        "return Pose.create_from_pq(p=p, q=q)",
    ]
    return "midpoint" if pose == expected else None


_GRASP_BODY = [
    "l_contact_forces = self.scene.get_pairwise_contact_forces(self.{left}, object)",
    "r_contact_forces = self.scene.get_pairwise_contact_forces(self.{right}, object)",
    "lforce = torch.linalg.norm(l_contact_forces, axis=1)",
    "rforce = torch.linalg.norm(r_contact_forces, axis=1)",
    "ldirection = {lsign}self.{left}.pose.to_transformation_matrix()[..., :3, {laxis}]",
    "rdirection = {rsign}self.{right}.pose.to_transformation_matrix()[..., :3, {raxis}]",
    "langle = common.compute_angle_between(ldirection, l_contact_forces)",
    "rangle = common.compute_angle_between(rdirection, r_contact_forces)",
    "lflag = torch.logical_and(lforce >= min_force, torch.rad2deg(langle) <= max_angle)",
    "rflag = torch.logical_and(rforce >= min_force, torch.rad2deg(rangle) <= max_angle)",
    "return torch.logical_and(lflag, rflag)",
]
_DIRECTION = re.compile(
    rf"[lr]direction = (-?){_ATTR}\.pose\.to_transformation_matrix\(\)\[\.\.\., :3, ([012])\]"
)


def _grasping(cls: type, named: dict[str, Any], method: str) -> GraspingRecord | None:
    """A two-finger ``is_grasping`` written as robospec's ``grasping`` writes it."""
    owner = _definer(cls, method, 0)
    function = _function(owner, method) if owner is not None else None
    if function is None:
        return None
    args = function.args
    names = [a.arg for a in args.args]
    if names != ["self", "object", "min_force", "max_angle"] or len(args.defaults) != 2:
        return None
    if args.vararg or args.kwarg or args.kwonlyargs or args.posonlyargs:
        return None
    try:
        min_force, max_angle = (ast.literal_eval(d) for d in args.defaults)
    except ValueError:
        return None
    lines = [ast.unparse(stmt) for stmt in _body(function)]
    if len(lines) != len(_GRASP_BODY):
        return None
    left, right = _DIRECTION.fullmatch(lines[4]), _DIRECTION.fullmatch(lines[5])
    if left is None or right is None:
        return None
    fill = {
        "left": left.group(2),
        "right": right.group(2),
        "lsign": left.group(1),
        "rsign": right.group(1),
        "laxis": left.group(3),
        "raxis": right.group(3),
    }
    if lines != [line.format(**fill) for line in _GRASP_BODY]:
        return None
    if not all(isinstance(named.get(fill[k]), _Link) for k in ("left", "right")):
        return None
    fingers = tuple(
        FingerRecord(m.group(2), ("-" if m.group(1) else "+") + AXES[int(m.group(3))])
        for m in (left, right)
    )
    numbers = (min_force, max_angle)
    if not all(isinstance(n, (int, float)) and not isinstance(n, bool) for n in numbers):
        return None
    return GraspingRecord(method, (fingers[0], fingers[1]), float(min_force), float(max_angle))
