"""RS092: a file named as a plain URDF whose content is xacro, found without expanding it.

Its own module, apart from :mod:`.xacro` (the expansion's child process): ``validate`` reads
every URDF through this check, and a plain URDF's spec imports nothing of the expansion.
"""

from __future__ import annotations

from robospec.diagnostics import Diagnostic, warning
from robospec.diagnostics.codes import XACRO_CONTENT

_XACRO_NAMESPACE = "http://www.ros.org/wiki/xacro"


def xacro_content(path: str, data: bytes) -> Diagnostic | None:
    """RS092, a warning at the first xacro element or ``${...}`` expression of the file at
    ``path``, named as a plain URDF: its content is xacro, which SAPIEN would ignore (a
    property unset, a macro never called: no joints), so robospec expands it as xacro. None
    for a plain URDF — one that only declares the xacro namespace, as many expansions do,
    included."""
    if b"xacro:" not in data and b"${" not in data:  # (no parse for the usual URDF)
        return None
    from robospec.description.source_columns import element_at
    from robospec.description.urdf import parse_xml

    root, _ = parse_xml(data, path)
    if root is None:  # not XML: the parse after says so
        return None
    for element in root.iter():
        tag = element.tag
        if not isinstance(tag, str):
            continue
        if tag.startswith(f"{{{_XACRO_NAMESPACE}}}") or tag.startswith("xacro:"):
            what = f"<xacro:{tag.rsplit('}', 1)[-1].removeprefix('xacro:')}>"
        else:
            expression = next((k for k, v in element.attrib.items() if "${" in v), None)
            if expression is None:
                continue
            what = f'{expression}="{element.get(expression)}"'
        return warning(
            element_at(path, element),
            XACRO_CONTENT,
            f"this URDF is xacro ({what}): robospec expanded it as xacro, which SAPIEN "
            "reading it as a plain URDF would not",
            "name it `description: {xacro: FILE}` (or rename it .urdf.xacro) to say so",
        )
    return None
