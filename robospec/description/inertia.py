"""Masses and inertias as SAPIEN loads them, checked at the URDF's ``<inertial>``.

SAPIEN 3.0.3's URDF loader (``URDFLoader._build_link``) uses an ``<inertial>`` only when its mass
is not 0 and its inertia not all zeros; otherwise it ignores the whole element and PhysX
computes the link's mass and inertia from its collision shapes (density 1000), or gives a link
without any 1e-6 kg. A used inertia is diagonalised (as written when it is diagonal, else by
``numpy.linalg.eigh``) and every principal moment must be > 0: else it asserts ``invalid moment
of inertia`` and the robot does not load. So:

- RS059 (error): the inertia SAPIEN asserts on. Where the matrix is not diagonal and its
  smallest principal moment is within rounding of 0 (within 1e-14 of the largest), whether
  ``eigh`` lands above or below 0 is chance: robospec reports that singular inertia too.
- RS060 (error): a negative mass; PhysX replaces it with 1 kg and a unit inertia.
- RS061 (warning): an inertial SAPIEN ignores although it says something (a mass with an
  all-zero inertia, or mass 0 with an inertia); mass 0 with inertia 0 is the usual way to
  write a massless frame and is not reported.
- RS062 (warning): principal moments that break the triangle inequality (the two smaller sum
  to less than the largest): no rigid body has them, SAPIEN and PhysX take them anyway.

Only the standard library: a 3×3 symmetric eigenproblem has a closed form, and numpy costs the
``validate`` path 0.1 s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from lxml import etree

from robospec.description.urdf_values import Findings, at, read_floats
from robospec.diagnostics import Diagnostic, error, warning
from robospec.diagnostics.codes import (
    IGNORED_INERTIAL,
    INVALID_INERTIA,
    INVALID_STRUCTURE,
    NEGATIVE_MASS,
    TRIANGLE_INEQUALITY,
)
from robospec.geometry import Matrix, turned

INERTIA_ATTRIBUTES = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")  # URDF's <inertia>, in this order
# What PhysX makes of a link SAPIEN takes no <inertial> of: its collision shapes at this density
# (kg/m³; MuJoCo's default and ManiSkill's MJCF loader's too), or without any, this mass (kg,
# and this inertia, kg·m², about each of its axes).
DENSITY = 1000.0
EMPTY_LINK_MASS = 1e-6
# Below this fraction of the largest principal moment, the smallest is rounding noise.
_SINGULAR = 1e-14
# Principal moments read from a file are rounded: a sum short of the largest by less than this
# fraction is a body at the limit (a thin plate), not a broken one.
_TRIANGLE_SLACK = 1e-3


def stated_masses(root: etree._Element) -> dict[str, float]:
    """Link -> the mass its ``<inertial>`` states (kg), for the links of a URDF that state a
    finite one: what the description says, whether or not SAPIEN takes it (RS061)."""
    found = {}
    for link in root.iterfind("link"):
        element = link.find("inertial/mass")
        try:
            mass = float(element.get("value", "")) if element is not None else math.nan
        except ValueError:
            continue
        if math.isfinite(mass) and link.get("name"):
            found[str(link.get("name"))] = mass
    return found


def check_inertials(root: etree._Element, path: str) -> list[Diagnostic]:
    """Every link's ``<inertial>``: readable as urchin reads it, and physically valid."""
    found = Findings()
    impossible: list[_Impossible] = []
    for link in root.iterfind("link"):
        inertial = link.find("inertial")
        if inertial is not None:
            broken = _check(inertial, f"link '{link.get('name')}'", path, found)
            if broken is not None:
                impossible.append(broken)
    if impossible:
        found.add(_triangle_warning(path, impossible))
    return found.result()


@dataclass(frozen=True)
class _Impossible:
    """An inertia that breaks the triangle inequality: where, and its principal moments."""

    what: str
    element: etree._Element
    moments: tuple[float, float, float]


def _triangle_warning(path: str, impossible: list[_Impossible]) -> Diagnostic:
    """One warning for the whole description: SAPIEN takes these inertias, and a description
    that has one usually has several (ManiSkill's own Allegro hand has twelve)."""
    first = impossible[0]
    low, middle, high = first.moments
    others = impossible[1:]
    listed = ", ".join(
        f"{o.what.removeprefix('link ')} (line {at(path, o.element).line})" for o in others[:4]
    )
    more = f" and {len(others) - 4} more" if len(others) > 4 else ""
    also = f"; so do the inertias of links {listed}{more}" if others else ""
    return warning(
        at(path, first.element),
        TRIANGLE_INEQUALITY,
        f"{first.what}: principal moments {_shown(first.moments)} break the triangle "
        f"inequality ({low:.3g} + {middle:.3g} < {high:.3g}): no rigid body has them{also}",
        "SAPIEN and PhysX simulate them anyway; check the inertia (its units, and whether it "
        "is about the centre of mass)",
    )


