"""What ManiSkill's MJCF loader does to the robot's geoms and frames, reported at the element
(measured with ManiSkill 3.0.1 and SAPIEN 3.0.3, see tests/test_mjcf_loader_gaps.py):

* RS073 — contype/conaffinity: a geom gets a collision shape unless its contype is 0, and then
  collides with every other; conaffinity is not read. Geoms MuJoCo would still collide (contype
  0, conaffinity not) lose their contacts; links MuJoCo never collides with each other collide.
* RS074 — a mesh's ``scale`` is read from the ``<mesh>`` element only, never from ``<default>``
  (Menagerie's Robotiq 2F-85 loads about 75 m wide): ten times off or more is an error.
* RS075 — ``<inertial>`` and geom ``mass=`` are not read: each link weighs what its collision
  geoms do at their density (1000 kg/m³ unless ``density=`` says otherwise).
* RS076 — a moving body whose subtree has no collision shape gets SAPIEN's minimum mass, 1e-6 kg.
* RS078 — geoms get a visual body only in groups 0 and 2; MuJoCo draws groups 0 to 2.
* RS079 — ``ellipsoid`` and ``plane`` geoms are skipped; ``hfield`` and ``sdf`` raise
  NotImplementedError (anywhere in the file: the loader parses it all).
* RS080 — orientations read differently (:mod:`robospec.description.mjcf_frames`): a robot
  frame that differs is an error, a ``zaxis`` along ±z fails the whole load.
* RS085 — meshes the loader cannot resolve: a geom's ``mesh=`` missing from its table (an
  unnamed mesh is named after its file path there, with folders; MuJoCo uses the file's name),
  a ``<mesh>`` without ``file=`` (an assertion), a geom whose mesh a default class names that
  the loader's default tables do not give it (``<default class="main">``: ``KeyError: None``,
  or a unit sphere; robospec.description.mjcf_class_meshes).
* RS056 (as for URDF) — a mesh file missing where the loader looks (the model's folder joined
  with ``<compiler meshdir>``; ``assetdir`` is not read): SAPIEN loads nothing for it,
  silently. An error for a collision, a warning for a visual.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator
from itertools import combinations

from lxml import etree

from robospec.description.inertia import DENSITY, EMPTY_LINK_MASS
from robospec.description.mjcf_class_meshes import lost_meshes
from robospec.description.mjcf_frames import (
    Unparsable,
    maniskill_rotation,
    mujoco_rotation,
    orientation_attribute,
    same_axis,
    same_rotation,
)
from robospec.description.mjcf_loaded import (
    COLLISION_TYPES,
    LoadedBody,
    LoadedGeom,
    LoadedMjcf,
    parsed_elements,
)
from robospec.description.mjcf_mujoco import MAIN_CLASS, attributes
from robospec.description.mjcf_structure import names
from robospec.description.numbers import finite_numbers
from robospec.diagnostics import Diagnostic, error, warning
from robospec.diagnostics.codes import (
    MESH_NOT_FOUND,
    MJCF_COLLISION_FILTER,
    MJCF_GEOM_TYPE,
    MJCF_MASSES,
    MJCF_MESH_SCALE,
    MJCF_MESH_UNRESOLVED,
    MJCF_NO_MASS,
    MJCF_ORIENTATION,
    MJCF_VISUAL_GROUP,
)

# the route that loads an MJCF as MuJoCo compiles it (robospec.derive.mujoco_urdf)
MUJOCO_ROUTE = (
    "`description: {mjcf: ..., loader: mujoco}` loads the robot as MuJoCo compiles it, "
    "with the file's masses"
)

CERTAINLY_WRONG = 10.0  # a mesh this many times too large or small is an error
MANISKILL_VISUAL_GROUPS = (0, 2)
MUJOCO_VISUAL_GROUPS = (0, 1, 2)


def _elsewhere(elements: list[etree._Element]) -> str:
    more = len(elements) - 1
    return f" (here and at {more} more place{'s' if more > 1 else ''})" if more else ""


def _label(geom: LoadedGeom) -> str:
    name = geom.element.get("name")
    return name if name else f"a {geom.type} of {geom.body.name}"


# -- meshes --------------------------------------------------------------------------------------


def _meshes(loaded: LoadedMjcf) -> dict[str, etree._Element]:
    """The loader's mesh table: name (or the file path without its extension) -> element."""
    table = {}
    for asset in (el for el in loaded.top if el.tag == "asset"):
        for mesh in asset.findall("mesh"):
            file = mesh.get("file")
            if file is not None or mesh.get("name") is not None:
                table[mesh.get("name") or os.path.splitext(file or "")[0]] = mesh
    return table


