"""Collision shapes SAPIEN simulates well: each link's collision meshes rewritten as files that
SAPIEN loads without complaint, or as fewer, simpler shapes.

What SAPIEN 3.0.3 builds from a ``<collision><mesh>`` (``sapien/wrapper/urdf_loader.py``,
``_parse_link``, and its C++ ``src/physx/mesh.cpp``):

- ``load_multiple_collisions_from_file`` false (ManiSkill's default): one PhysX convex hull of
  every vertex in the file (``add_convex_collision_from_file``); STL or not, no warning.
- true (ManiSkill's G1 and H1; ``BaseAgent.load_multiple_collisions``):
  ``add_multiple_convex_collisions_from_file`` -> ``PhysxConvexMesh::LoadByConnectedParts``. For
  ``.stl``/``.ply`` it is ``loadComponentVerticesFromMeshFileStlPly``: an STL prints "loading
  multiple convex collision meshes from STL file is unsupported ..." and is read with
  ``aiProcess_JoinIdenticalVertices``; ``splitMesh`` then cuts the mesh into its connected parts
  (a depth-first walk over the vertex graph) and each part's vertices, in walk order, are cooked
  into one PhysX convex hull (``vertexLimit = 255``). Any other format
  (``loadComponentVerticesFromMeshFileAssimpScene``) gives one convex hull per node of the
  file's scene: an OBJ of one object is one hull, read as written, without a warning.

PhysX's hull cooking depends on the order of its input points and on points inside the hull
(measured: cooking only the hull's vertices changes 8 of the G1's 122 parts), so ``convert``
writes each part's points in SAPIEN's walk order, one OBJ per part, one ``<collision>`` each.

Methods (``method=``): ``convert`` (that, for STL meshes; the behaviour stays), ``hull`` (one
convex OBJ per mesh, at most ``max_vertices`` vertices), ``coacd`` (a convex decomposition, one
OBJ per part), ``primitives`` (a box, capsule or sphere where one lies within ``max_error``
metres of the mesh's hull, each mesh not fitted becoming its ``convert`` shapes). A primitive
fit encloses the hull (the oriented bounding box, the thinnest capsule along its longest axis,
the smallest sphere), so its error is how far its surface stands off the hull at most
(:func:`~robospec.optimize.shapes.error_bound.fit_error`). A link whose mass SAPIEN takes from
its collision shapes (no usable ``<inertial>``) keeps its meshes: a primitive would change its
mass. trimesh and numpy are imported when the function runs (they cost a second).

The modules, one job each: :mod:`.mesh` (reading a mesh, SAPIEN's split), :mod:`.obj` (OBJ text
assimp reads back bit for bit), the methods :mod:`.hull`, :mod:`.decompose` (coacd) and
:mod:`.primitives` (with :mod:`.error_bound`, how far a primitive stands off the mesh),
:mod:`.elements` (the ``<collision>`` elements that replace one) and :mod:`.collisions`
(:func:`optimize_collisions`, which runs a method over every link).
"""

from robospec.optimize.shapes.collisions import METHODS, ShapeChange, optimize_collisions
from robospec.optimize.shapes.decompose import MissingDependency

__all__ = ["METHODS", "MissingDependency", "ShapeChange", "optimize_collisions"]
