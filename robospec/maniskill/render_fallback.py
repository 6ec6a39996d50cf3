"""Load ManiSkill robots and task scenes where SAPIEN finds no rendering device.

SAPIEN refuses to create a ``RenderMaterial`` (or a ``RenderTexture2D``) when it finds no
rendering device, and ManiSkill creates them while it *parses* a robot description and builds a
task's objects — before it decides, in ``ArticulationBuilder._build_entities``, that a scene
which cannot render gets no render bodies anyway. So on a machine without a GPU,
``gym.make(..., render_backend="none")`` fails with "failed to find a rendering device" for
fetch (URDF visuals with ``<material>``), koch/so100 (primitive visuals: ``add_box_visual``
makes a default material), every MJCF robot (the MJCF loader makes a material for every geom)
and task scenes such as PickCube's (the cube's material).

The patches here describe no visual body at all — URDF ``<visual>`` elements are left out,
MJCF geoms get no visual group, and task scenes get a stand-in material that never reaches
SAPIEN. Collision shapes, inertials, joints and link order are untouched, so physics is
identical to a normal load.

- :func:`install` puts them in place for the rest of the process, and only when SAPIEN finds
  no rendering device: with one, nothing changes and visuals load as before.
  ``robospec.register`` calls it, and so does the ``__init__.py`` of every package
  ``robospec build`` writes.
- :func:`acquire` and :func:`release` put them in place for a while, device or not (robospec's
  own headless runs, which never render).

This file imports nothing from robospec: ``robospec build`` copies it, as it is, into every
package it writes (``_robospec_headless.py``), so a built package loads headless where robospec
is not installed. sapien and mani_skill are imported inside the functions: importing this
module stays cheap.
"""

from __future__ import annotations

import importlib
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from collections.abc import Iterable

    from mani_skill.agents.base_agent import BaseAgent
    from mani_skill.utils.building._mjcf_loader import MJCFLoader
    from sapien.render import RenderMaterial
    from sapien.wrapper.urdf_loader import URDFLoader

# On every stand-in class: whichever copy of this module put the patches in place, another
# copy (robospec's, or a built package's) sees them and does not stack its own.
STAND_IN_MARK = "_robospec_render_stand_in"

_lock = threading.RLock()
_holders = 0  # acquire() calls not yet released, the process-wide install counting as one
_owned = False  # whether this copy installed the patches (another copy may have)
_process_wide = False
_restore: list[Callable[[], None]] = []
_device: bool | None = None  # whether SAPIEN finds a rendering device, once asked
_original_material: type[RenderMaterial] | None = None  # while the stand-in replaces it


class NoRenderMaterial:
    """Stand-in for ``sapien.render.RenderMaterial``/``RenderTexture2D`` while robots load
    without visuals.

    The MJCF loader builds these for every geom and ``<asset><material>`` even when the geom
    gets no visual body, and tasks build them for their objects; they only store and pass them
    on. Accepting and keeping any attribute is all that is needed, and it never reaches SAPIEN
    because no visual body is added.
    """

    _robospec_render_stand_in = True

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.__dict__.update(kwargs)

    def __getattr__(self, name: str) -> Any:
        # tasks also call the material's setters (PlugCharger-v1: ``mat.set_base_color(...)``):
        # a setter stores its value under the property's name, as an assignment would
        if name.startswith("set_") and len(name) > 4:
            field = name[4:]

            def setter(*args: Any) -> None:
                self.__dict__[field] = args[0] if len(args) == 1 else args

            return setter
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __repr__(self) -> str:
        return "<stand-in for a SAPIEN render material: no rendering device>"