def _mesh_dir(loaded: LoadedMjcf) -> str:
    compiler = next((el for el in loaded.top if el.tag == "compiler"), None)
    meshdir = compiler.get("meshdir", ".") if compiler is not None else "."
    return os.path.join(os.path.dirname(loaded.path), meshdir)


def _class_meshes(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS085: geoms whose mesh a default class names and the loader reads without it (one
    diagnostic for them all, at the first: a model that spells its root class ``main`` loses
    every such mesh)."""
    lost = list(lost_meshes(loaded.worldbody, loaded.classes, loaded.mujoco_classes))
    if not lost:
        return
    first = next((m for m in lost if m.fails), lost[0])
    others = [m for m in lost if m is not first]
    read = (
        "a mesh without a name: loading fails (KeyError: None in _build_geom)"
        if first.fails
        else f"a {first.loaded_type}"
        + (f" of mesh '{first.loaded_mesh}'" if first.loaded_mesh else "")
    )
    why = (
        ' (it reads a top-level <default class="main"> as a class of its own, applied '
        "only where a geom names it)"
        if first.holder == MAIN_CLASS
        else ""
    )
    lines = ", ".join(str(loaded.where(m.geom).line) for m in others[:6])
    plural = "s" if len(others) > 1 else ""
    more = f" (and {len(others)} more geom{plural}: line{plural} {lines})" if others else ""
    yield error(
        loaded.where(first.geom),
        MJCF_MESH_UNRESOLVED,
        f"geom takes mesh '{first.mesh}' from default class '{first.holder}' in MuJoCo, and "
        f"ManiSkill's MJCF loader reads it as {read}{why}{more}",
        f'write mesh="{first.mesh}" on the geom: `description: {{mend: {{geom_meshes: '
        "defaults}}` does it in a copy of the model",
    )


def mesh_files(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS085: meshes the loader fails on; RS056: mesh files it loads as nothing."""
    table = _meshes(loaded)
    for asset in (el for el in loaded.top if el.tag == "asset"):
        for mesh in asset.findall("mesh"):
            if mesh.get("file") is None:
                yield error(
                    loaded.where(mesh),
                    MJCF_MESH_UNRESOLVED,
                    f"mesh '{mesh.get('name', '')}' has no file=: ManiSkill's MJCF loader "
                    "asserts that every mesh has one (vertex= meshes are not supported)",
                    "save the mesh to a file (.stl or .obj) and name it with file=",
                )
    unknown: dict[str, etree._Element] = {}
    for element, attrs in parsed_elements(loaded):
        name = attrs.get("mesh")
        if element.tag == "geom" and name is not None and name not in table:
            unknown.setdefault(name, element)
    if unknown:
        # one diagnostic for them all: an exporter that leaves meshes unnamed leaves dozens
        name, element = next(iter(unknown.items()))
        by_file = {n: [k for k in table if os.path.basename(k) == n] for n in unknown}
        if all(by_file.values()):
            hint = (
                f"name the meshes as MuJoCo does (ManiSkill calls the unnamed <mesh> of that "
                f"file '{by_file[name][0]}'): `description: {{mend: {{mesh_names: mujoco}}}}` "
                "does it in a copy"
            )
        elif by_file[name]:
            hint = (
                "name the mesh: ManiSkill calls the unnamed <mesh> of that file "
                f"'{by_file[name][0]}'"
            )
        else:
            hint = "define it in an <asset> of the model or of a file it includes at the top level"
        others = len(unknown) - 1
        more = f" (and {others} more: {names(list(unknown)[1:])})" if others else ""
        yield error(
            loaded.where(element),
            MJCF_MESH_UNRESOLVED,
            f"geom uses mesh '{name}'{more}, which ManiSkill's MJCF loader does not know: "
            "loading fails (KeyError)",
            hint,
        )
    yield from _class_meshes(loaded)
    missing_collision: list[tuple[LoadedGeom, str]] = []
    missing_visual: list[tuple[LoadedGeom, str]] = []
    folder = _mesh_dir(loaded)
    compiler = next((el for el in loaded.top if el.tag == "compiler"), None)
    meshdir = compiler.get("meshdir", ".") if compiler is not None else "."
    assetdir = (
        compiler is not None and "assetdir" in compiler.attrib and "meshdir" not in compiler.attrib
    )
    for geom in loaded.geoms():
        used = table.get(geom.attributes.get("mesh", ""))
        if geom.type != "mesh" or used is None or used.get("file") is None:
            continue
        if not os.path.isfile(os.path.join(folder, used.get("file", ""))):
            (missing_collision if geom.collides else missing_visual).append(
                (geom, used.get("file", ""))
            )
    for found, report, what in (
        (missing_collision, error, "its collision shape is missing, and its mass"),
        (missing_visual, warning, "it is drawn without it"),
    ):
        if found:
            files = sorted({file for _, file in found})
            links = sorted({geom.body.name for geom, _ in found})
            yield report(
                loaded.where(found[0][0].element),
                MESH_NOT_FOUND,
                f"mesh file(s) {names(files)} not found where ManiSkill's MJCF loader looks "
                f'(the model\'s folder joined with <compiler meshdir="{meshdir}">), and SAPIEN '
                f"loads nothing for a missing file: link(s) {names(links)}: {what}",
                "ManiSkill does not read <compiler assetdir>: give meshdir" if assetdir else None,
            )


def mesh_scale(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS074: meshes whose scale comes from a default class."""
    table = _meshes(loaded)
    used: dict[etree._Element, list[LoadedGeom]] = {}
    for geom in loaded.geoms():
        mesh = table.get(geom.attributes.get("mesh", ""))
        if geom.type == "mesh" and mesh is not None:
            used.setdefault(mesh, []).append(geom)
    wrong: list[tuple[etree._Element, tuple[float, ...], bool]] = []
    off: list[tuple[etree._Element, tuple[float, ...], bool]] = []
    for mesh, geoms in used.items():
        if "scale" in mesh.attrib:
            continue
        meant = finite_numbers(attributes(loaded.mujoco_classes, mesh, MAIN_CLASS).get("scale"))
        if meant is None or len(meant) != 3 or meant == (1.0, 1.0, 1.0):
            continue
        collides = any(geom.collides for geom in geoms)
        # the loader scales by 1 where the file means ``meant``: 1/meant times too large
        far = any(v == 0 or max(abs(v), abs(1 / v)) >= CERTAINLY_WRONG for v in meant)
        (wrong if far else off).append((mesh, meant, collides))
    for found, severe in ((wrong, True), (off, False)):
        if not found:
            continue
        mesh, meant, _ = found[0]
        collides = any(c for _, _, c in found)
        factors = [f"{1 / v:.6g}" if v else "∞" for v in meant]
        factor = factors[0] + " times" if len(set(factors)) == 1 else " × ".join(factors)
        listed = names([_mesh_name(m) for m, _, _ in found])
        message = (
            f"ManiSkill's MJCF loader reads a mesh's scale only from the <mesh> element, not "
            f"from <default>: {len(found)} mesh(es) ({listed}) "
            f"load unscaled, '{_mesh_name(mesh)}' {factor} the size the file means (scale "
            f"{' '.join(f'{v:g}' for v in meant)})"
        )
        if collides:
            message += ", collision shapes and masses with it"
        hint = f'write scale="{" ".join(f"{v:g}" for v in meant)}" on each <mesh> element'
        report = error if severe and collides else warning
        yield report(loaded.where(_scale_source(loaded, mesh)), MJCF_MESH_SCALE, message, hint)


def _mesh_name(mesh: etree._Element) -> str:
    return mesh.get("name") or os.path.splitext(os.path.basename(mesh.get("file", "")))[0]


def _scale_source(loaded: LoadedMjcf, mesh: etree._Element) -> etree._Element:
    """The ``<default>``'s ``<mesh scale=...>`` that the mesh takes its scale from."""
    wanted = mesh.get("class", MAIN_CLASS)
    for section in (el for el in loaded.top if el.tag == "default"):
        for default in section.iter("default"):
            if default.get("class", MAIN_CLASS) != wanted:
                continue
            for candidate in (default, *default.iterancestors("default")):
                setting = next((m for m in candidate.findall("mesh") if "scale" in m.attrib), None)
                if setting is not None:
                    return setting
    return mesh


# -- geom types, groups and collision filters ----------------------------------------------------


def geom_types(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS079: geoms the loader fails on (anywhere) or skips (on the robot)."""
    failing = [
        element
        for element, attrs in parsed_elements(loaded)
        if element.tag == "geom" and "mesh" not in attrs and attrs.get("type") in ("hfield", "sdf")
    ]
    if failing:
        kinds = sorted({str(element.get("type")) for element in failing})
        yield error(
            loaded.where(failing[0]),
            MJCF_GEOM_TYPE,
            f"ManiSkill's MJCF loader cannot load {' or '.join(kinds)} geoms and raises "
            f"NotImplementedError{_elsewhere(failing)}: the file cannot be loaded at all (it "
            "parses every geom, robot or not)",
            "remove them from a copy of the model (ManiSkill's scenes have their own ground)",
        )
    # a body left without any shape is RS076's, an error that says why
    ghosts = ghost_bodies(loaded)
    skipped = [
        geom
        for geom in loaded.geoms()
        if geom.type in ("ellipsoid", "plane")
        and not any(geom.body is b or _below(geom.body, b) for b in ghosts)
    ]
    if skipped:
        links = sorted({geom.body.name for geom in skipped})
        yield warning(
            loaded.where(skipped[0].element),
            MJCF_GEOM_TYPE,
            f"ManiSkill's MJCF loader skips ellipsoid and plane geoms: {len(skipped)} of the "
            f"robot's are not loaded, and link(s) {names(links)} lack their collision shapes "
            "and the mass they give",
            "a sphere or capsule of about the same size in a copy of the model is loaded",
        )


def visual_groups(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS078: geoms MuJoCo draws that ManiSkill gives no visual body."""
    hidden = [
        geom
        for geom in loaded.geoms()
        if geom.int_attribute("group", 0) in MUJOCO_VISUAL_GROUPS
        and geom.int_attribute("group", 0) not in MANISKILL_VISUAL_GROUPS
        and geom.type in COLLISION_TYPES
    ]
    if hidden:
        links = sorted({geom.body.name for geom in hidden})
        yield warning(
            loaded.where(hidden[0].element),
            MJCF_VISUAL_GROUP,
            f"{len(hidden)} geom(s) of group 1, which MuJoCo draws, get no visual body in "
            f"ManiSkill (its MJCF loader draws groups 0 and 2 only): link(s) {names(links)} "
            "are drawn without them",
            "put them in group 2 in a copy of the model",
        )


def _bits(geom: LoadedGeom) -> tuple[int, int]:
    return geom.int_attribute("contype", 1), geom.int_attribute("conaffinity", 1)


def collision_filters(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS073: contacts MuJoCo's contype/conaffinity make that ManiSkill loses or adds."""
    geoms = [geom for geom in loaded.geoms() if geom.type in COLLISION_TYPES]
    contypes = [
        _int(attrs.get("contype"), 1)
        for element, attrs in parsed_elements(loaded)
        if element.tag == "geom"
    ]
    lost = [
        geom
        for geom in geoms
        if _bits(geom)[0] == 0 and _bits(geom)[1] != 0 and any(c & _bits(geom)[1] for c in contypes)
    ]
    if lost:
        links = sorted({geom.body.name for geom in lost})
        yield warning(
            loaded.where(lost[0].element),
            MJCF_COLLISION_FILTER,
            f"{len(lost)} geom(s) with contype=0 but conaffinity set collide in MuJoCo with "
            "geoms whose contype matches (a floor, say), but get no collision shape in "
            f"ManiSkill, which reads contype only: link(s) {names(links)} lose those contacts",
            "set contype to the conaffinity bits in a copy of the model",
        )
    added, any_mujoco = _collisions_added(loaded, geoms)
    if added:
        listed = ", ".join(f"[{a}, {b}]" for a, b in added[:12])
        hint = (
            "loader: {disable_self_collisions: true} (MuJoCo collides no two links of it)"
            if not any_mujoco
            else f"never_collide: [{listed}]"
            if len(added) <= 12
            else "list those pairs in never_collide"
        )
        first = next(geom for geom in geoms if geom.body.name in added[0] and geom.collides)
        yield warning(
            loaded.where(first.element),
            MJCF_COLLISION_FILTER,
            f"{len(added)} pair(s) of links never collide in MuJoCo (their geoms' contype and "
            "conaffinity share no bit) but do in ManiSkill, which collides every geom whose "
            f"contype is not 0: {', '.join(f'{a} + {b}' for a, b in added[:6])}"
            + (" ..." if len(added) > 6 else ""),
            hint,
        )


def filtered_pairs(loaded: LoadedMjcf) -> tuple[tuple[str, str], ...]:
    """The pairs of the robot's links (each sorted), both with collision shapes and not parent
    and child, that MuJoCo never lets collide and ManiSkill does: their geoms' contype and
    conaffinity share no bit (RS073's), or a ``<contact><exclude>`` names them (RS072's)."""
    geoms = [geom for geom in loaded.geoms() if geom.type in COLLISION_TYPES]
    added, _ = _collisions_added(loaded, geoms)
    shaped = {geom.body.name for geom in geoms if geom.collides}
    robot = {body.name for body in loaded.robot}
    parents = {b.name: b.parent.name for b in loaded.robot if b.parent is not None}
    excluded = [
        (a, b)
        for a, b in (sorted(pair) for pair in _excluded(loaded) if len(pair) == 2)
        if {a, b} <= shaped & robot and parents.get(a) != b and parents.get(b) != a
    ]
    return tuple(sorted({(min(a, b), max(a, b)) for a, b in [*added, *excluded]}))


def _excluded(loaded: LoadedMjcf) -> set[frozenset[str]]:
    """The body pairs the MJCF's ``<contact><exclude>``s name."""
    return {
        frozenset((el.get("body1", ""), el.get("body2", "")))
        for section in loaded.sections("contact")
        for el in loaded.includes.find_all(section, "exclude")
    }


def _int(text: str | None, default: int) -> int:
    try:
        return int(text) if text is not None else default
    except ValueError:
        return default


def _collisions_added(
    loaded: LoadedMjcf, geoms: list[LoadedGeom]
) -> tuple[list[tuple[str, str]], bool]:
    """Link pairs ManiSkill collides and MuJoCo does not, and whether MuJoCo collides any
    pair of the robot's links (not parent and child, which neither does)."""
    patterns: dict[str, set[tuple[int, int]]] = {}
    shaped: set[str] = set()
    for geom in geoms:
        patterns.setdefault(geom.body.name, set()).add(_bits(geom))
        if geom.collides:
            shaped.add(geom.body.name)
    parents = {b.name: b.parent.name for b in loaded.robot if b.parent is not None}
    excluded = _excluded(loaded)
    added: list[tuple[str, str]] = []
    any_mujoco = False
    order = [b.name for b in loaded.robot if b.name in patterns]
    for a, b in combinations(order, 2):
        if parents.get(a) == b or parents.get(b) == a or frozenset((a, b)) in excluded:
            continue
        mujoco = any(
            (ct1 & ca2) or (ct2 & ca1) for ct1, ca1 in patterns[a] for ct2, ca2 in patterns[b]
        )
        any_mujoco = any_mujoco or mujoco
        if not mujoco and a in shaped and b in shaped:
            added.append((a, b))
    return added, any_mujoco


# -- masses ---------------------------------------------------------------------------------------


def _volume(geom: LoadedGeom) -> float | None:
    """The volume SAPIEN gives the geom's collision shape; None for a mesh (its convex hull
    is not computed here)."""
    size = finite_numbers(geom.attributes.get("size")) or (1.0, 1.0, 1.0)
    kind = geom.type
    if kind == "sphere":
        return 4 / 3 * math.pi * size[0] ** 3
    if kind not in ("capsule", "cylinder", "box"):
        return None
    fromto = finite_numbers(geom.attributes.get("fromto"))
    if fromto is not None and len(fromto) == 6:
        half = math.dist(fromto[:3], fromto[3:]) / 2
    else:
        half = size[1] if len(size) > 1 else size[0]
    if kind == "box":
        sides = (*size, size[-1], size[-1])[:3]
        return 8 * sides[0] * sides[1] * sides[2]
    cylinder = math.pi * size[0] ** 2 * 2 * half
    return cylinder + (4 / 3 * math.pi * size[0] ** 3 if kind == "capsule" else 0.0)


def _loaded_mass(geoms: list[LoadedGeom]) -> float | None:
    """The link's mass in ManiSkill; None when a mesh makes it unknown here."""
    total = 0.0
    shapes = [geom for geom in geoms if geom.collides]
    for geom in shapes:
        volume = _volume(geom)
        if volume is None:
            return None
        density = finite_numbers(geom.attributes.get("density")) or (DENSITY,)
        total += density[0] * volume
    return total if shapes else EMPTY_LINK_MASS


def _file_mass(
    body: LoadedBody, geoms: list[LoadedGeom]
) -> tuple[float | None, etree._Element | None]:
    """The mass MuJoCo gives the body where the file sets one explicitly (an ``<inertial>``, or
    geoms with ``mass=``: the others then weigh their volume at their density, whatever their
    contype), and the element that sets it; (None, None) where the file sets none."""
    inertial = body.element.find("inertial")
    if inertial is not None:
        mass = finite_numbers(inertial.get("mass"))
        return (mass[0] if mass else None), inertial
    with_mass = [geom for geom in geoms if "mass" in geom.attributes]
    if not with_mass:
        return None, None
    total = 0.0
    for geom in geoms:
        if "mass" in geom.attributes:
            total += (finite_numbers(geom.attributes["mass"]) or (0.0,))[0]
            continue
        volume = _volume(geom)
        if volume is None:
            return None, with_mass[0].element
        total += (finite_numbers(geom.attributes.get("density")) or (DENSITY,))[0] * volume
    return total, with_mass[0].element


def masses(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS075: file masses the loader does not read, once for the robot."""
    by_body: dict[str, list[LoadedGeom]] = {}
    for geom in loaded.geoms():
        by_body.setdefault(geom.body.name, []).append(geom)
    rows: list[tuple[float, str]] = []
    first: etree._Element | None = None
    count = 0
    for body in loaded.robot:
        mass, element = _file_mass(body, by_body.get(body.name, []))
        if element is None:
            continue
        count += 1
        first = first if first is not None else element
        loaded_mass = _loaded_mass(by_body.get(body.name, []))
        if mass is None:
            continue
        if loaded_mass is None:
            rows.append((0.0, f"{body.name}: {mass:.4g} kg in the file"))
        elif not math.isclose(mass, loaded_mass, rel_tol=1e-3):
            ratio = max(mass, loaded_mass) / max(min(mass, loaded_mass), EMPTY_LINK_MASS)
            text = f"{body.name}: {mass:.4g} kg in the file, {loaded_mass:.4g} kg loaded"
            rows.append((ratio, text))
    if first is None:
        return
    rows.sort(key=lambda row: -row[0])
    shown = "; ".join(text for _, text in rows[:4]) + ("; ..." if len(rows) > 4 else "")
    yield warning(
        loaded.where(first),
        MJCF_MASSES,
        "ManiSkill's MJCF loader reads neither <inertial> nor geom mass=: each link weighs "
        f"what its collision geoms do at their density ({DENSITY:g} kg/m³ unless density= "
        f"says otherwise), so the file's masses of {count} bodies are not used"
        + (f" ({shown})" if rows else ""),
        MUJOCO_ROUTE,
    )


def ghost_bodies(loaded: LoadedMjcf) -> list[LoadedBody]:
    """Moving bodies with nothing below them that has a collision shape (the topmost of each
    such subtree): ManiSkill loads them as links of SAPIEN's minimum mass."""
    shaped = {geom.body.name for geom in loaded.geoms() if geom.collides}
    holds: dict[str, bool] = {}
    for body in reversed(loaded.robot):  # children come after their parent
        holds[body.name] = body.name in shaped or holds.get(body.name, False)
        if body.parent is not None and holds[body.name]:
            holds[body.parent.name] = True
    return [
        body
        for body in loaded.robot
        if body.moves
        and not holds[body.name]
        and not (body.parent is not None and body.parent.moves and not holds[body.parent.name])
    ]


def massless_links(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS076: :func:`ghost_bodies`, once for the robot."""
    found = ghost_bodies(loaded)
    if not found:
        return
    reasons = sorted(
        {
            _why_no_shape(geom)
            for body in found
            for geom in loaded.geoms()
            if geom.body.name == body.name or _below(geom.body, body)
        }
    )
    joints = [j.get("name", "") for body in found for j in body.joints]
    what = " and ".join(f"'{body.name}'" for body in found[:6]) + (" ..." if len(found) > 6 else "")
    yield error(
        loaded.where(found[0].element),
        MJCF_NO_MASS,
        f"ManiSkill's MJCF loader gives {what} and what hangs below no collision shape"
        + (f" ({'; '.join(reasons)})" if reasons else " (there are no geoms)")
        + f": a weightless ghost of SAPIEN's minimum mass, {EMPTY_LINK_MASS:g} kg, moves on "
        f"joint(s) {names(joints)} and touches nothing",
        "give each such body a geom the loader makes a collision shape of (sphere, capsule, "
        "cylinder, box or mesh with contype not 0) in a copy of the model, or " + MUJOCO_ROUTE,
    )


def _below(body: LoadedBody, ancestor: LoadedBody) -> bool:
    parent = body.parent
    while parent is not None:
        if parent is ancestor:
            return True
        parent = parent.parent
    return False


def _why_no_shape(geom: LoadedGeom) -> str:
    if geom.type not in COLLISION_TYPES:
        return f"{geom.type} geoms are skipped"
    if _bits(geom)[0] == 0:
        return "contype=0 geoms get none"
    return "its mesh file is missing"


# -- orientations -------------------------------------------------------------------------------


def orientations(loaded: LoadedMjcf) -> Iterator[Diagnostic]:
    """RS080: frames the loader fails on, and robot frames it reads differently."""
    failing: list[etree._Element] = []
    for element, attrs in parsed_elements(loaded):
        try:
            if maniskill_rotation(attrs, loaded.degrees) is None:
                failing.append(element)
        except Unparsable:
            continue
    if failing:
        mend = _quat_mend(loaded, failing)
        yield error(
            loaded.where(failing[0]),
            MJCF_ORIENTATION,
            "zaxis along ±z makes ManiSkill's MJCF loader divide by zero (LinAlgError: "
            f"Eigenvalues did not converge){_elsewhere(failing)}: the file cannot be loaded at all",
            "write the same rotation as quat= in a copy of the model (`description: {mend: "
            f"{{orientations: quat}}}}` does it): {mend}",
        )
    differing: list[tuple[etree._Element, str]] = []
    reasons: set[str] = set()
    for body in loaded.robot:
        if _differs(loaded, dict(body.element.attrib), full=True):
            differing.append((body.element, f"body {body.name}"))
            reasons.add(_MISREAD[orientation_attribute(body.element.attrib) or "euler"])
    for geom in loaded.geoms():
        if geom.type == "sphere" or geom.type not in COLLISION_TYPES or "fromto" in geom.attributes:
            continue
        full = geom.type not in ("capsule", "cylinder")
        if _differs(loaded, geom.attributes, full=full):
            differing.append((geom.element, f"geom {_label(geom)}"))
            reasons.add(_MISREAD[orientation_attribute(geom.attributes) or "euler"])
    if differing:
        yield error(
            loaded.where(differing[0][0]),
            MJCF_ORIENTATION,
            f"ManiSkill's MJCF loader reads {len(differing)} frame(s) of the robot turned "
            f"otherwise than MuJoCo ({names([what for _, what in differing])}): it "
            + ", ".join(sorted(reasons)),
            "write them as quat= in a copy of the model (`description: {mend: {orientations: "
            "quat}}` does it): " + _quat_mend(loaded, [element for element, _ in differing]),
        )


# what the loader does to each orientation attribute that makes a frame differ
_MISREAD = {
    "euler": "negates euler's second angle and ignores <compiler eulerseq>",
    "xyaxes": "takes xyaxes' y axis for the frame's z axis",
    "zaxis": "turns zaxis frames about their z axis",
    "quat": "reads quat as MuJoCo does",
    "axisangle": "reads axisangle as MuJoCo does",
}


def _differs(loaded: LoadedMjcf, attrs: dict[str, str], full: bool) -> bool:
    try:
        theirs = maniskill_rotation(attrs, loaded.degrees)
        meant = mujoco_rotation(attrs, loaded.degrees, loaded.eulerseq)
    except Unparsable:
        return False
    if theirs is None:
        return False  # reported as failing
    return not (same_rotation if full else same_axis)(theirs, meant)


def _quat_mend(loaded: LoadedMjcf, elements: list[etree._Element]) -> str:
    shown = []
    for element in elements[:3]:
        try:
            q = mujoco_rotation(element.attrib, loaded.degrees, loaded.eulerseq)
        except Unparsable:
            continue
        text = " ".join(f"{v:.6g}" if abs(v) > 1e-12 else "0" for v in q)
        shown.append(f'line {loaded.where(element).line}: quat="{text}"')
    return "; ".join(shown) + ("; ..." if len(elements) > 3 else "")
