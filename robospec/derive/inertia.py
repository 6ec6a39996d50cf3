"""Mend class ``inertia`` (RS706): inertias SAPIEN rejects, or that no rigid body has.

SAPIEN asserts ``invalid moment of inertia`` on an inertia whose principal moments are not all
positive, and takes a singular one by rounding luck (RS059: Go1's and ANYmal's products of
inertia cancel their moments, iCub's heads are all but zero); principal moments that break the
triangle inequality load but are no body (RS062). The policies, in the spirit of MuJoCo's
compiler options, are tried in the order given on each inertia that needs one; the first that
makes it valid is written:

- ``diagonal``: the products of inertia set to 0, when the diagonal alone is valid (the usual
  fault: products exported with the wrong sign or frame);
- ``bound``: every principal moment raised to at least that of a solid sphere of the link's
  mass 1 cm in radius (``0.4 m r²``), the principal axes kept (MuJoCo's ``boundinertia``);
- ``balance``: principal moments that break the triangle inequality (or are not positive)
  set to their mean, when that is positive (MuJoCo's ``balanceinertia``).

Only the inertias that need mending are touched; SAPIEN ignores an inertial with mass 0 or an
all-zero inertia, so those are left alone (mend ``mass`` speaks for them).
"""

from __future__ import annotations

from typing import Literal

from lxml import etree

from robospec.derive.document import Document
from robospec.derive.mend import CANNOT_MEND
from robospec.description.inertia import (
    from_axes,
    impossible,
    principal_axes,
    principal_moments,
    rejected,
)

NAME = "inertia"
KINDS = frozenset({"urdf"})
STAGE: Literal["text", "tree"] = "tree"
CODE = "RS706"
FIXES = ("RS059", "RS062")
WHY = "SAPIEN rejects these inertias ('invalid moment of inertia')"

_ATTRIBUTES = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_SPHERE_RADIUS = 0.01  # m: the bound is the inertia of a solid sphere this size
_FLOOR = 1e-12  # kg m^2: the bound of a link whose mass says nothing


def apply(document: Document, policy: str | list[str]) -> None:
    policies = [policy] if isinstance(policy, str) else list(policy)
    for link in document.tree.iterfind("link"):
        inertia = link.find("inertial/inertia")
        mass = _mass(link)
        values = _values(inertia)
        if inertia is None or values is None or mass is None or mass == 0 or not any(values):
            continue  # unreadable (its own error), or ignored by SAPIEN
        moments = principal_moments(*values)
        broken = rejected(*values)
        if not broken and not ("balance" in policies and impossible(moments)):
            continue
        for name in policies:
            mended = _POLICIES[name](values, mass)
            if (
                mended is not None
                and not rejected(*mended)
                and not (name == "balance" and impossible(principal_moments(*mended)))
            ):
                _write(inertia, mended)
                document.changed(
                    inertia,
                    f"link '{link.get('name')}' <inertia>",
                    f"principal moments {_shown(moments)}",
                    f"{_shown(principal_moments(*mended))} ({name})",
                )
                break
        else:
            if broken:  # a triangle-only fault left as it is loads anyway: RS062 says so
                document.refuse(
                    inertia,
                    CANNOT_MEND,
                    f"mend 'inertia: {policy}' cannot mend link '{link.get('name')}': principal "
                    f"moments {_shown(moments)}",
                    _advice(policies),
                )


def suggest(document: Document) -> list[str] | str | None:
    """``diagonal`` where it mends every rejected inertia, ``bound`` where it alone does, else
    both in that order."""
    for policy in ("diagonal", "bound"):
        if document.would_change(apply, policy):
            return policy
    both = ["diagonal", "bound"]
    return both if document.would_change(apply, both) else None


def _advice(policies: list[str]) -> str:
    missing = [p for p in ("diagonal", "bound") if p not in policies]
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
    floor = max(0.4 * abs(mass) * _SPHERE_RADIUS**2, _FLOOR)
    # rounding must not undo the bound: the smallest moment is kept above rounding noise
    floor = max(floor, 1e-12 * max(abs(m) for m in moments))
    bounded = (max(moments[0], floor), max(moments[1], floor), max(moments[2], floor))
    return from_axes(bounded, axes)


def _balance(values: tuple[float, ...], mass: float) -> tuple[float, ...] | None:
    moments, axes = principal_axes(*values)
    mean = sum(moments) / 3
    if mean <= 0:
        return None
    return from_axes((mean, mean, mean), axes)


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
        return tuple(float(inertia.get(a, "")) for a in _ATTRIBUTES)
    except ValueError:
        return None


def _write(inertia: etree._Element, values: tuple[float, ...]) -> None:
    for attribute, value in zip(_ATTRIBUTES, values, strict=True):
        inertia.set(attribute, _number(value))


def _number(value: float) -> str:
    text = f"{value:.12g}"
    return "0" if text in ("0", "-0") else text


def _shown(values: tuple[float, ...]) -> str:
    return ", ".join(f"{v:.4g}" for v in values)