def _check(inertial: etree._Element, what: str, path: str, found: Findings) -> _Impossible | None:
    """Report what is wrong with one ``<inertial>``; an inertia that only breaks the triangle
    inequality is returned instead (reported once per description)."""
    diagnostics = found.plain
    origin = inertial.find("origin")
    if origin is not None:
        for attribute in ("xyz", "rpy"):
            read_floats(origin, attribute, 3, path, diagnostics, f"{what} <inertial> <origin>")
    mass_element = inertial.find("mass")
    inertia_element = inertial.find("inertia")
    mass = _mass(inertial, mass_element, what, path, diagnostics)
    moments = _inertia(inertial, inertia_element, what, path, diagnostics)
    if mass is None or moments is None:
        return None
    assert mass_element is not None and inertia_element is not None
    xx, xy, xz, yy, yz, zz = moments
    all_zero = not any(moments)
    if mass == 0 or all_zero:
        if not (mass == 0 and all_zero):
            said = f"mass {mass:g}" if all_zero else "an inertia"
            found.add(
                warning(
                    at(path, inertial),
                    IGNORED_INERTIAL,
                    f"{what}: SAPIEN ignores this <inertial> (mass 0 or an all-zero inertia), "
                    f"{said} included; the link's mass comes from its collision shapes "
                    "(density 1000), or is 1e-6 kg without any",
                    "give both a positive mass and the inertia, or neither",
                ),
                fold_as="more inertials SAPIEN ignores",
            )
        return None
    if mass < 0:
        diagnostics.append(
            error(
                at(path, mass_element),
                NEGATIVE_MASS,
                f"{what} has mass {mass:g}; PhysX replaces a mass that is not positive with 1 kg",
                "write the link's mass in kg (mass 0 and an all-zero inertia let SAPIEN "
                "compute both from the collision shapes)",
            )
        )
    principal = principal_moments(xx, xy, xz, yy, yz, zz)
    smallest, largest = principal[0], principal[2]
    diagonal = xy == 0 and xz == 0 and yz == 0
    # SAPIEN takes a diagonal as it is; otherwise eigh's rounding decides a moment near 0
    noise = 0.0 if diagonal else _SINGULAR * abs(largest)
    if smallest <= noise:
        if smallest < -noise or diagonal:
            said = "SAPIEN asserts 'invalid moment of inertia'"
        else:
            said = (
                "the inertia is singular: whether SAPIEN asserts 'invalid moment of inertia' "
                "is up to rounding, and a link that loads resists no torque about one axis"
            )
        diagnostics.append(
            error(
                at(path, inertia_element),
                INVALID_INERTIA,
                f"{what}: {said}: the principal moments are {_shown(principal)}, and every one "
                "must be > 0",
                _inertia_hint(xx, yy, zz, diagonal),
            )
        )
        return None
    if principal[0] + principal[1] < principal[2] * (1 - _TRIANGLE_SLACK):
        return _Impossible(what, inertia_element, principal)
    return None


def _mass(
    inertial: etree._Element,
    element: etree._Element | None,
    what: str,
    path: str,
    diagnostics: list[Diagnostic],
) -> float | None:
    if element is None or element.get("value") is None:
        diagnostics.append(
            error(
                at(path, element if element is not None else inertial),
                INVALID_STRUCTURE,
                f'{what} <inertial> has no <mass value="..."/>; SAPIEN\'s URDF parser stops at it',
            )
        )
        return None
    values = read_floats(element, "value", 1, path, diagnostics, f"{what} <mass>")
    return values[0] if values else None


def _inertia(
    inertial: etree._Element,
    element: etree._Element | None,
    what: str,
    path: str,
    diagnostics: list[Diagnostic],
) -> tuple[float, ...] | None:
    if element is None:
        diagnostics.append(
            error(
                at(path, inertial),
                INVALID_STRUCTURE,
                f"{what} <inertial> has no <inertia>; SAPIEN's URDF parser stops at it",
            )
        )
        return None
    missing = [a for a in INERTIA_ATTRIBUTES if element.get(a) is None]
    if missing:
        diagnostics.append(
            error(
                at(path, element),
                INVALID_STRUCTURE,
                f"{what} <inertia> has no {', '.join(missing)}; SAPIEN's URDF parser needs all six",
            )
        )
        return None
    values = [
        read_floats(element, a, 1, path, diagnostics, f"{what} <inertia>")
        for a in INERTIA_ATTRIBUTES
    ]
    if any(v is None for v in values):
        return None
    return tuple(v[0] for v in values if v is not None)


