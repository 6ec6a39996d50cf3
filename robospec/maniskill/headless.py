"""Load any ManiSkill robot on a machine without a render device.

SAPIEN refuses to create a ``RenderMaterial`` (or a ``RenderTexture2D``) when it finds no
rendering device, and both robot loaders create them while they *parse* a description — before
ManiSkill decides, in ``ArticulationBuilder._build_entities``, that a scene which cannot render
gets no render bodies anyway. So ``gym.make(..., render_backend="none")`` still fails for fetch
(URDF visuals with ``<material>``), koch/so100 (primitive visuals: ``add_box_visual`` makes a
default material) and every MJCF robot (the MJCF loader makes a material for every geom).

:func:`headless_loading` patches exactly those parse steps so that no visual body is described
at all. Collision shapes, inertials, joints and link order are untouched, so physics is identical
to a normal load (a test proves panda's rollout bit-identical with and without it).

sapien and mani_skill are imported inside the function: importing this module stays cheap.
"""

from __future__ import annotations

import importlib
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

# Re-entrancy: only the outermost ``with`` installs and removes the patches.
_lock = threading.RLock()
_depth = 0
_restore: list[Callable[[], None]] = []


class _NoRenderMaterial:
    """Stand-in for ``sapien.render.RenderMaterial``/``RenderTexture2D`` during a headless load.

    The MJCF loader builds these for every geom and ``<asset><material>`` even when the geom gets
    no visual body; it only stores and passes them on. Accepting and keeping any attribute is all
    that is needed, and it never reaches SAPIEN because no visual body is added.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.__dict__.update(kwargs)

    def __repr__(self) -> str:
        return "<headless stand-in for a SAPIEN render material>"


def strip_urdf_visuals(urdf_string: str) -> str:
    """Return ``urdf_string`` without the ``<visual>`` elements of its links.

    Only ``robot/link/visual`` is removed: gazebo extensions and everything else stay as they
    are. If the text is not well-formed it is returned unchanged, so SAPIEN reports the error
    exactly as it would without the patch.
    """
    from lxml import etree

    try:
        root = etree.fromstring(urdf_string.encode("utf-8"))
    except etree.XMLSyntaxError:
        return urdf_string
    visuals = root.findall("link/visual")
    if not visuals:
        return urdf_string
    for visual in visuals:
        parent = visual.getparent()
        if parent is not None:
            parent.remove(visual)
    return etree.tostring(root, encoding="unicode")


def _set_attr(owner: Any, name: str, value: Any) -> None:
    """Replace ``owner.name`` and remember how to put the original back."""
    had_own = name in vars(owner)
    original = vars(owner).get(name)

    def restore() -> None:
        if had_own:
            setattr(owner, name, original)
        else:
            delattr(owner, name)

    setattr(owner, name, value)
    _restore.append(restore)


def _install() -> None:
    # import_module, not ``import a.b.c as m``: the latter walks attributes, and after
    # ``import mani_skill.envs`` the attribute ``mani_skill.utils`` is rebound to
    # ``mani_skill.envs.utils`` (a submodule import of the same name), so it fails.
    mjcf_module = importlib.import_module("mani_skill.utils.building._mjcf_loader")
    urdf_module = importlib.import_module("sapien.wrapper.urdf_loader")

    # Patch 1 (URDF). ``URDFLoader._parse_urdf`` receives the file's text; SAPIEN's
    # ``_build_link`` creates a RenderMaterial for every visual with a <material> and
    # ``add_*_visual`` creates one for every primitive visual. Without <visual> elements neither
    # happens. ``urdf_dir`` is left alone, so collision meshes still resolve relative to the
    # original file. ManiSkill's URDFLoader subclasses SAPIEN's and does not override
    # ``_parse_urdf``, so patching the base class covers both.
    original_parse_urdf = urdf_module.URDFLoader._parse_urdf

    def _parse_urdf_without_visuals(self: Any, urdf_string: str) -> Any:
        return original_parse_urdf(self, strip_urdf_visuals(urdf_string))

    _set_attr(urdf_module.URDFLoader, "_parse_urdf", _parse_urdf_without_visuals)

    # Patch 2 (MJCF). ``_build_geom`` and ``_parse_material`` call RenderMaterial (and
    # RenderTexture2D for textured materials) unconditionally, through the names imported into
    # the loader's module. A stand-in there keeps parsing going; nothing else in SAPIEN sees it.
    _set_attr(mjcf_module, "RenderMaterial", _NoRenderMaterial)
    _set_attr(mjcf_module, "RenderTexture2D", _NoRenderMaterial)

    # Patch 3 (MJCF). A geom gets a visual body when its group is in ``visual_groups``; the
    # visual would then carry the stand-in material into ``add_*_visual``. An empty
    # ``visual_groups`` for the duration of the parse means no visual bodies at all. Collision
    # shapes do not depend on it.
    original_parse_mjcf = mjcf_module.MJCFLoader._parse_mjcf

    def _parse_mjcf_without_visuals(self: Any, mjcf_string: str) -> Any:
        saved = self.visual_groups
        self.visual_groups = []
        try:
            return original_parse_mjcf(self, mjcf_string)
        finally:
            self.visual_groups = saved

    _set_attr(mjcf_module.MJCFLoader, "_parse_mjcf", _parse_mjcf_without_visuals)

    # Patch 4 (task scenes). Tasks build their objects and the ground with
    # ``sapien.render.RenderMaterial(...)`` (cubes, goal markers) and RenderTexture2D (floor
    # texture), looked up on the module at call time. The stand-in lets those calls pass; a
    # scene that cannot render never turns the recorded visuals into render bodies, so the
    # stand-in goes no further and the physics is untouched.
    # ``sapien.render`` (ManiSkill's view) re-exports ``sapien.pysapien.render`` (SAPIEN's
    # wrappers import ``sapien.pysapien as sapien``): both names must see the stand-in.
    for render_module in (
        importlib.import_module("sapien.render"),
        importlib.import_module("sapien.pysapien").render,
    ):
        _set_attr(render_module, "RenderMaterial", _NoRenderMaterial)
        _set_attr(render_module, "RenderTexture2D", _NoRenderMaterial)


def _uninstall() -> None:
    while _restore:
        _restore.pop()()


@contextmanager
def headless_loading() -> Iterator[None]:
    """Within this block, ManiSkill loads robots without visual bodies (see the module doc).

    Re-entrant (nested blocks share one set of patches) and exception-safe: everything is
    restored when the outermost block exits.
    """
    global _depth
    with _lock:
        if _depth == 0:
            try:
                _install()
            except BaseException:
                _uninstall()
                raise
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                _uninstall()


def is_active() -> bool:
    """Whether the headless patches are installed right now."""
    return _depth > 0


def make_empty_env(
    uid: str,
    control_mode: str | None = None,
    *,
    headless: bool = True,
    num_envs: int = 1,
    sim_backend: str = "physx_cpu",
) -> Any:
    """ManiSkill's ``Empty-v1`` with robot ``uid``, state observations, no renderer: the
    environment every headless run and comparison in robospec uses (on the CPU unless
    ``sim_backend`` says ``physx_cuda``)."""
    import gymnasium as gym
    import mani_skill.envs  # noqa: F401  (registers Empty-v1)

    kwargs: dict[str, Any] = {}
    if control_mode is not None:
        kwargs["control_mode"] = control_mode
    if not headless:
        return gym.make(
            "Empty-v1",
            robot_uids=uid,
            obs_mode="state",
            sim_backend=sim_backend,
            render_backend="none",
            num_envs=num_envs,
            **kwargs,
        )
    with headless_loading():
        return make_empty_env(
            uid, control_mode, headless=False, num_envs=num_envs, sim_backend=sim_backend
        )
