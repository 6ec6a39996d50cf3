"""SARIF 2.1.0 for code scanning (GitHub's upload-sarif, IDE viewers): one run whose driver
lists a rule per code used (its title from :mod:`robospec.diagnostics.codes`) and a result per
diagnostic.

File locations are URIs relative to ``%SRCROOT%`` (the directory robospec ran in, given in
``originalUriBaseIds``) with forward slashes, as code scanning expects; a file outside it keeps
an absolute ``file:`` URI."""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from importlib import metadata
from pathlib import Path, PurePosixPath
from urllib.parse import quote

from robospec.diagnostics import Diagnostic, Location
from robospec.diagnostics.codes import CODES

SCHEMA_URI = "https://json.schemastore.org/sarif-2.1.0.json"
SRCROOT = "%SRCROOT%"


def project_urls() -> dict[str, str]:
    """The installed package's ``[project.urls]`` (Homepage, Documentation), if it declares any."""
    try:
        entries = metadata.metadata("robospec").get_all("Project-URL") or []
    except metadata.PackageNotFoundError:
        return {}
    pairs = (entry.split(",", 1) for entry in entries if "," in entry)
    return {label.strip().lower(): url.strip() for label, url in pairs}


def _version() -> str:
    try:
        return metadata.version("robospec")
    except metadata.PackageNotFoundError:
        return "0+unknown"


def rule(code: str, docs_url: str | None) -> dict[str, object]:
    entry: dict[str, object] = {"id": code}
    known = CODES.get(code)
    if known is not None:
        entry["shortDescription"] = {"text": known.title}
    if docs_url:  # each code has its page, docs/codes/RSxxx.md
        entry["helpUri"] = f"{docs_url.rstrip('/')}/codes/{code}.md"
    return entry


def artifact_location(file: str, root: Path) -> dict[str, str]:
    path = Path(file)
    absolute = path if path.is_absolute() else root / path
    try:
        relative = PurePosixPath(Path(os.path.normpath(absolute)).relative_to(root).as_posix())
    except ValueError:
        return {"uri": Path(os.path.normpath(absolute)).as_uri()}
    # ':' is quoted too, so a first segment like 'c:' can never read as a URI scheme
    return {"uri": quote(str(relative), safe="/"), "uriBaseId": SRCROOT}


def result(d: Diagnostic, rule_index: int, root: Path) -> dict[str, object]:
    loc: Location = d.location
    text = d.message if not d.hint else f"{d.message}\nhint: {d.hint}"
    return {
        "ruleId": d.code,
        "ruleIndex": rule_index,
        "level": d.severity.value,  # SARIF's levels include "error", "warning" and "note"
        "message": {"text": text},
        "locations": [
            {
                "physicalLocation": {
                    "artifactLocation": artifact_location(loc.file, root),
                    "region": {"startLine": loc.line, "startColumn": loc.column},
                }
            }
        ],
    }


def sarif_log(
    diagnostics: Sequence[Diagnostic], root: Path, urls: dict[str, str] | None = None
) -> dict[str, object]:
    """The SARIF log of ``diagnostics`` (relative paths in them are relative to ``root``).

    ``urls`` (default: the package's ``[project.urls]``) gives the driver's informationUri
    (``homepage``) and each rule's helpUri under ``documentation``, the URL at which the docs/
    folder is browsable as Markdown (a repository's docs/ folder); without them both are left
    out, which SARIF allows."""
    urls = project_urls() if urls is None else urls
    codes = sorted({d.code for d in diagnostics})
    index = {code: i for i, code in enumerate(codes)}
    docs_url = urls.get("documentation")
    driver: dict[str, object] = {"name": "robospec", "version": _version()}
    if urls.get("homepage"):
        driver["informationUri"] = urls["homepage"]
    driver["rules"] = [rule(code, docs_url) for code in codes]
    run = {
        "tool": {"driver": driver},
        "originalUriBaseIds": {SRCROOT: {"uri": root.as_uri().rstrip("/") + "/"}},
        "results": [result(d, index[d.code], root) for d in diagnostics],
        "columnKind": "unicodeCodePoints",
    }
    return {"$schema": SCHEMA_URI, "version": "2.1.0", "runs": [run]}


def render(diagnostics: Sequence[Diagnostic]) -> str:
    return json.dumps(sarif_log(diagnostics, Path.cwd().resolve()), indent=2)
