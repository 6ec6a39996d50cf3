"""Python references in a spec (``extends: "module:Class"``, hooks): import and check them.

This is the one place where validating a spec runs user code: importing the named module. It
happens only for specs that name Python, and before anything is registered, so a typo or a
wrong signature is a located diagnostic rather than an error at ``gym.make`` time.
"""

from __future__ import annotations

import importlib
import inspect
from dataclasses import dataclass
from typing import Any, Literal

from robospec.resolve.resolved import PythonRef

RefKind = Literal["agent_class", "hook", "member"]


@dataclass(frozen=True)
class CheckedRef:
    ref: PythonRef | None
    value: Any = None
    problem: str | None = None  # why the reference is unusable
    hint: str | None = None


def parse_ref(text: str) -> PythonRef:
    module, _, attributes = text.partition(":")
    return PythonRef(module, tuple(attributes.split(".")))


def check_ref(text: str, kind: RefKind) -> CheckedRef:
    """Import ``module:attr.path`` and check it is the kind of thing ``kind`` needs."""
    ref = parse_ref(text)
    try:
        value: Any = importlib.import_module(ref.module)
    except Exception as exc:  # user code: any failure to import is the user's to see
        return CheckedRef(
            None,
            problem=f"cannot import module '{ref.module}': {type(exc).__name__}: {exc}",
            hint="is the module on sys.path (installed, or beside where you run robospec)?",
        )
    for index, attribute in enumerate(ref.attributes):
        last = index == len(ref.attributes) - 1
        try:
            # the last step keeps descriptors as written (staticmethod, property)
            value = (
                inspect.getattr_static(value, attribute)
                if last and inspect.isclass(value)
                else getattr(value, attribute)
            )
        except AttributeError:
            where = ".".join((ref.module, *ref.attributes[:index]))
            return CheckedRef(None, problem=f"'{where}' has no attribute '{attribute}'")
    problem = _kind_problem(value, kind)
    if problem is not None:
        return CheckedRef(None, value, problem[0], problem[1])
    return CheckedRef(ref, value)


def _kind_problem(value: Any, kind: RefKind) -> tuple[str, str | None] | None:
    if kind == "agent_class":
        from mani_skill.agents.base_agent import BaseAgent

        if not (inspect.isclass(value) and issubclass(value, BaseAgent)):
            return (
                f"{_describe(value)} is not a ManiSkill agent class",
                "extends names a subclass of mani_skill.agents.base_agent.BaseAgent",
            )
        return None
    if kind == "hook":
        if not callable(value):
            return f"{_describe(value)} is not callable", "a hook is a function f(agent)"
        try:
            inspect.signature(value).bind(object())
        except TypeError:
            return (
                f"{_describe(value)} cannot be called with the agent as its only argument",
                "a hook is a function f(agent)",
            )
        except ValueError:  # builtins without a signature: accept
            return None
        return None
    if inspect.isfunction(value):
        try:
            inspect.signature(value).bind_partial(object())
        except TypeError:
            return (
                f"{_describe(value)} takes no arguments, so it cannot be a method",
                "a method's first parameter receives the agent (self)",
            )
    return None


def _describe(value: Any) -> str:
    name = getattr(value, "__qualname__", None) or type(value).__name__
    return f"'{name}'"
