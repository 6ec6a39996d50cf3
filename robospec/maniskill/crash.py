"""Where ManiSkill or SAPIEN broke while robospec checked a robot, and whose code it was.

A :class:`Crash` comes from a Python exception (its traceback) or from a process that died of a
signal (the traceback ``faulthandler`` wrote for it). It names the innermost frame that belongs
to ManiSkill, SAPIEN or robospec — in a file path relative to the package, never a path of the
machine it ran on — and so says whether the crash is upstream's. For an exception it also
names the element of the robot description the loader was reading (a ``<link>``, a ``<geom>``,
a ``<transmission>``), found in the loader's own local variables, so the diagnostic can point
at that element's line.
"""

from __future__ import annotations

import re
import signal
import sysconfig
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Any

# top-level module -> who it is, for the frames a crash is told by
OWNERS = {
    "mani_skill": "ManiSkill",
    "sapien": "SAPIEN",
    "robospec": "robospec",
    "robospec_agents": "robospec",  # the generated agent modules register() loads
}
UPSTREAM = frozenset({"ManiSkill", "SAPIEN"})
USER = "user code"  # a module outside every installed package: a hook the spec names
_ROBOSPEC_ROOT = Path(__file__).resolve().parents[2]  # the folder robospec/ stands in
_STANDARD_LIBRARY = tuple(
    Path(sysconfig.get_paths()[key]).resolve() for key in ("stdlib", "platstdlib")
)
# the local variables through which ManiSkill's and SAPIEN's loaders hold the element they read
ELEMENT_LOCALS = ("node", "geom", "body", "joint", "link", "transmission", "actuator", "element")
# the shape of a faulthandler frame line: File "PATH", line N in FUNCTION
_FAULT_FRAME = re.compile(r'^\s*File "(?P<path>.+)", line (?P<line>\d+) in (?P<function>\S+)')


@dataclass(frozen=True)
class Frame:
    path: str  # relative to the folder holding its top-level package: mani_skill/envs/scene.py
    line: int
    function: str
    # ManiSkill, SAPIEN, robospec, USER, or "" (the standard library, numpy, torch, ...)
    owner: str

    def describe(self) -> str:
        return f"{self.path}:{self.line} ({self.function})"


@dataclass(frozen=True)
class Element:
    """An element of the robot description: its tag, its name, its line in the text the loader
    read (None when the loader's object does not know it)."""

    tag: str
    name: str
    line: int | None = None


@dataclass(frozen=True)
class Crash:
    what: str  # "AssertionError: invalid moment of inertia", "SIGSEGV (segmentation fault)"
    frame: Frame | None  # the innermost frame of ManiSkill, SAPIEN or robospec
    element: Element | None = None

    @property
    def upstream(self) -> bool:
        return self.frame is not None and self.frame.owner in UPSTREAM

    def where(self) -> str:
        """``in SAPIEN's sapien/wrapper/urdf_loader.py:278 (_build_link), upstream's code`` or
        the same for robospec, said as a bug of ours."""
        if self.frame is None:
            return "in code outside ManiSkill, SAPIEN and robospec"
        place = f"in {self.frame.owner}'s {self.frame.describe()}"
        if self.upstream:
            return f"{place}: upstream's code, not robospec's"
        if self.frame.owner == "robospec":
            return f"{place}: a bug in robospec, please report it with this spec"
        if self.frame.owner == USER:
            return f"in {self.frame.describe()}: the spec's own code (a hook), not upstream's"
        return place


def from_exception(exc: BaseException) -> Crash:
    """The crash an exception tells of: the exception ManiSkill or SAPIEN raised first (a
    wrapper's re-raise, such as Gymnasium's "was raised from the environment creator", is
    looked through), its innermost ManiSkill/SAPIEN/robospec frame and the element read."""
    root = root_cause(exc)
    frames = list(_walk(root.__traceback__))
    return Crash(_summary(root), _owned_frame(frames), _element(frames))


def from_fault_log(text: str, returncode: int) -> Crash:
    """The crash of a process that died with ``returncode`` (a negative signal number), from
    what ``faulthandler`` wrote (its innermost frame comes first)."""
    frames = []
    for line in text.splitlines():
        match = _FAULT_FRAME.match(line)
        if match:
            path = match["path"]
            frames.append(
                Frame(_shown(path, None), int(match["line"]), match["function"], _owner(path, None))
            )
    # the innermost frame, whoever's: it called the native code that crashed
    return Crash(signal_name(returncode), frames[0] if frames else None)


