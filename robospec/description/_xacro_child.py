"""Child-process side of :func:`robospec.description.xacro.expand_xacro`.

Run as a script (``runpy.run_path``), never imported by robospec itself: expanding a xacro file
runs the code in it, so this must happen in a throwaway process whose memory is capped *before*
xacro is imported. Usage::

    python -c BOOTSTRAP <this file> <xacro path> <memory bytes> <cpu seconds> <args as JSON>
        <output bytes> <include depth> <packages as JSON> <robospec/description/packages.py>

It writes exactly one JSON object to the stdout it was started with:

- ``{"ok": true, "urdf": "..."}``
- ``{"ok": false, "kind": "memory"}``
- ``{"ok": false, "kind": "xml", "message": ..., "file": ..., "line": ..., "column": ...}``
- ``{"ok": false, "kind": "xacro", "message": ..., "file": ..., "files": [...]}``
- ``{"ok": false, "kind": "package", "package": ..., "file": ..., "files": [...]}``: a
  ``$(find NAME)`` that names a package found nowhere

Everything else it (or the xacro file) prints goes to stderr, a file capped by ``RLIMIT_FSIZE``.

This module imports only the standard library (and xacro, after the limits are in place) so that
it does not depend on how robospec is installed. ``$(find NAME)`` (which xacro 2 answers with
ROS 2's ament index, absent here) is answered by robospec's own package search, loaded from
``packages.py`` by its path: the spec's ``packages`` map, then the folders from the xacro file's
folder up (robospec.description.packages).
"""

from __future__ import annotations

import errno
import json
import os
import sys
from typing import Any

# Error messages from a runaway recursion list every macro frame; the parent needs the gist only.
_MAX_MESSAGE = 4000


def _set_limits(memory_bytes: int, cpu_seconds: int, output_bytes: int) -> None:
    try:
        import resource
    except ImportError:  # not POSIX: only the parent's wall-clock timeout protects us
        return
    # Soft and hard alike, so that code inside the xacro file cannot raise the limit again.
    limits = [
        (resource.RLIMIT_AS, memory_bytes),
        (resource.RLIMIT_CPU, cpu_seconds),
        (resource.RLIMIT_FSIZE, output_bytes),  # printing without end fills no disk
    ]
    if hasattr(resource, "RLIMIT_CORE"):
        limits.append((resource.RLIMIT_CORE, 0))  # a crash must not leave a core dump behind
    # Python ignores SIGXFSZ, which turns the output limit into an error the file's code could
    # catch and loop on; by default the signal ends the process, which the parent reports.
    import signal

    if hasattr(signal, "SIGXFSZ"):
        signal.signal(signal.SIGXFSZ, signal.SIG_DFL)
    for which, value in limits:
        _soft, hard = resource.getrlimit(which)
        if hard != resource.RLIM_INFINITY:
            value = min(value, hard)
        try:
            resource.setrlimit(which, (value, value))
        except (ValueError, OSError):
            pass


def _cause(exc: BaseException | None, test: Any) -> Any:
    """The first exception in ``exc``'s chain that passes ``test``, or None."""
    # xacro wraps evaluation errors in XacroException(exc=...), so look through the whole chain.
    seen: set[int] = set()
    stack: list[Any] = [exc]
    while stack:
        e = stack.pop()
        if e is None or id(e) in seen:
            continue
        seen.add(id(e))
        if test(e):
            return e
        stack.extend([getattr(e, "exc", None), e.__cause__, e.__context__])
    return None


def _caused_by(exc: BaseException | None, test: Any) -> bool:
    return _cause(exc, test) is not None


def _message(exc: BaseException) -> str:
    text = str(exc).strip() or type(exc).__name__
    if len(text) > _MAX_MESSAGE:
        text = text[:_MAX_MESSAGE] + " ..."
    return text


def _limit_include_depth(xacro: Any, depth: int) -> None:
    """Stop an include that nests deeper than ``depth`` (a file including itself) at once,
    instead of after a thousand levels of Python recursion."""
    parse = xacro.parse

    def limited_parse(inp: Any, filename: Any = None) -> Any:
        stack = xacro.filestack or []
        if inp is None and len(stack) > depth:
            raise xacro.XacroException(
                f"xacro:include nested more than {depth} deep (does a file include itself?)"
            )
        return parse(inp, filename)

    xacro.parse = limited_parse


class PackageNotFound(Exception):
    def __init__(self, name: str) -> None:
        super().__init__(f"ROS package '{name}' not found")
        self.name = name


def _answer_find(xacro: Any, packages: dict[str, str], finder_file: str) -> None:
    """Make ``$(find NAME)`` use robospec's package search."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("robospec_packages", finder_file)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    finder = module.PackageFinder(os.getcwd(), packages)

    def find(name: str) -> str:
        folder = finder.find(name)
        if folder is None:
            raise PackageNotFound(name)
        return str(folder)

    xacro.substitution_args._eval_find = find


def _expand(
    path: str,
    mappings: dict[str, str],
    include_depth: int,
    packages: dict[str, str],
    finder_file: str,
) -> dict[str, Any]:
    import xml.parsers.expat

    import xacro
    import xacro.substitution_args

    _limit_include_depth(xacro, include_depth)
    _answer_find(xacro, packages, finder_file)
    try:
        doc = xacro.process_file(path, mappings=mappings)
        return {"ok": True, "urdf": doc.toprettyxml(indent="  ")}
    except MemoryError:
        return {"ok": False, "kind": "memory"}
    except xml.parsers.expat.ExpatError as e:
        files = [f for f in (xacro.filestack or []) if f]
        return {
            "ok": False,
            "kind": "xml",
            "message": f"XML parsing error: {xml.parsers.expat.ErrorString(e.code)}",
            "file": files[-1] if files else path,
            "line": e.lineno,
            "column": e.offset + 1,  # expat's offset is 0-based
            "files": files,
        }
    except BaseException as e:  # anything the file's code raises is the file's problem
        if _caused_by(e, lambda x: isinstance(x, MemoryError)):
            return {"ok": False, "kind": "memory"}
        if _caused_by(e, lambda x: isinstance(x, OSError) and x.errno == errno.EFBIG):
            return {"ok": False, "kind": "output"}  # over RLIMIT_FSIZE, SIGXFSZ ignored again
        files = [f for f in (xacro.filestack or []) if f]
        missing = _cause(e, lambda x: isinstance(x, PackageNotFound))
        if missing is not None:
            return {
                "ok": False,
                "kind": "package",
                "package": missing.name,
                "file": files[-1] if files else path,
                "files": files,
            }
        return {
            "ok": False,
            "kind": "xacro",
            "message": _message(e),
            "file": files[-1] if files else path,
            "files": files,
        }


def main(argv: list[str]) -> int:
    path, memory, cpu, args_json, output, include_depth, packages_json, finder_file = argv
    _set_limits(int(memory), int(cpu), int(output))
    # The result goes to the original stdout; anything the xacro file manages to print goes to
    # stderr, so it cannot corrupt the JSON answer.
    result_fd = os.dup(1)
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    mappings = json.loads(args_json)
    try:
        result = _expand(path, mappings, int(include_depth), json.loads(packages_json), finder_file)
        answer = json.dumps(result, ensure_ascii=True)
    except MemoryError:
        answer = json.dumps({"ok": False, "kind": "memory"})
    with os.fdopen(result_fd, "w", encoding="ascii") as out:
        out.write(answer)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
