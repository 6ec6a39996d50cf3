"""The imports of a generated module: exactly the names its code uses, the base class and the
modules of its hooks (named by :mod:`robospec.emit.python_refs`), in isort's order."""

from __future__ import annotations

import ast
from collections.abc import Iterable

from robospec.emit.layout.imports import sorted_imports
from robospec.emit.python_refs import PythonNames, module_imports
from robospec.model.controller_kinds import CONFIG_MODULE, CONTROLLER_KINDS

# a name the generated code may use -> (module it comes from, None for `import module`; the
# module or the imported name; the name it is bound to)
IMPORTABLE: dict[str, tuple[str | None, str]] = {
    "os": (None, "os"),
    "importlib": (None, "importlib"),
    "inspect": (None, "inspect"),
    "np": (None, "numpy"),
    "sapien": (None, "sapien"),
    "torch": (None, "torch"),
    "PACKAGE_ASSET_DIR": ("mani_skill", "PACKAGE_ASSET_DIR"),
    "ASSET_DIR": ("mani_skill", "ASSET_DIR"),
    "BaseAgent": ("mani_skill.agents.base_agent", "BaseAgent"),
    "Keyframe": ("mani_skill.agents.base_agent", "Keyframe"),
    "deepcopy_dict": ("mani_skill.agents.controllers", "deepcopy_dict"),
    **{kind.config_class: (CONFIG_MODULE, kind.config_class) for kind in CONTROLLER_KINDS},
    "register_agent": ("mani_skill.agents.registration", "register_agent"),
    "CameraConfig": ("mani_skill.sensors.camera", "CameraConfig"),
    "common": ("mani_skill.utils", "common"),
    "Pose": ("mani_skill.utils.structs.pose", "Pose"),
    "vectorize_pose": ("mani_skill.utils.structs.pose", "vectorize_pose"),
}


def used_names(nodes: Iterable[ast.AST]) -> set[str]:
    return {
        node.id
        for tree in nodes
        for node in ast.walk(tree)
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)
    }


def import_statements(code: list[ast.stmt], python: PythonNames) -> list[ast.stmt]:
    """Sorted import statements for every importable name ``code`` uses, the base class and
    the hooks' modules."""
    straight: list[ast.Import] = []
    members: dict[str, list[ast.alias]] = {}
    names = used_names(code)
    separate: list[ast.stmt] = module_imports(python, names)
    for used in sorted(names & IMPORTABLE.keys()):
        module, imported = IMPORTABLE[used]
        if module is None:
            straight.append(ast.Import([ast.alias(imported, None if used == imported else used)]))
        else:
            members.setdefault(module, []).append(ast.alias(imported))
    base, base_name = python.base, python.base_name
    if base is not None and base_name is not None:
        own = base.attributes[0]
        if base_name == own:
            members.setdefault(base.module, []).append(ast.alias(own))
        else:  # isort keeps a renamed import on a line of its own
            separate.append(ast.ImportFrom(base.module, [ast.alias(own, base_name)], 0))
    from_imports = [ast.ImportFrom(module, names, 0) for module, names in members.items()]
    return sorted_imports([*straight, *from_imports, *separate])  # type: ignore[list-item]