def signal_name(returncode: int) -> str:
    """``SIGSEGV (segmentation fault)`` for a process that returned -11, else the exit code."""
    if returncode >= 0:
        return f"exit status {returncode}"
    try:
        number = signal.Signals(-returncode)
    except ValueError:
        return f"signal {-returncode}"
    description = signal.strsignal(number) or ""
    return f"{number.name} ({description.lower()})" if description else number.name


def root_cause(exc: BaseException) -> BaseException:
    """The exception first raised: ``exc`` followed through its causes and contexts."""
    seen = {id(exc)}
    while True:
        cause = exc.__cause__ or (None if exc.__suppress_context__ else exc.__context__)
        if cause is None or id(cause) in seen:
            return exc
        seen.add(id(cause))
        exc = cause


def _summary(exc: BaseException) -> str:
    """The exception's type and message: its first line, and its last when that says more
    (pybind11's "incompatible arguments" names the arguments there)."""
    lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
    text = lines[0] if lines else ""
    if len(lines) > 1:
        text += " ... " + lines[-1]
    if len(text) > 400:
        text = text[:397] + "..."
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _walk(tb: TracebackType | None) -> list[tuple[Frame, dict[str, Any]]]:
    """Frames innermost first, each with its local variables."""
    found = []
    while tb is not None:
        code = tb.tb_frame.f_code
        module = tb.tb_frame.f_globals.get("__name__")
        frame = Frame(
            _shown(code.co_filename, module),
            tb.tb_lineno,
            code.co_name,
            _owner(code.co_filename, module),
        )
        found.append((frame, tb.tb_frame.f_locals))
        tb = tb.tb_next
    return found[::-1]


def _owned_frame(frames: list[tuple[Frame, dict[str, Any]]]) -> Frame | None:
    return _first_owned([frame for frame, _ in frames])


def _first_owned(frames: list[Frame]) -> Frame | None:
    return next((f for f in frames if f.owner), frames[0] if frames else None)


def _owner(path: str, module: object) -> str:
    if isinstance(module, str) and module.split(".")[0] in OWNERS:
        return OWNERS[module.split(".")[0]]
    parts = Path(path).parts
    for marker in ("site-packages", "dist-packages"):
        if marker in parts:
            index = len(parts) - 1 - parts[::-1].index(marker)
            top = Path(parts[index + 1]).stem if index + 1 < len(parts) else ""
            return OWNERS.get(top, "")
    resolved = Path(path).resolve()
    if resolved.is_relative_to(_ROBOSPEC_ROOT / "robospec"):
        return "robospec"
    if not resolved.is_file() or any(resolved.is_relative_to(p) for p in _STANDARD_LIBRARY):
        return ""  # the standard library, or code that is not a file (<string>, frozen)
    return USER


def _shown(path: str, module: object) -> str:
    """``path`` from its top-level package down (``mani_skill/envs/scene.py``): what a user
    can find in their own installation."""
    parts = Path(path).parts
    top = module.split(".")[0] if isinstance(module, str) else None
    if top is not None and top in parts:
        index = len(parts) - 1 - parts[::-1].index(top)
        return "/".join(parts[index:])
    for marker in ("site-packages", "dist-packages"):
        if marker in parts:
            index = len(parts) - 1 - parts[::-1].index(marker)
            return "/".join(parts[index + 1 :])
    try:
        return Path(path).resolve().relative_to(_ROBOSPEC_ROOT).as_posix()
    except ValueError:
        return Path(path).name


def _element(frames: list[tuple[Frame, dict[str, Any]]]) -> Element | None:
    """The description element the innermost loader frame holds in a local variable."""
    for _, variables in frames:
        for name in ELEMENT_LOCALS:
            element = _as_element(name, variables.get(name))
            if element is not None:
                return element
    return None


def _as_element(variable: str, value: object) -> Element | None:
    """An XML element the loader parses, or an object ManiSkill or SAPIEN built for one (a
    urchin ``Link``, a PhysX joint): named by its ``name``, its tag by the variable."""
    if value is None:
        return None
    tag = getattr(value, "tag", None)
    if isinstance(tag, str) and hasattr(value, "attrib"):
        return _xml_element(value)
    name = getattr(value, "name", None)
    module = type(value).__module__ or ""
    if isinstance(name, str) and name and module.split(".")[0] in ("sapien", "mani_skill"):
        return Element(variable, name)
    return None


def _xml_element(element: Any) -> Element | None:
    """An lxml or ElementTree element, or its nearest named ancestor (lxml knows parents)."""
    while element is not None:
        name = element.get("name")
        if name:
            line = getattr(element, "sourceline", None)
            return Element(str(element.tag), name, line if isinstance(line, int) else None)
        getparent = getattr(element, "getparent", None)
        element = getparent() if getparent is not None else None
    return None
