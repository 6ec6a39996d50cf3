"""Which commands need which extra, and what a command says when its extra is not installed.

The light core (`pip install -e .`) runs validate, build, schema, inspect, new and doc. The
other commands need an extra; without it they say so at the command, with the line that
installs it, and exit 2 (a usage error: the command cannot run here), instead of failing deep
inside with a traceback. tests/test_light_core.py runs every command without the extras.
"""

from __future__ import annotations

import importlib.util

# the modules each extra brings that robospec imports, in the order they are looked for
# (tests/test_light_core.py checks each against pyproject.toml's extras)
EXTRA_MODULES: dict[str, tuple[str, ...]] = {
    "maniskill": ("mani_skill", "sapien", "torch", "gymnasium", "numpy", "matplotlib"),
    "lsp": ("pygls", "lsprotocol"),
    "optimize": ("coacd",),
    "reference": ("mujoco", "scipy"),
    # doc --images (robospec/pictures): without it, doc --images reports RS660
    "render": ("mujoco", "trimesh", "collada", "fast_simplification", "PIL"),
}


def missing_module(extra: str) -> str | None:
    """The first module of ``extra`` that is not installed, or None."""
    for module in EXTRA_MODULES[extra]:
        if importlib.util.find_spec(module) is None:
            return module
    return None


def extra_of(module: str | None) -> str | None:
    """The extra that installs ``module`` (a dotted name), if robospec knows one."""
    top = (module or "").partition(".")[0]
    return next((extra for extra, mods in EXTRA_MODULES.items() if top in mods), None)


def needs_extra_message(command: str, extra: str, module: str) -> str:
    return (
        f"robospec {command}: needs the {extra} extra ({module} is not installed): "
        f"pip install 'robospec[{extra}]' (in a clone of robospec: pip install -e '.[{extra}]')"
    )