def principal_moments(
    xx: float, xy: float, xz: float, yy: float, yz: float, zz: float
) -> tuple[float, float, float]:
    """The eigenvalues of the symmetric inertia matrix, smallest first (Smith's closed form;
    exact for a diagonal matrix, as SAPIEN takes the diagonal itself)."""
    off = xy * xy + xz * xz + yz * yz
    if off == 0:
        return tuple(sorted((xx, yy, zz)))  # type: ignore[return-value]
    mean = (xx + yy + zz) / 3
    spread = math.sqrt(((xx - mean) ** 2 + (yy - mean) ** 2 + (zz - mean) ** 2 + 2 * off) / 6)
    # B = (A - mean I) / spread; det(B) / 2 is cos(3 phi)
    bxx, byy, bzz = (xx - mean) / spread, (yy - mean) / spread, (zz - mean) / spread
    bxy, bxz, byz = xy / spread, xz / spread, yz / spread
    det = (
        bxx * (byy * bzz - byz * byz)
        - bxy * (bxy * bzz - byz * bxz)
        + bxz * (bxy * byz - byy * bxz)
    )
    phi = math.acos(max(-1.0, min(1.0, det / 2))) / 3
    largest = mean + 2 * spread * math.cos(phi)
    smallest = mean + 2 * spread * math.cos(phi + 2 * math.pi / 3)
    return smallest, 3 * mean - largest - smallest, largest


def _shown(values: tuple[float, ...]) -> str:
    return ", ".join(f"{v:.4g}" for v in values)


def _inertia_hint(xx: float, yy: float, zz: float, diagonal: bool) -> str:
    if not diagonal and min(xx, yy, zz) > 0:
        return (
            f"with ixy, ixz and iyz set to 0 the moments are {_shown((xx, yy, zz))}, which "
            "SAPIEN accepts; or write the link's real inertia"
        )
    return "write the link's real inertia (or mass 0 and all six 0: SAPIEN then computes both)"


def rejected(xx: float, xy: float, xz: float, yy: float, yz: float, zz: float) -> bool:
    """Whether SAPIEN rejects this inertia (or takes it by rounding luck): RS059's rule."""
    principal = principal_moments(xx, xy, xz, yy, yz, zz)
    diagonal = xy == 0 and xz == 0 and yz == 0
    noise = 0.0 if diagonal else _SINGULAR * abs(principal[2])
    return principal[0] <= noise


def impossible(moments: tuple[float, float, float]) -> bool:
    """Whether principal moments (smallest first) break the triangle inequality: RS062's rule."""
    return moments[0] + moments[1] < moments[2] * (1 - _TRIANGLE_SLACK)


def principal_axes(
    xx: float, xy: float, xz: float, yy: float, yz: float, zz: float
) -> tuple[tuple[float, float, float], Matrix]:
    """The principal moments and axes (the columns of a rotation) of a symmetric inertia, by
    cyclic Jacobi rotations: exact to rounding, and no numpy on the validate path."""
    a = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]
    v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    for _sweep in range(50):
        off = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2
        scale = a[0][0] ** 2 + a[1][1] ** 2 + a[2][2] ** 2
        if off <= 1e-30 * max(scale, 1e-300):
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if a[p][q] == 0.0:
                continue
            theta = (a[q][q] - a[p][p]) / (2 * a[p][q])
            t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1))
            c = 1 / math.sqrt(t * t + 1)
            s = t * c
            for k in range(3):  # A <- A J (columns p, q)
                akp, akq = a[k][p], a[k][q]
                a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
            for k in range(3):  # A <- J^T A (rows p, q)
                apk, aqk = a[p][k], a[q][k]
                a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
            for k in range(3):
                vkp, vkq = v[k][p], v[k][q]
                v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    moments = (a[0][0], a[1][1], a[2][2])
    return moments, tuple(tuple(row) for row in v)  # type: ignore[return-value]


def from_axes(moments: tuple[float, float, float], axes: Matrix) -> tuple[float, ...]:
    """The inertia ``R diag(moments) R^T`` as (ixx, ixy, ixz, iyy, iyz, izz)."""
    diagonal = ((moments[0], 0.0, 0.0), (0.0, moments[1], 0.0), (0.0, 0.0, moments[2]))
    m = turned(axes, diagonal)
    return (m[0][0], m[0][1], m[0][2], m[1][1], m[1][2], m[2][2])
