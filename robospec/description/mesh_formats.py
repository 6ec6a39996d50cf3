"""Whether SAPIEN can read a mesh file, judged from its name and first bytes (no mesh library).

SAPIEN 3.0.3 reads collision and visual meshes with the Open Asset Import Library (assimp,
inside its renderer library), which picks a reader by the file's suffix, case-insensitively,
and only for a suffix it has no reader for by the file's first bytes (so a binary STL named
``.txt`` or with no suffix at all is not read: it has no signature). A file assimp cannot read
makes PhysX's ``cookConvexMesh`` fail, and SAPIEN's actor builder drops the collision shape
without a word (``except RuntimeError: continue``). These checks are measured against SAPIEN
in tests/test_description_meshes.py; they look only at what is cheap to look at, so a file that
passes them can still be broken inside.
"""

from __future__ import annotations

import os
import struct
from collections.abc import Callable

# The suffixes of assimp's importers in SAPIEN's build (their names are in libsvulkan2.so),
# and USD, which SAPIEN converts to glTF before loading.
ASSIMP_SUFFIXES: frozenset[str] = frozenset(
    """3d 3ds 3mf ac ac3d acc amf ase ask assbin b3d bvh cob dae dxf enff fbx glb gltf hmp ifc
    ifczip iqm irr irrmesh lwo lws lxo md2 md3 md5anim md5camera md5mesh mdc mdl mesh mot ms3d
    ndo nff obj off pk3 ply pmx prj q3o q3s raw scn sib smd stl ter uc vta x x3d x3db xgl xml
    zae zgl usd usda usdc usdz""".split()
)

_Check = Callable[[bytes, int], "str | None"]

# How much of a file the content checks read.
_HEAD = 1 << 12
# Assimp's OBJ reader refuses anything shorter ("OBJ-file is too small").
_OBJ_MIN_SIZE = 16
# A Git LFS pointer stands in for a mesh whose repository was cloned without `git lfs pull`.
_LFS_POINTER = b"version https://git-lfs.github.com/spec/"


def unreadable_reason(path: str) -> str | None:
    """Why SAPIEN cannot read the mesh at ``path`` (an existing file), or None when it may.

    The reason completes "SAPIEN cannot read it: ..." in a message.
    """
    suffix = os.path.splitext(path)[1].lower().lstrip(".")
    try:
        with open(path, "rb") as handle:
            size = os.fstat(handle.fileno()).st_size
            head = handle.read(_HEAD)
    except OSError as exc:
        return f"the file cannot be opened ({exc.strerror or exc})"
    if size == 0:
        return "the file is empty"
    if head.startswith(_LFS_POINTER):
        return "it is a Git LFS pointer, not the mesh (fetch it with `git lfs pull`)"
    if suffix not in ASSIMP_SUFFIXES:
        if _has_signature(head):
            return None  # assimp recognises the format by its first bytes
        shown = f"'.{suffix}'" if suffix else "no suffix"
        return (
            f"{shown} is not a mesh format it reads, and the file does not start as one it "
            "recognises without its suffix (a binary STL needs '.stl')"
        )
    check = _CONTENT_CHECKS.get(suffix)
    return check(head, size) if check is not None else None


# The first tokens of a line by which assimp's OBJ reader recognises a file (in its first 200
# bytes) when the suffix does not name the format.
_OBJ_TOKENS = (b"mtllib", b"usemtl", b"v ", b"vt ", b"vn ", b"o ", b"g ", b"s ", b"f ")


def _has_signature(head: bytes) -> bool:
    """Whether assimp recognises the file by its content: with a suffix it has no reader for,
    it asks each reader whether the first bytes are its format's."""
    start = head.lstrip()
    lowered = start[:512].lower()
    if lowered.startswith((b"solid", b"ply", b"gltf")) or b"<collada" in lowered:
        return True
    if b"off" in lowered.split(b"\n", 1)[0]:
        return True
    return any(line.lstrip().startswith(_OBJ_TOKENS) for line in head[:200].splitlines())


def _stl(head: bytes, size: int) -> str | None:
    # assimp: binary when the size is exactly 84 + 50 bytes per triangle the header counts,
    # else ASCII when it starts with "solid", else "Failed to determine STL storage".
    if size >= 84 and 84 + 50 * struct.unpack_from("<I", head, 80)[0] == size:
        return None
    if head.lstrip().startswith(b"solid"):
        return None
    if size >= 84:
        count = struct.unpack_from("<I", head, 80)[0]
        return (
            f"a binary STL of {count} triangles has {84 + 50 * count} bytes, this file "
            f"{size} (assimp reads only the exact size)"
        )
    return "it is neither a binary STL nor an ASCII one (which starts with 'solid')"


def _obj(head: bytes, size: int) -> str | None:
    if size < _OBJ_MIN_SIZE:
        return f"an OBJ file of {size} bytes is too small for assimp"
    if size <= _HEAD and not any(line.startswith((b"v ", b"v\t")) for line in head.splitlines()):
        return "the OBJ file has no vertices ('v' lines)"
    return None


def _starts_with(magic: bytes, what: str, *, ignore_case: bool = False) -> _Check:
    def check(head: bytes, size: int) -> str | None:
        start = head.lstrip().lower() if ignore_case else head.lstrip()
        return None if start.startswith(magic) else f"it does not start as {what} does"

    return check


def _off(head: bytes, size: int) -> str | None:
    # OFF files begin with a keyword that ends in OFF: OFF, COFF, NOFF, STOFF, 4OFF, ...
    first = head.lstrip().split(b"\n", 1)[0].lower()
    return None if b"off" in first else "it does not start as an OFF file does ('OFF')"


def _collada(head: bytes, size: int) -> str | None:
    return None if b"<collada" in head.lower() else "it is not a COLLADA document (no <COLLADA>)"


_CONTENT_CHECKS: dict[str, _Check] = {
    "stl": _stl,
    "obj": _obj,
    "dae": _collada,
    "ply": _starts_with(b"ply", "a PLY file"),
    "glb": _starts_with(b"gltf", "a binary glTF file ('glTF')", ignore_case=True),
    "gltf": _starts_with(b"{", "a glTF file (JSON)"),
    "off": _off,
}
