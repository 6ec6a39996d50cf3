"""The Python a spec names, as a ManiSkill developer would write it: imported plainly.

An ``extends: module:Class`` base is ``from module import Class``; a hook's module is imported
once (``from hookmods import panda_hooks``) and its functions named through it
(``panda_hooks.after_init(self)``). A name is changed only when it is taken in the module
(``Panda`` as ``PandaBase`` for a class itself called ``Panda``). The attributes a reference
walks are identifiers the model checked; the last step from a class keeps the attribute as the
class declares it (``inspect.getattr_static``: a staticmethod or property, not bound).
"""

from __future__ import annotations

import ast
from collections.abc import Iterable
from dataclasses import dataclass

from robospec.emit.values import safe_identifier
from robospec.resolve.resolved import PythonRef, ResolvedRobot


@dataclass(frozen=True)
class PythonNames:
    """The names a generated module binds the spec's Python to."""

    modules: dict[str, str]  # a hook's module -> the name it is imported as
    base: PythonRef | None = None
    base_name: str | None = None  # what the base class is imported as

    def expr(self, ref: PythonRef) -> ast.expr:
        """The object ``ref`` names, through the imported base class or module."""
        if self._is_base(ref):
            assert self.base_name is not None
            node: ast.expr = ast.Name(self.base_name, ast.Load())
            steps, offset = list(ref.attributes[1:]), 1
        else:
            node = ast.Name(self.modules[ref.module], ast.Load())
            steps, offset = list(ref.attributes), 0
        for index, attribute in enumerate(steps):
            if index == len(steps) - 1 and index + offset > 0:
                getter = ast.Attribute(
                    ast.Name("inspect", ast.Load()), "getattr_static", ast.Load()
                )
                node = ast.Call(getter, [node, ast.Constant(attribute)], [])
            else:
                node = ast.Attribute(node, safe_identifier(attribute), ast.Load())
        return node

    def _is_base(self, ref: PythonRef) -> bool:
        base = self.base
        return base is not None and (ref.module, ref.attributes[0]) == (
            base.module,
            base.attributes[0],
        )


def hook_refs(robot: ResolvedRobot) -> list[PythonRef]:
    hooks = robot.hooks
    refs = [hooks.after_loading_articulation, hooks.after_init]
    refs += [ref for _, ref in hooks.methods]
    return [ref for ref in refs if ref is not None]


def python_names(robot: ResolvedRobot, taken: set[str] | None) -> PythonNames:
    """Names for the base class and the hooks' modules, none of them in ``taken`` (the names
    the module uses or defines otherwise). With ``taken`` None: placeholders that are no
    identifiers (``<base>``), for code generated before the names it uses are known."""
    base_name = None
    if robot.base is not None:
        own = safe_identifier(robot.base.attributes[0])
        base_name = "<base>" if taken is None else _free(own, taken, "Base")
    names = PythonNames({}, robot.base, base_name)
    for ref in hook_refs(robot):
        if ref.module not in names.modules and not names._is_base(ref):
            leaf = safe_identifier(ref.module.rpartition(".")[2])
            bound = f"<{ref.module}>" if taken is None else _free(leaf, taken, "_module")
            names.modules[ref.module] = bound
    return names


def rename(nodes: Iterable[ast.AST], placeholders: PythonNames, names: PythonNames) -> None:
    """Replace the placeholders' names in ``nodes`` by the real ones, in place."""
    mapping = {placeholders.modules[m]: names.modules[m] for m in placeholders.modules}
    if placeholders.base_name is not None and names.base_name is not None:
        mapping[placeholders.base_name] = names.base_name
    for tree in nodes:
        for node in ast.walk(tree):
            if isinstance(node, ast.Name) and node.id in mapping:
                node.id = mapping[node.id]


def _free(own: str, taken: set[str], suffix: str) -> str:
    candidate = own if own not in taken else own + suffix
    while candidate in taken:
        candidate += "_"
    taken.add(candidate)
    return candidate


def module_imports(names: PythonNames, used: Iterable[str]) -> list[ast.stmt]:
    """``import m`` or ``from package import m`` for each hook module the code uses."""
    statements: list[ast.stmt] = []
    used = set(used)
    for module, bound in names.modules.items():
        if bound not in used:
            continue
        parent, _, leaf = module.rpartition(".")
        alias = None if bound == leaf else bound
        if parent:
            statements.append(ast.ImportFrom(parent, [ast.alias(leaf, alias)], 0))
        else:
            statements.append(ast.Import([ast.alias(module, alias)]))
    return statements
