"""The MJCF a generated package carries beside its module (a description robospec composed or
mended), written so ManiSkill's loader reads it from there.

ManiSkill's MJCF loader opens ``<include>`` files and assets from the model's own folder (its
``<compiler meshdir>`` below it), so the copy is made standalone: the includes are read into it
as that loader reads them (their elements appended to the model, one level deep), and every
file it names is written as a path from the module's folder — or, for ``build``'s self-contained
package, as the name of a copy beside the module, ``<module>.<file name>``.
"""

from __future__ import annotations

import os
from pathlib import Path

from lxml import etree

from robospec.compose.mjcf import FILE_FOLDERS, ModelFolders
from robospec.compose.xml import parse
from robospec.emit.package import GENERATED_MARKER
from robospec.resolve.resolved import FileRef


def carried_mjcf(
    ref: FileRef, module_dir: Path, module: str, self_contained: bool
) -> tuple[str, dict[str, str | bytes]]:
    """The MJCF text to write as ``<module>.xml``, and the copies to write beside it."""
    text = ref.generated_text if ref.generated_text is not None else ref.absolute.read_text()
    root = parse(text.encode("utf-8"))
    assert root is not None, "a description that parsed when it was resolved"
    folder = os.path.dirname(str(ref.absolute))
    for include in list(root.findall("include")):
        full = os.path.join(folder, include.get("file") or "")
        root.remove(include)
        included = parse(Path(full).read_bytes()) if os.path.isfile(full) else None
        if included is not None:
            root.extend(c for c in included if isinstance(c.tag, str) and c.tag != "include")
    folders = ModelFolders(root, folder)
    copies: dict[str, str | bytes] = {}
    named: dict[str, str] = {}  # file -> its copy's name
    for element in root.iter(*FILE_FOLDERS):
        full = folders.file(element)
        if full is None:
            continue
        if self_contained and os.path.isfile(full):
            if full not in named:
                named[full] = _copy_name(module, full, set(named.values()))
                copies[named[full]] = Path(full).read_bytes()
            element.set("file", named[full])
        else:
            element.set("file", Path(os.path.relpath(full, module_dir)).as_posix())
    compiler = root.find("compiler")
    if compiler is not None:
        for attribute in ("meshdir", "texturedir", "assetdir"):
            compiler.attrib.pop(attribute, None)
    how = f", with {', '.join(ref.parts)} mounted" if ref.parts else ", mended"
    root.addprevious(etree.Comment(f" {GENERATED_MARKER} from {ref.relative}{how}: do not edit "))
    written = etree.tostring(root.getroottree(), encoding="unicode", xml_declaration=False)
    return (written if written.endswith("\n") else written + "\n"), copies


def _copy_name(module: str, source: str, taken: set[str]) -> str:
    import re

    stem, suffix = os.path.splitext(os.path.basename(source))
    stem = re.sub(r"[^A-Za-z0-9_.\-]", "_", stem) or "file"
    name, n = f"{module}.{stem}{suffix}", 1
    lowered = {t.lower() for t in taken}
    while name.lower() in lowered:
        n += 1
        name = f"{module}.{stem}_{n}{suffix}"
    return name
