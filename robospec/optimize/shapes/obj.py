"""OBJ files whose vertices reach PhysX exactly as written: assimp's OBJ reader, number by
number."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from robospec.optimize.outputs import MARK

if TYPE_CHECKING:
    import numpy as np

HEADER = f"# {MARK}\n"


def point_obj(points: np.ndarray) -> tuple[str, int]:
    """An OBJ whose vertices reach PhysX exactly as ``points``, in order. Assimp's OBJ reader makes
    one vertex per face corner, so the faces take the points three by three (the last repeated
    to fill a triangle: a repeated point changes nothing) -- a triangle soup, only a point set
    for the hull that PhysX cooks from it."""
    count = len(points)
    lines = [HEADER, "# the points of one convex collision shape, in the order PhysX reads them\n"]
    lines += [_vertex_line(p) for p in points]
    indices = [*range(1, count + 1)] + [count] * (-count % 3)
    lines += [f"f {a} {b} {c}\n" for a, b, c in zip(*[iter(indices)] * 3, strict=True)]
    return "".join(lines), count


def obj_text(vertices: np.ndarray, faces: np.ndarray) -> tuple[str, int]:
    lines = [HEADER, *(_vertex_line(v) for v in vertices)]
    lines += [f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces.tolist()]
    return "".join(lines), len(vertices)


def _vertex_line(vertex: Any) -> str:
    return "v " + " ".join(number(x) for x in vertex) + "\n"


# assimp's fast_atoreal_move (Real = float): the integer part, then at most 15 decimals read as
# double(digits) * 10^-n and added in float, then an exponent applied as f *= powf(10, exp)
_DECIMALS = [10.0**-n for n in range(16)]


def assimp_reads(text: str) -> float:
    import numpy as np

    negative = text.startswith("-")
    mantissa, _, exponent = text.lstrip("-").partition("e")
    whole, _, fraction = mantissa.partition(".")
    value = np.float32(float(int(whole or "0")))
    if fraction:
        fraction = fraction[:15]
        value = np.float32(value + np.float32(int(fraction) * _DECIMALS[len(fraction)]))
    if exponent:
        value = np.float32(value * np.float32(10.0 ** int(exponent)))
    return float(-value if negative else value)


def number(x: float) -> str:
    """``x`` as a float32 written so that assimp's OBJ reader reads back the same bits: PhysX's
    hull depends on every one (measured: a part of the G1's hip changes its volume by 1.5e-4 when
    values near 1e-9 are off by a rounding). Positional where that suffices (the shortest text,
    else more decimals); an exponent only for the tiny values 15 decimals cannot hold."""
    import numpy as np

    value = float(np.float32(x))
    text = np.format_float_positional(np.float32(x), unique=True, trim="-")
    if assimp_reads(text) == value:
        return text
    candidates = [f"{value:.{decimals}f}" for decimals in range(1, 16)]
    if value != 0:
        exponent = math.floor(math.log10(abs(value)))
        for shift in (0, -1, 1):
            scaled = value / 10.0 ** (exponent + shift)
            candidates += [f"{scaled:.{d}f}e{exponent + shift}" for d in range(6, 16)]
    for candidate in candidates:
        if assimp_reads(candidate) == value:
            return candidate
    return text
