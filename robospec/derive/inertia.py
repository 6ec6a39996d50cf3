"""Mend class ``inertia`` (RS706): inertias SAPIEN rejects, or that no rigid body has.

SAPIEN asserts ``invalid moment of inertia`` on an inertia whose principal moments are not all
positive, and takes a singular one by rounding luck (RS059: Go1's and ANYmal's products of
inertia cancel their moments, iCub's heads are all but zero); principal moments that break the
triangle inequality load but are no body (RS062). The policies, in the spirit of MuJoCo's
compiler options, are tried in the order given on each inertia that needs one; the first that
makes it valid is written:

- ``diagonal``: the products of inertia set to 0, when the diagonal alone is valid (the usual
  fault: products exported with the wrong sign or frame);
- ``bound``: every principal moment raised to at least ``m (2 mm)²`` (a radius of gyration of
  2 mm, below any real link's), the principal axes kept (MuJoCo's ``boundinertia``): for
  inertias SAPIEN rejects, and for those far too small for their mass (iCub's legs have radii
  of gyration of 1e-10 m, and explode at the first step);
- ``shapes``: the inertia of a solid box around the link's collision shapes, at its mass (in
  the spirit of MuJoCo's ``inertiafromgeom``): for inertias SAPIEN rejects, far too small, or
  all zero beside a mass (which SAPIEN would ignore, taking the mass from the shapes' volume);
- ``balance``: principal moments that break the triangle inequality (or are not positive)
  set to their mean, when that is positive (MuJoCo's ``balanceinertia``).

Only the inertias that need what the policies do are touched: a massless frame (mass 0) is
left to SAPIEN, and an all-zero inertia beside a mass only by ``shapes`` and ``bound``.
"""

from __future__ import annotations

from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.description.inertia import (
    INERTIA_ATTRIBUTES,
    from_axes,
    impossible,
    principal_axes,
    principal_moments,
    rejected,
)
from robospec.description.shapes import Box, box_inertia, collision_box
from robospec.diagnostics.codes import (
    CANNOT_MEND,
    INVALID_INERTIA,
    MENDED_INERTIAS,
    TRIANGLE_INEQUALITY,
)

NAME = "inertia"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = MENDED_INERTIAS
FIXES = (INVALID_INERTIA, TRIANGLE_INEQUALITY)
WHY = "SAPIEN rejects these inertias ('invalid moment of inertia'), or they are far too small"

_GYRATION = 0.002  # m: the bound's radius of gyration about each principal axis
TOO_SMALL_GYRATION = 1e-4  # m: a radius of gyration no link has (new writes the bound)
_FLOOR = 1e-12  # kg m^2: the bound of a link whose mass says nothing


def apply(document: Document, policy: str | list[str]) -> None:
    policies = [policy] if isinstance(policy, str) else list(policy)
    for link in document.tree.iterfind("link"):
        inertia = link.find("inertial/inertia")
        mass = _mass(link)
        values = _values(inertia)
        if inertia is None or values is None or mass is None or mass == 0:
            continue  # unreadable (its own error), or a massless frame SAPIEN computes
        sizing = "bound" in policies or "shapes" in policies
        if not any(values) and not (mass > 0 and sizing):
            continue  # ignored by SAPIEN, which computes mass and inertia from the shapes
        if _acceptable(values, mass, policies):
            continue
        moments = principal_moments(*values)
        box = (
            collision_box(link, document.source.path, document.source.packages)
            if "shapes" in policies
            else None
        )
        for name in policies:
            mended = _shapes(mass, box) if name == "shapes" else _POLICIES[name](values, mass)
            if mended is not None and _acceptable(mended, mass, policies):
                _write(inertia, mended)
                document.changed(
                    inertia,
                    f"link '{link.get('name')}' <inertia>",
                    f"principal moments {_shown(moments)}",
                    f"{_shown(principal_moments(*mended))} ({name})",
                )
                break
        else:
            if rejected(*values):  # one that loads anyway is left as it is: RS062 says so
                document.refuse(
                    inertia,
                    CANNOT_MEND,
                    f"mend 'inertia: {policy}' cannot mend link '{link.get('name')}': principal "
                    f"moments {_shown(moments)}",
                    _advice(policies),
                )


