"""Started by Python itself when this folder is on PYTHONPATH: the modules named in
$ROBOSPEC_TEST_BLOCKED (comma-separated top-level names) and the distributions named in
$ROBOSPEC_TEST_BLOCKED_DISTS are then not found, as if they were not installed:
``import numpy`` raises ModuleNotFoundError, ``importlib.util.find_spec("numpy")`` is None and
``importlib.metadata.version("numpy")`` raises PackageNotFoundError. tests/test_light_core.py
runs robospec's commands so, to see what a user of the light core (`pip install -e .`) sees,
without a second environment."""

import os
import re
import sys


def _names(variable):
    return frozenset(filter(None, os.environ.get(variable, "").split(",")))


_BLOCKED = _names("ROBOSPEC_TEST_BLOCKED")
_BLOCKED_DISTS = _names("ROBOSPEC_TEST_BLOCKED_DISTS")


def _normalized(name):
    return re.sub(r"[-_.]+", "-", name or "").lower()


class _NotInstalled:
    """A finder of sys.meta_path that finds nothing the environment is said not to have."""

    def __init__(self, finder):
        self._finder = finder

    def find_spec(self, fullname, path=None, target=None):
        if fullname.partition(".")[0] in _BLOCKED:
            return None
        return self._finder.find_spec(fullname, path, target)

    def find_distributions(self, *args, **kwargs):
        found = getattr(self._finder, "find_distributions", None)
        if found is None:
            return iter(())
        return (
            d
            for d in found(*args, **kwargs)
            if _normalized(d.metadata["Name"]) not in _BLOCKED_DISTS
        )

    def __getattr__(self, name):
        return getattr(self._finder, name)


if _BLOCKED:
    sys.meta_path[:] = [_NotInstalled(finder) for finder in sys.meta_path]
    # already imported by the interpreter's start-up (a .pth file): gone too
    for _name in list(sys.modules):
        if _name.partition(".")[0] in _BLOCKED:
            del sys.modules[_name]
