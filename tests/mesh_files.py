"""Tiny meshes for the tests of mesh handling: the smallest files SAPIEN reads."""

from __future__ import annotations

# A tetrahedron, as ASCII STL: the smallest mesh SAPIEN cooks into a convex shape.
STL = """solid t
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 0.05 0
  vertex 0.05 0 0
 endloop
endfacet
facet normal 0 -1 0
 outer loop
  vertex 0 0 0
  vertex 0.05 0 0
  vertex 0 0 0.1
 endloop
endfacet
facet normal -1 0 0
 outer loop
  vertex 0 0 0
  vertex 0 0 0.1
  vertex 0 0.05 0
 endloop
endfacet
facet normal 1 1 1
 outer loop
  vertex 0.05 0 0
  vertex 0 0.05 0
  vertex 0 0 0.1
 endloop
endfacet
endsolid t
"""

# One triangle as binary STL: an 80-byte header, the count, 50 bytes per triangle.
BINARY_STL = (b"\0" * 80) + (1).to_bytes(4, "little") + (b"\0" * 50)
