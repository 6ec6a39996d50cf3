"""``coacd``: a convex decomposition of each mesh (the coacd package, an optional dependency),
each part a capped hull."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from robospec.optimize.shapes.hull import capped_hull
from robospec.optimize.shapes.mesh import Mesh

if TYPE_CHECKING:
    import numpy as np


class MissingDependency(Exception):
    """A method needs a package that is not installed: the caller turns it into a diagnostic."""

    def __init__(self, package: str, hint: str) -> None:
        super().__init__(f"robospec optimize needs the {package} package for this method")
        self.package = package
        self.hint = hint


def import_coacd() -> Any:
    try:
        import coacd
    except ImportError as error:
        raise MissingDependency("coacd", "pip install 'robospec[optimize]'") from error
    return coacd


def coacd_hulls(
    mesh: Mesh, max_vertices: int | None, threshold: float
) -> list[tuple[np.ndarray, np.ndarray]]:
    import numpy as np

    coacd = import_coacd()
    coacd.set_log_level("error")
    parts = coacd.run_coacd(
        coacd.Mesh(np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces)),
        threshold=threshold,  # the concavity each part may keep
        seed=0,  # the same parts every run
        max_ch_vertex=max_vertices or 256,
    )
    return [capped_hull(np.asarray(vertices), max_vertices) for vertices, _ in parts]
