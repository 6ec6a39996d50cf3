"""MuJoCo, imported to draw offscreen: the one place that chooses its OpenGL.

MuJoCo picks its OpenGL platform when it is first imported (``MUJOCO_GL``): robospec asks for
EGL, which Mesa provides on a machine without a GPU (llvmpipe draws on the CPU), unless the
user set ``MUJOCO_GL`` themselves. Every module of the pictures imports MuJoCo through
:func:`import_mujoco`, so the first import is always this one.
"""

from __future__ import annotations

import importlib.util
import os
from typing import Any


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
            "RS660",
            f"pictures need the render extra: {exc}",
            "pip install 'robospec[render]' (mujoco, trimesh, pycollada, fast-simplification)",
        ) from exc
    return mujoco
