"""MuJoCo, imported to draw offscreen: the one place that chooses its OpenGL.

robospec asks for EGL, which Mesa provides on a machine without a GPU (llvmpipe draws on the
CPU), unless the user set ``MUJOCO_GL`` themselves. MuJoCo picks ``mujoco.GLContext`` when it
is first imported, and something else may have imported it first (ManiSkill does, without
``MUJOCO_GL``, which leaves GLFW's, needing a display): so the context is taken from the chosen
platform's own module (:func:`gl_context`), whoever imported MuJoCo.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
from typing import Any

from robospec.diagnostics.codes import NO_RENDER_EXTRA

PLATFORMS = ("egl", "osmesa", "glfw")  # MUJOCO_GL's values, each mujoco.<value>.GLContext


class RenderUnavailable(Exception):
    """No picture can be drawn here: ``code`` (RS660, RS661, RS664), the message, a hint."""

    def __init__(self, code: str, message: str, hint: str) -> None:
        super().__init__(message)
        self.code = code
        self.message = message
        self.hint = hint


def import_mujoco() -> Any:
    """MuJoCo, set to draw offscreen through EGL unless ``MUJOCO_GL`` says otherwise."""
    os.environ.setdefault("MUJOCO_GL", "egl")
    try:
        import mujoco

        # the meshes' reader, imported only to read a mesh not in the cache (it costs seconds);
        # missing, it is said now rather than half-way
        if importlib.util.find_spec("trimesh") is None:
            raise ImportError("No module named 'trimesh'")
    except ImportError as exc:
        raise RenderUnavailable(
            NO_RENDER_EXTRA,
            f"pictures need the render extra: {exc}",
            "pip install 'robospec[render]' (mujoco, trimesh, pycollada, fast-simplification)",
        ) from exc
    return mujoco


def gl_context(width: int, height: int) -> Any:
    """An offscreen OpenGL context of the platform ``MUJOCO_GL`` names (default EGL), made
    current. Raises what the platform raises when it cannot make one."""
    mujoco = import_mujoco()
    platform = os.environ.get("MUJOCO_GL", "egl").lower()
    if platform in PLATFORMS:
        context = importlib.import_module(f"mujoco.{platform}").GLContext(width, height)
    else:
        context = mujoco.GLContext(width, height)
    context.make_current()
    return context
