"""What SAPIEN's URDF loader needs of a URDF's text, beyond the kinematic tree.

SAPIEN 3.0.3 parses a URDF with its copy of urchin (``sapien/wrapper/urchin/urdf.py``), which
reads every element it knows strictly: a missing attribute it needs, a word where it wants a
number or a shape element it does not know stops the load with a Python exception, even in
parts SAPIEN never uses (transmissions, materials). Each rule below is one such failure,
measured in tests/test_description_loader_rules.py, reported at the element instead:

- RS052: the element or number urchin needs (``<robot name>``, a ``<geometry>`` and its shape,
  ``<material name>`` and its ``rgba``, a texture's ``filename``, mesh ``scale`` as 3 numbers,
  ``<safety_controller k_velocity>``, gazebo camera sensors, duplicate material names);
- RS063 (robospec.description.urdf_values): a substitution left in a number;
- RS064: a ``<transmission>`` urchin cannot read (SAPIEN ignores transmissions once read, so
  removing it is always a fix).

The kinematic tree (links, joints, limits, mimic) is checked in robospec.description.urdf, and
inertials in robospec.description.inertia.
"""

from __future__ import annotations

from lxml import etree

from robospec.description.urdf_values import Findings, at, read_floats, read_text_float
from robospec.diagnostics import Diagnostic, error
from robospec.diagnostics.codes import BAD_TRANSMISSION, INVALID_STRUCTURE

# urchin's geometry elements and the attributes each needs (numbers, and how many).
_SHAPES: dict[str, tuple[tuple[str, int], ...]] = {
    "box": (("size", 3),),
    "cylinder": (("radius", 1), ("length", 1)),
    "capsule": (("radius", 1), ("length", 1)),
    "sphere": (("radius", 1),),
    "mesh": (),  # filename (any text) is checked below, scale is optional
}

_TRANSMISSION_HINT = (
    "SAPIEN reads transmissions but never uses them: removing the <transmission> is a fix"
)


def check_loader_rules(root: etree._Element, path: str) -> list[Diagnostic]:
    """Every problem SAPIEN's URDF parser would stop at, outside the kinematic tree."""
    found = Findings()
    if root.get("name") is None:
        found.add(
            error(
                at(path, root),
                INVALID_STRUCTURE,
                '<robot> has no name=""; SAPIEN\'s URDF parser needs one',
                '<robot name="my_robot">',
            )
        )
    _top_level_materials(root, path, found)
    for link in root.iterfind("link"):
        owner = f"link '{link.get('name')}'"
        for role in ("visual", "collision"):
            for element in link.iterfind(role):
                _shape(element, f"{owner} <{role}>", path, found)
        for material in link.iterfind("visual/material"):
            _material(material, f"{owner} <visual>", path, found)
    for joint in root.iterfind("joint"):
        _joint_extras(joint, path, found)
    _transmissions(root, path, found)
    _cameras(root, path, found)
    return found.result()


def _origin(element: etree._Element, what: str, path: str, found: Findings) -> None:
    origin = element.find("origin")
    if origin is not None:
        for attribute in ("xyz", "rpy"):
            read_floats(origin, attribute, 3, path, found.plain, f"{what} <origin>")


def _shape(element: etree._Element, what: str, path: str, found: Findings) -> None:
    """A ``<visual>`` or ``<collision>``: its origin, and a geometry urchin can build."""
    _origin(element, what, path, found)
    geometry = element.find("geometry")
    if geometry is None:
        found.add(
            error(
                at(path, element),
                INVALID_STRUCTURE,
                f"{what} has no <geometry>; SAPIEN's URDF parser needs one",
            )
        )
        return
    shapes = [child for child in geometry if child.tag in _SHAPES]
    if not shapes:
        others = [str(child.tag) for child in geometry if isinstance(child.tag, str)]
        found.add(
            error(
                at(path, geometry),
                INVALID_STRUCTURE,
                f"{what} <geometry> has "
                + (f"<{others[0]}>" if others else "nothing")
                + ", not one of box, cylinder, capsule, sphere or mesh: SAPIEN's URDF parser "
                "stops at it",
            )
        )
        return
    for shape in shapes:
        shape_what = f"{what} <{shape.tag!s}>"
        for attribute, count in _SHAPES[str(shape.tag)]:
            if shape.get(attribute) is None:
                found.add(_missing(path, shape, shape_what, attribute))
            else:
                read_floats(shape, attribute, count, path, found.plain, shape_what)
        if shape.tag == "mesh":
            if shape.get("filename") is None:
                found.add(_missing(path, shape, shape_what, "filename"))
            # SAPIEN multiplies the scale into a 3-vector: "1 1 1 1" is a TypeError
            read_floats(shape, "scale", 3, path, found.plain, shape_what)