def strip_urdf_visuals(urdf_string: str) -> str:
    """Return ``urdf_string`` without the ``<visual>`` elements of its links, every other
    element on the line it was on (so an element SAPIEN chokes on is reported at its line in
    the original file).

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
        if parent is None:
            continue
        # the visual's own lines stay, blank, before whatever followed it
        kept = "\n" * etree.tostring(visual, with_tail=False).count(b"\n") + (visual.tail or "")
        previous = visual.getprevious()
        if previous is not None:
            previous.tail = (previous.tail or "") + kept
        else:
            parent.text = (parent.text or "") + kept
        parent.remove(visual)
    # what stood before <robot> (the XML declaration, comments) becomes blank lines
    return "\n" * ((root.sourceline or 1) - 1) + etree.tostring(root, encoding="unicode")


def render_device_available() -> bool:
    """Whether SAPIEN finds a rendering device: it makes a render material, or says "failed
    to find a rendering device". Asked once per process (it costs about a millisecond)."""
    global _device
    if _device is None:
        import sapien

        material = _original_material or sapien.render.RenderMaterial
        if getattr(material, STAND_IN_MARK, False):
            _device = False  # another copy found none and put the stand-in there
        else:
            try:
                material()
                _device = True
            except RuntimeError:
                _device = False
    return _device


def install() -> bool:
    """Where SAPIEN finds no rendering device, load robots and task scenes without visuals for
    the rest of the process; returns whether it did. Idempotent; with a rendering device it
    changes nothing."""
    global _process_wide
    with _lock:
        if _process_wide:
            return True
        if render_device_available():
            return False
        acquire()
        _process_wide = True
        return True


def guard_loading(agents: Iterable[type[BaseAgent]]) -> None:
    """Where robospec is installed, make loading each of ``agents`` (a built package's agent
    classes) raise ``robospec.SpecError`` with a located diagnostic (RS514, at the element of
    the description the loader was reading) where ManiSkill's loaders raise; where it is not,
    ManiSkill's exception is left as it is. Here only because this is the one file a built
    package carries (robospec.maniskill.load_guard does the work)."""
    try:
        from robospec.maniskill.load_guard import guard_described
    except ImportError:
        return
    for agent in agents:
        guard_described(agent)


def acquire() -> None:
    """Load without visuals until the matching :func:`release` (calls nest)."""
    global _holders, _owned
    with _lock:
        if _holders == 0 and not installed():
            try:
                _install()
            except BaseException:
                _uninstall()
                raise
            _owned = True
        _holders += 1


def release() -> None:
    global _holders, _owned
    with _lock:
        _holders -= 1
        if _holders == 0 and _owned:
            _uninstall()
            _owned = False


def installed() -> bool:
    """Whether robots load without visuals now (by this copy of the module or another)."""
    import sapien

    return bool(getattr(sapien.render.RenderMaterial, STAND_IN_MARK, False))


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
    global _original_material
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

    def _parse_urdf_without_visuals(self: URDFLoader, urdf_string: str) -> Any:
        return original_parse_urdf(self, strip_urdf_visuals(urdf_string))

    _set_attr(urdf_module.URDFLoader, "_parse_urdf", _parse_urdf_without_visuals)

    # Patch 2 (MJCF). ``_build_geom`` and ``_parse_material`` call RenderMaterial (and
    # RenderTexture2D for textured materials) unconditionally, through the names imported into
    # the loader's module. A stand-in there keeps parsing going; nothing else in SAPIEN sees it.
    _set_attr(mjcf_module, "RenderMaterial", NoRenderMaterial)
    _set_attr(mjcf_module, "RenderTexture2D", NoRenderMaterial)

    # Patch 3 (MJCF). A geom gets a visual body when its group is in ``visual_groups``; the
    # visual would then carry the stand-in material into ``add_*_visual``. An empty
    # ``visual_groups`` for the duration of the parse means no visual bodies at all. Collision
    # shapes do not depend on it.
    original_parse_mjcf = mjcf_module.MJCFLoader._parse_mjcf

    def _parse_mjcf_without_visuals(self: MJCFLoader, mjcf_string: str) -> Any:
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
    _original_material = importlib.import_module("sapien.render").RenderMaterial
    for render_module in (
        importlib.import_module("sapien.render"),
        importlib.import_module("sapien.pysapien").render,
    ):
        _set_attr(render_module, "RenderMaterial", NoRenderMaterial)
        _set_attr(render_module, "RenderTexture2D", NoRenderMaterial)


def _uninstall() -> None:
    global _original_material
    while _restore:
        _restore.pop()()
    _original_material = None