def _acceptable(values: tuple[float, ...], mass: float, policies: list[str]) -> bool:
    """Whether an inertia needs none of the policies asked: SAPIEN takes it, and it is not
    below the bound or impossible where those are asked for."""
    sizing = "bound" in policies or "shapes" in policies
    if not any(values):
        return not sizing  # SAPIEN ignores it: these give the file's mass an inertia
    if rejected(*values):
        return False
    moments = principal_moments(*values)
    if "bound" in policies and moments[0] < _floor(mass, moments) * (1 - 1e-6):
        return False
    if "shapes" in policies and moments[0] < mass * TOO_SMALL_GYRATION**2:
        return False
    return not ("balance" in policies and impossible(moments))


def _floor(mass: float, moments: tuple[float, float, float]) -> float:
    """The bound: a radius of gyration of ``_GYRATION`` about every axis (and above rounding
    noise of the largest moment)."""
    return max(abs(mass) * _GYRATION**2, _FLOOR, 1e-12 * max(abs(m) for m in moments))


def suggest(document: Document) -> list[str] | str | None:
    """``diagonal`` where it mends every inertia that needs mending; else the policies of
    ``diagonal``, ``shapes``, ``bound`` (in that order) that mend something."""
    tiny = _far_too_small(document)
    if not tiny and document.would_change(apply, "diagonal"):
        return "diagonal"
    if not tiny and not _any_rejected(document):
        return None
    everything = ["diagonal", "shapes", "bound"]
    trial = document.trial()
    apply(trial, everything)
    if not trial.changes or trial.refusals:
        return None
    used = [p for p in everything if any(c.after.endswith(f"({p})") for c in trial.changes)]
    return used[0] if len(used) == 1 else used


def _any_rejected(document: Document) -> bool:
    for link in document.tree.iterfind("link"):
        values, mass = _values(link.find("inertial/inertia")), _mass(link)
        if values is not None and mass and any(values) and rejected(*values):
            return True
    return False


def _far_too_small(document: Document) -> bool:
    """Whether a used inertia is so small for its link's mass that PhysX cannot solve it (a
    radius of gyration under 0.1 mm: iCub's legs have 1e-10 m, and explode at once)."""
    for link in document.tree.iterfind("link"):
        values, mass = _values(link.find("inertial/inertia")), _mass(link)
        if values is None or mass is None or mass <= 0 or not any(values) or rejected(*values):
            continue
        if principal_moments(*values)[0] < mass * TOO_SMALL_GYRATION**2:
            return True
    return False


def _advice(policies: list[str]) -> str:
    missing = [p for p in ("diagonal", "shapes", "bound") if p not in policies]
    if missing:
        return (
            f"add '{missing[-1]}' (inertia: [{', '.join([*policies, missing[-1]])}]), or "
            "write the link's real inertia"
        )
    return "write the link's real inertia"


def _diagonal(values: tuple[float, ...], mass: float) -> tuple[float, ...] | None:
    xx, _xy, _xz, yy, _yz, zz = values
    if min(xx, yy, zz) <= 0:
        return None
    return (xx, 0.0, 0.0, yy, 0.0, zz)


def _bound(values: tuple[float, ...], mass: float) -> tuple[float, ...] | None:
    moments, axes = principal_axes(*values)
    floor = _floor(mass, moments)
    bounded = (max(moments[0], floor), max(moments[1], floor), max(moments[2], floor))
    return from_axes(bounded, axes)


def _balance(values: tuple[float, ...], mass: float) -> tuple[float, ...] | None:
    moments, axes = principal_axes(*values)
    mean = sum(moments) / 3
    if mean <= 0:
        return None
    return from_axes((mean, mean, mean), axes)


def _shapes(mass: float, box: Box | None) -> tuple[float, ...] | None:
    if box is None or min(box[1][i] - box[0][i] for i in range(3)) <= 0:
        return None
    return box_inertia(mass, box)


_POLICIES = {"diagonal": _diagonal, "bound": _bound, "balance": _balance}


def _mass(link: etree._Element) -> float | None:
    element = link.find("inertial/mass")
    try:
        return float(element.get("value", "")) if element is not None else None
    except ValueError:
        return None


def _values(inertia: etree._Element | None) -> tuple[float, ...] | None:
    if inertia is None:
        return None
    try:
        return tuple(float(inertia.get(a, "")) for a in INERTIA_ATTRIBUTES)
    except ValueError:
        return None


def _write(inertia: etree._Element, values: tuple[float, ...]) -> None:
    for attribute, value in zip(INERTIA_ATTRIBUTES, values, strict=True):
        inertia.set(attribute, _number(value))


def _number(value: float) -> str:
    text = f"{value:.12g}"
    return "0" if text in ("0", "-0") else text


def _shown(values: tuple[float, ...]) -> str:
    return ", ".join(f"{v:.4g}" for v in values)