def _missing(path: str, element: etree._Element, what: str, attribute: str) -> Diagnostic:
    return error(
        at(path, element),
        INVALID_STRUCTURE,
        f'{what} has no {attribute}=""; SAPIEN\'s URDF parser needs it',
    )


def _material(material: etree._Element, what: str, path: str, found: Findings) -> None:
    where = f"{what} <material>"
    if material.get("name") is None:
        found.add(_missing(path, material, where, "name"))
    else:
        where = f'{what} <material name="{material.get("name")}">'
    color = material.find("color")
    if color is not None:
        if color.get("rgba") is None:
            found.add(_missing(path, color, f"{where} <color>", "rgba"))
        else:
            read_floats(color, "rgba", 4, path, found.plain, f"{where} <color>")
    texture = material.find("texture")
    if texture is not None and texture.get("filename") is None:
        found.add(
            error(
                at(path, texture),
                INVALID_STRUCTURE,
                f'{where} has a <texture> without filename=""; SAPIEN\'s URDF parser stops at it',
                "remove the empty <texture/>, or name the image file",
            ),
            fold_as="more materials with an empty <texture/>",
        )


def _top_level_materials(root: etree._Element, path: str, found: Findings) -> None:
    first_line: dict[str, int] = {}
    for material in root.iterfind("material"):
        _material(material, "<robot>", path, found)
        name = material.get("name")
        if name is None:
            continue
        if name in first_line:
            found.add(
                error(
                    at(path, material),
                    INVALID_STRUCTURE,
                    f"duplicate material name '{name}' (first defined on line "
                    f"{first_line[name]}); SAPIEN's URDF parser stops at it",
                )
            )
        else:
            first_line[name] = at(path, material).line


def _joint_extras(joint: etree._Element, path: str, found: Findings) -> None:
    """The optional joint elements urchin reads numbers from (limits, origin, axis and mimic
    are read with the tree)."""
    what = f"joint '{joint.get('name')}'"
    dynamics = joint.find("dynamics")
    if dynamics is not None:
        for attribute in ("damping", "friction"):
            read_floats(dynamics, attribute, 1, path, found.plain, f"{what} <dynamics>")
    calibration = joint.find("calibration")
    if calibration is not None:
        for attribute in ("rising", "falling"):
            read_floats(calibration, attribute, 1, path, found.plain, f"{what} <calibration>")
    safety = joint.find("safety_controller")
    if safety is not None:
        where = f"{what} <safety_controller>"
        if safety.get("k_velocity") is None:
            found.add(_missing(path, safety, where, "k_velocity"))
        for attribute in ("k_velocity", "k_position", "soft_lower_limit", "soft_upper_limit"):
            read_floats(safety, attribute, 1, path, found.plain, where)


def _transmissions(root: etree._Element, path: str, found: Findings) -> None:
    for _transmission, problems in transmission_problems(root, path):
        for problem in problems:
            found.add(_as_transmission_problem(problem), fold_as="more transmission problems")


def unreadable_transmissions(root: etree._Element, path: str) -> list[tuple[etree._Element, str]]:
    """Each ``<transmission>`` SAPIEN's parser stops at, and the first reason why."""
    return [
        (transmission, problems[0].message.removesuffix(_STOPS))
        for transmission, problems in transmission_problems(root, path)
        if problems
    ]


_STOPS = "; SAPIEN's URDF parser stops at it"


