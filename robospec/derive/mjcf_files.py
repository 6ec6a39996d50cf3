"""The files an MJCF model names (meshes, textures, height fields, skins), found as MuJoCo finds
them, and the model written so that it names them from elsewhere: what carrying a derived MJCF
into robospec's cache or a built package takes.

MuJoCo takes a mesh, height field or skin ``file`` relative to ``<compiler meshdir>`` (else
``assetdir``), a texture's relative to ``texturedir`` (else ``assetdir``), each relative to the
model's folder. ManiSkill's loader takes every one relative to ``meshdir``. A carried model has
its includes written in place, every file named relative to where it is carried (or by the name
of its copy there), every mesh by the name it had, and no directories in its ``<compiler>``:
both read it the same way.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

from lxml import etree

from robospec.derive.document import Document, Source

_MESH_LIKE = ("mesh", "hfield", "skin")
_DIRECTORIES = ("assetdir", "meshdir", "texturedir")


def named_files(root: etree._Element, model: str) -> list[tuple[etree._Element, str]]:
    """Each element of ``root`` (an MJCF read from the file ``model``) that names a file, and
    the file (absolute), as MuJoCo finds it."""
    folder = os.path.dirname(os.path.abspath(model))
    compiler = root.find("compiler")
    get = compiler.get if compiler is not None else (lambda _key, default=None: default)
    assets = get("assetdir", "") or ""
    meshes = get("meshdir", None) or assets
    textures = get("texturedir", None) or assets
    found = []
    for element in root.iter(*_MESH_LIKE, "texture"):
        file = element.get("file")
        parent = element.getparent()
        if not file or parent is None or parent.tag == "default":
            continue
        base = textures if element.tag == "texture" else meshes
        found.append((element, os.path.normpath(os.path.join(folder, base, file))))
    return found


def inlined(source: Source) -> Document:
    """The MJCF ``source`` parsed (``root`` None where it is not XML), every ``<include>``
    written in place as MuJoCo reads them; an include it cannot read is among its
    ``refusals`` (RS050, at the ``<include>``, named as ``source`` shows its file)."""
    from robospec.derive.includes import inline_all

    document = Document(source)
    if document.parse():
        inline_all(document, note=False)
    return document


def carried_text(text: str, model: str, name_of: Callable[[str], str]) -> str:
    """The model ``text`` (read from the file ``model``) as written elsewhere: includes in
    place, each file named ``name_of(absolute path)``, no compiler directories."""
    document = inlined(Source(model, model, "mjcf", text.encode("utf-8")))
    if document.root is None:  # MuJoCo's parser would refuse it too: its errors are ValueErrors
        raise ValueError(f"XML Error: '{model}' is not well-formed XML")
    if document.refusals:
        raise ValueError(f"XML Error: {document.refusals[0].message}")
    root = document.tree
    for element, path in named_files(root, model):
        if element.tag == "mesh" and element.get("name") is None:
            # an unnamed mesh is named after its file, without folders (MuJoCo) or with them
            # (ManiSkill's loader): named here as both named it where it was, before its file
            # moves folders away and the geoms' mesh= no longer find it
            element.set("name", os.path.splitext(os.path.basename(element.get("file", "")))[0])
        element.set("file", name_of(path))
    for compiler in root.iter("compiler"):
        for attribute in _DIRECTORIES:
            compiler.attrib.pop(attribute, None)
    return etree.tostring(root, encoding="unicode") + "\n"


def compiled_model(text: bytes, path: str) -> Any:
    """MuJoCo's model of the MJCF ``text`` read from ``path`` (its ``<include>``s written in
    place and its files named absolutely, so that a derived copy compiles as the file would).
    Raises ValueError, with MuJoCo's message, where MuJoCo refuses it."""
    return compiled_with_warnings(text, path)[0]


def compiled_with_warnings(text: bytes, path: str) -> tuple[Any, list[str]]:
    """:func:`compiled_model`, and what MuJoCo's compiler warned about while compiling it.

    Compiled through ``MjSpec``, whose ``compile`` hands each compiler warning to Python as a
    ``UserWarning``: ``MjModel.from_xml_string`` prints them instead, and MuJoCo's default
    handler appends them to a ``MUJOCO_LOG.TXT`` in the working folder, beside the user's
    files."""
    import warnings

    import mujoco

    try:
        xml = carried_text(text.decode("utf-8"), path, lambda file: file)
    except UnicodeDecodeError as exc:
        raise ValueError(str(exc)) from exc
    # the XML parser's own warnings ("XML contains a 'NaN'") go to MuJoCo's user warning
    # handler, whose default also appends them to MUJOCO_LOG.TXT in the working folder
    parsed: list[str] = []
    before = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(parsed.append)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", UserWarning)
            # the parser's and the compiler's errors are ValueErrors
            model = mujoco.MjSpec.from_string(xml).compile()
    finally:
        mujoco.set_mju_user_warning(before)
    said = parsed + [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    return model, list(dict.fromkeys(said))
