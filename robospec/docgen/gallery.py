"""Pictures of robots for the docs: the zoo's gallery (docs/zoo.md, written here), the
pictures of the docs' own pages (the home page's, the tutorial's robot and what its camera
sees: :data:`PAGE_PICTURES`) and the corpus's (docs/robots.md, written by ``tests/corpus.py
--write``).

A robot's gallery picture is its ``doc --images`` three-quarter view at its first keyframe
(:mod:`robospec.pictures`). The pictures are checked in, and kept current by what they are
drawn from, not by comparing pixels (another machine's OpenGL draws other pixels): beside them,
``inputs.json`` holds for each robot a hash of everything the picture is drawn from — the
description file, the visual meshes it names, the first keyframe as resolved, the view — and
:data:`RENDER_VERSION`, which a change to how pictures are drawn bumps. A picture whose inputs
hash differs from the recorded one is stale: ``python -m robospec.docgen.gallery --write docs``
draws it again (a minute for the zoo).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from robospec.pipeline import CompiledSpec, compile_spec

RENDER_VERSION = "2"
GALLERY_VIEW = "three_quarter"
ZOO_FOLDER = Path("images") / "zoo"
INPUTS_FILE = "inputs.json"
ZOO_PAGE = "zoo.md"
ZOO_SPECS = Path("specs") / "maniskill"
WRITE_COMMAND = ".venv/bin/python -m robospec.docgen.gallery --write docs"
START = "<!-- gallery: generated (docs/development.md says how) -->"
END = "<!-- end of gallery -->"
COLUMNS = 3
# the pictures the docs' pages show, beyond the galleries: name -> (spec, what it shows: a
# standard view of the robot at its first keyframe, or ``table:<camera>``, what that camera
# sees of a table before the robot)
PAGE_FOLDER = Path("images") / "pages"
PAGE_PICTURES = {
    "tutorial_my_panda": ("docs/examples/tutorial/my_panda.yaml", GALLERY_VIEW),
    "tutorial_my_panda_hand_camera": ("docs/examples/tutorial/my_panda.yaml", "table:hand_camera"),
}


def render_inputs(compiled: CompiledSpec, view: str = GALLERY_VIEW) -> str:
    """The hash of what the picture of ``compiled`` (its gallery picture, or ``view``) is
    drawn from (no drawing)."""
    robot, description = compiled.robot, compiled.description
    assert robot is not None and description is not None
    digest = hashlib.sha256(f"robospec-gallery {RENDER_VERSION} {GALLERY_VIEW}\n".encode())
    if view != GALLERY_VIEW:  # (the gallery's hashes stay as they were recorded)
        digest.update(f"{view}\n{robot.cameras!r}\n".encode())
    text = robot.description.read_bytes()
    digest.update(robot.description_kind.encode() + b"\n" + text)
    for mesh in sorted(description.mesh_files, key=lambda m: (m.uri, m.role)):
        if mesh.role == "visual" and mesh.path is not None:
            digest.update(mesh.uri.encode() + b"\n" + Path(mesh.path).read_bytes())
    if robot.keyframes:
        first = robot.keyframes[0]
        values = (first.name, first.p, first.q, first.qpos, robot.active_joints)
        digest.update(repr(values).encode())
    return digest.hexdigest()


def gallery_picture(compiled: CompiledSpec, view: str = GALLERY_VIEW) -> bytes:
    """The robot's gallery picture, or ``view`` (:data:`PAGE_PICTURES`), as a PNG: what
    ``doc --images`` draws. Raises RenderUnavailable where nothing is drawn."""
    from robospec.pictures.album import AlbumOptions, CameraSettings, make_album
    from robospec.pictures.camera_checks import Limits

    robot, description = compiled.robot, compiled.description
    assert robot is not None and description is not None
    kind, _, camera = view.partition(":")
    camera_view = bool(camera)
    options = AlbumOptions(
        views=() if camera_view else (view,), cameras=camera_view, first_keyframe_only=True
    )
    unused = CameraSettings(Limits(1.0, 1.0, 0.0, False), None, {})
    album = make_album(robot, description, unused, "", options)
    if not camera_view:
        return album.pictures[0].png
    (found,) = [p for p in album.pictures if p.kind == kind and p.name == camera]
    return found.png


def gallery_markdown(entries: Sequence[tuple[str, str]], columns: int = COLUMNS) -> str:
    """A table of pictures, ``columns`` a row: ``entries`` are (caption, link)."""
    lines = ["| " + " | ".join([" "] * columns) + " |", "|" + " --- |" * columns]
    for start in range(0, len(entries), columns):
        row = list(entries[start : start + columns])
        cells = [f"![{caption}](<{link}>)<br>`{caption}`" for caption, link in row]
        cells += [" "] * (columns - len(cells))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def zoo_specs(root: Path) -> list[Path]:
    return sorted((root / ZOO_SPECS).glob("*.yaml"))


def recorded_inputs(docs_dir: Path) -> dict[str, str]:
    path = docs_dir / ZOO_FOLDER / INPUTS_FILE
    return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}


def zoo_gallery(docs_dir: Path, names: Sequence[str]) -> str:
    entries = [(name, (ZOO_FOLDER / f"{name}.png").as_posix()) for name in names]
    return f"{START}\n\n{gallery_markdown(entries)}\n{END}"


def with_gallery(page: str, gallery: str) -> str:
    """``page`` with its gallery (between :data:`START` and :data:`END`) replaced."""
    before, _, rest = page.partition(START)
    _, _, after = rest.partition(END)
    return before + gallery + after


def write_zoo(root: Path, docs_dir: Path, only: Sequence[str] = ()) -> list[str]:
    """Draw the zoo's stale pictures (or those of ``only``) and write the gallery; returns the
    names drawn."""
    recorded = recorded_inputs(docs_dir)
    folder = docs_dir / ZOO_FOLDER
    folder.mkdir(parents=True, exist_ok=True)
    inputs: dict[str, str] = {}
    drawn = []
    for spec in zoo_specs(root):
        compiled = compile_spec(spec)
        inputs[spec.stem] = render_inputs(compiled)
        stale = inputs[spec.stem] != recorded.get(spec.stem)
        if (spec.stem in only) if only else stale or not (folder / f"{spec.stem}.png").is_file():
            (folder / f"{spec.stem}.png").write_bytes(gallery_picture(compiled))
            drawn.append(spec.stem)
    (folder / INPUTS_FILE).write_text(json.dumps(inputs, indent=1, sort_keys=True) + "\n")
    page = docs_dir / ZOO_PAGE
    page.write_text(
        with_gallery(page.read_text(encoding="utf-8"), zoo_gallery(docs_dir, sorted(inputs)))
    )
    return drawn


def recorded_page_inputs(docs_dir: Path) -> dict[str, str]:
    path = docs_dir / PAGE_FOLDER / INPUTS_FILE
    return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else {}


def page_inputs(root: Path) -> dict[str, str]:
    """The inputs hash of each of :data:`PAGE_PICTURES`, as they are now."""
    return {
        name: render_inputs(compile_spec(root / spec), view)
        for name, (spec, view) in sorted(PAGE_PICTURES.items())
    }


def write_pages(root: Path, docs_dir: Path) -> list[str]:
    """Draw the stale pictures of :data:`PAGE_PICTURES`; returns the names drawn."""
    recorded = recorded_page_inputs(docs_dir)
    folder = docs_dir / PAGE_FOLDER
    folder.mkdir(parents=True, exist_ok=True)
    inputs = page_inputs(root)
    drawn = []
    for name, (spec, view) in sorted(PAGE_PICTURES.items()):
        if inputs[name] != recorded.get(name) or not (folder / f"{name}.png").is_file():
            (folder / f"{name}.png").write_bytes(gallery_picture(compile_spec(root / spec), view))
            drawn.append(name)
    (folder / INPUTS_FILE).write_text(json.dumps(inputs, indent=1, sort_keys=True) + "\n")
    return drawn


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="draw the zoo's pictures for docs/zoo.md and the pages' own pictures"
    )
    parser.add_argument("--write", type=Path, required=True, metavar="DOCS")
    parser.add_argument("--only", nargs="+", default=(), metavar="NAME", help="draw these again")
    args = parser.parse_args(argv)
    root = args.write.resolve().parent
    for name in write_zoo(root, args.write, args.only):
        print(f"drew {(args.write / ZOO_FOLDER / name).as_posix()}.png")
    for name in write_pages(root, args.write):
        print(f"drew {(args.write / PAGE_FOLDER / name).as_posix()}.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