def transmission_problems(
    root: etree._Element, path: str
) -> list[tuple[etree._Element, list[Diagnostic]]]:
    """Every ``<transmission>`` and what SAPIEN's parser cannot read in it (often nothing)."""
    first_line: dict[str, int] = {}
    result: list[tuple[etree._Element, list[Diagnostic]]] = []
    for transmission in root.iterfind("transmission"):
        name = transmission.get("name")
        what = f"transmission '{name}'" if name is not None else "<transmission>"
        problems: list[Diagnostic] = []
        if name is None:
            problems.append(_transmission_error(path, transmission, f'{what} has no name=""'))
        elif name in first_line:
            problems.append(
                _transmission_error(
                    path,
                    transmission,
                    f"duplicate transmission name '{name}' (first defined on line "
                    f"{first_line[name]})",
                )
            )
        else:
            first_line[name] = at(path, transmission).line
        if transmission.find("type") is None:
            old_style = transmission.get("type")
            problems.append(
                _transmission_error(
                    path,
                    transmission,
                    f"{what} has no <type> element"
                    + (
                        f' (type="{old_style}" is an attribute, the old URDF format)'
                        if old_style
                        else ""
                    ),
                )
            )
        for tag in ("joint", "actuator"):
            children = transmission.findall(tag)
            if not children:
                problems.append(_transmission_error(path, transmission, f"{what} has no <{tag}>"))
            for child in children:
                if child.get("name") is None:
                    problems.append(
                        _transmission_error(path, child, f'{what}: a <{tag}> has no name=""')
                    )
        for reduction in transmission.iterfind("actuator/mechanicalReduction"):
            read_text_float(reduction, path, problems, f"{what} <mechanicalReduction>")
        result.append((transmission, problems))
    return result


def _transmission_error(path: str, element: etree._Element, message: str) -> Diagnostic:
    return error(
        at(path, element),
        BAD_TRANSMISSION,
        f"{message}{_STOPS}",
        _TRANSMISSION_HINT,
    )


def _as_transmission_problem(problem: Diagnostic) -> Diagnostic:
    """A number in a transmission is RS064 too, with its hint: the mend is the same."""
    if problem.code == BAD_TRANSMISSION:
        return problem
    return error(
        problem.location,
        BAD_TRANSMISSION,
        f"{problem.message}{_STOPS}",
        problem.hint or _TRANSMISSION_HINT,
    )


def _cameras(root: etree._Element, path: str, found: Findings) -> None:
    """Camera sensors SAPIEN's loader reads (``<gazebo reference=...><sensor>`` and top-level
    ``<sensor>`` with a ``<parent>``), with its assertions: an image with a positive width and
    height, a field of view, numbers where it reads numbers."""
    sensors = [
        s
        for gazebo in root.iterfind("gazebo")
        if gazebo.get("reference") is not None
        for s in gazebo.iterfind("sensor")
    ]
    sensors += [s for s in root.iterfind("sensor") if s.find("parent") is not None]
    for sensor in sensors:
        camera = sensor.find("camera")
        if camera is None:
            continue
        what = f"camera sensor '{sensor.get('name')}'"
        origin = sensor.find("origin")
        if origin is not None:
            for attribute in ("xyz", "rpy"):
                if origin.get(attribute) is not None:
                    read_floats(origin, attribute, 3, path, found.plain, f"{what} <origin>")
        image = camera.find("image")
        if image is None:
            found.add(_camera_error(path, camera, f"{what} has no <image>"))
            continue
        for size in ("width", "height"):
            element = image.find(size)
            raw = element.text if element is not None else image.get(size)
            if not raw or not raw.strip().isdigit() or int(raw) <= 0:
                found.add(
                    _camera_error(
                        path,
                        element if element is not None else image,
                        f"{what} <image> {size} is {raw.strip() if raw else 'missing'!r}, not "
                        "a positive whole number",
                    )
                )
        if camera.find("horizontal_fov") is None and camera.find("vertical_fov") is None:
            if image.get("hfov") is None and image.get("vfov") is None:
                found.add(
                    _camera_error(path, camera, f"{what} has no horizontal_fov or vertical_fov")
                )
        for tag in ("horizontal_fov", "vertical_fov", "clip/near", "clip/far"):
            element = camera.find(tag)
            if element is not None:
                read_text_float(element, path, found.plain, f"{what} <{tag}>")


def _camera_error(path: str, element: etree._Element, message: str) -> Diagnostic:
    return error(
        at(path, element),
        INVALID_STRUCTURE,
        f"{message}: SAPIEN's URDF loader asserts on it",
        "fix the sensor, or remove it (robospec cameras are declared in the spec)",
    )
