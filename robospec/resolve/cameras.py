"""Cameras mounted on links of the robot."""

from __future__ import annotations

from typing import Any

from robospec.resolve.context import ResolveContext
from robospec.resolve.poses import position_and_quaternion
from robospec.resolve.resolved import ResolvedCamera
from robospec.resolve.selection import link


def resolve_camera(context: ResolveContext, uid: str, camera: Any) -> ResolvedCamera:
    link(context, camera.mount, ("cameras", uid, "mount"))
    p, q = position_and_quaternion(camera.pose)
    intrinsic = tuple(tuple(row) for row in camera.intrinsic) if camera.intrinsic else None
    return ResolvedCamera(
        uid,
        camera.mount,
        p,
        q,
        camera.width,
        camera.height,
        camera.fov,
        intrinsic,
        camera.near,
        camera.far,
        camera.shader_pack,
    )
