"""Stage 0 of `robospec import`: the ``module:Class`` argument → a ManiSkill agent class.

Every way the argument can be wrong is a diagnostic located in the argument itself (column of
the offending part), never a traceback: importing a module runs its code, so anything it raises
is reported.
"""

from __future__ import annotations

import importlib
import re
from dataclasses import dataclass

from robospec.diagnostics import Diagnostic, Location, error
from robospec.diagnostics.codes import (
    IMPORT_CLASS_NOT_FOUND,
    IMPORT_MODULE_UNIMPORTABLE,
    IMPORT_NOT_AN_AGENT,
    IMPORT_TARGET_FORM,
)

ARGUMENT = "<module:Class>"
_DOTTED = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")


@dataclass(frozen=True)
class Target:
    module: str
    qualname: str


def parse_target(text: str) -> tuple[Target | None, list[Diagnostic]]:
    """``package.module:Class`` (``Class`` may be dotted: ``module:Outer.Inner``)."""
    if text.count(":") != 1:
        return None, [
            error(
                Location(ARGUMENT, 1, 1),
                IMPORT_TARGET_FORM,
                f"expected module:Class, got {text!r}",
                "for example: mani_skill.agents.robots.panda.panda:Panda",
            )
        ]
    module, qualname = text.split(":")
    for part, column, what in ((module, 1, "module"), (qualname, len(module) + 2, "class")):
        if not _DOTTED.match(part):
            return None, [
                error(
                    Location(ARGUMENT, 1, column),
                    IMPORT_TARGET_FORM,
                    f"{what} name {part!r} is not a dotted Python name",
                    "for example: mani_skill.agents.robots.panda.panda:Panda",
                )
            ]
    return Target(module, qualname), []


def load_target(text: str) -> tuple[type | None, list[Diagnostic]]:
    """Import the module and return the class, checked to be a BaseAgent subclass."""
    target, diagnostics = parse_target(text)
    if target is None:
        return None, diagnostics
    try:
        module = importlib.import_module(target.module)
    except ModuleNotFoundError as exc:
        missing = exc.name or target.module
        return None, [
            error(
                Location(ARGUMENT, 1, 1),
                IMPORT_MODULE_UNIMPORTABLE,
                f"no module named {missing!r}",
                "check the spelling, and that the package is installed in this environment",
            )
        ]
    except BaseException as exc:  # importing runs arbitrary code: report whatever it raises
        if isinstance(exc, KeyboardInterrupt):
            raise
        return None, [
            error(
                Location(ARGUMENT, 1, 1),
                IMPORT_MODULE_UNIMPORTABLE,
                f"importing {target.module!r} failed: {type(exc).__name__}: {exc}",
            )
        ]
    column = len(target.module) + 2
    obj: object = module
    for name in target.qualname.split("."):
        if not hasattr(obj, name):
            from robospec.diagnostics.suggest import did_you_mean

            candidates = [n for n in vars(obj) if isinstance(vars(obj)[n], type)]
            return None, [
                error(
                    Location(ARGUMENT, 1, column),
                    IMPORT_CLASS_NOT_FOUND,
                    f"{target.module!r} has no class {target.qualname!r}",
                    did_you_mean(name, candidates),
                )
            ]
        obj = getattr(obj, name)
    from mani_skill.agents.base_agent import BaseAgent

    if not (isinstance(obj, type) and issubclass(obj, BaseAgent)) or obj is BaseAgent:
        kind = f"class {obj.__name__}" if isinstance(obj, type) else type(obj).__name__
        return None, [
            error(
                Location(ARGUMENT, 1, column),
                IMPORT_NOT_AN_AGENT,
                f"{target.qualname!r} is a {kind}, not a subclass of ManiSkill's BaseAgent",
                "name an agent class, such as mani_skill.agents.robots.panda.panda:Panda",
            )
        ]
    return obj, []
