"""RS314: a camera gives exactly one of ``fov`` and ``intrinsic``.

Passing::

    cameras:
      hand_camera: {mount: panda_hand, width: 128, height: 128, fov: pi/2}

Failing (RS314: neither)::

    cameras:
      hand_camera: {mount: panda_hand, width: 128, height: 128}
"""

from __future__ import annotations

from collections.abc import Iterator

from robospec.checks.context import CheckContext
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import CAMERA_FOV_OR_INTRINSIC


def check(context: CheckContext) -> Iterator[Diagnostic]:
    for uid, camera in context.spec.cameras.items():
        if (camera.fov is None) == (camera.intrinsic is None):
            yield error(
                context.key(("cameras", uid)),
                CAMERA_FOV_OR_INTRINSIC,
                f"camera '{uid}' needs exactly one of fov and intrinsic",
            )
