"""The spec's record classes and their validators: the pydantic models, frozen.

`robospec validate`, `build` and `register` validate with pydantic-core alone. The classes
defined here (``Spec``, ``Pose``, ``PDJointPosConfig``, ... one per pydantic model, with the
same names and fields) are plain records (:mod:`robospec.model.record`), and ``SCHEMAS`` holds
each model's pydantic-core schema as this pydantic makes it, calling the same validator
functions (:mod:`robospec.model.rules`).

Their text is written by :mod:`robospec.model.freeze` from the pydantic models, for the
pydantic installed, the first time it is needed; it is kept in robospec's cache folder
(:mod:`robospec.model.frozen_cache`), and every later run runs it from there without importing
pydantic. Where the cache cannot be written, the text is made in memory in every run: slower,
the same result.

Validation (:func:`validator_for`) and did-you-mean hints (:mod:`robospec.model.schema_info`)
both read ``SCHEMAS``: a hint describes the schema that validated.
"""

from __future__ import annotations

import contextlib
import functools
import warnings
from importlib.machinery import SourceFileLoader
from pathlib import Path
from types import CodeType
from typing import TYPE_CHECKING, Any

from pydantic_core import SchemaValidator

from robospec.files import write_atomically
from robospec.model.frozen_cache import entry_path
from robospec.model.record import Record

if TYPE_CHECKING:
    # The records are made by exec below, which a type checker cannot follow. Each has the name,
    # the fields and the mixins of the pydantic model it is frozen from (robospec.model.freeze
    # writes it from that model), so a checker reads it as that model; the records offer the
    # part of BaseModel the later stages use (robospec.model.record). A name used from here is
    # added to this list ("X as X": a re-export).
    from robospec.model.check_settings import Checks as Checks
    from robospec.model.common import AllBut as AllBut
    from robospec.model.common import Pose as Pose
    from robospec.model.controllers import MimicTarget as MimicTarget
    from robospec.model.controllers import PDJointPosConfig as PDJointPosConfig
    from robospec.model.members import HeightBand as HeightBand
    from robospec.model.spec import Keyframe as Keyframe
    from robospec.model.spec import Spec as Spec

SCHEMAS: dict[str, Any] = {}
"""Each model's pydantic-core schema, by class name (set by the frozen module's text below)."""


def frozen_code(path: Path) -> CodeType:
    """The frozen module at ``path`` compiled, written there first if it is not there yet."""
    try:
        return _compiled(path)
    except (OSError, SyntaxError, ValueError):  # not there yet, unreadable or damaged
        return _made(path)


def _compiled(path: Path) -> CodeType:
    # the import system's own loader: it keeps the bytecode beside the file, as for any module
    code = SourceFileLoader(__name__, str(path)).get_code(__name__)
    if code is None:
        raise ValueError(f"{path}: no code")
    return code


def _made(path: Path) -> CodeType:
    # the only place pydantic is imported on the way to a validator: a cold cache
    from robospec.model.freeze import frozen_source

    text = frozen_source()
    try:
        write_atomically(path, text)
        return _compiled(path)
    except OSError as exc:
        warnings.warn(
            f"robospec cannot cache its spec model in {path.parent} ({exc}); every run "
            "builds it again, which is slower: set ROBOSPEC_CACHE_DIR to a writable folder",
            RuntimeWarning,
            stacklevel=2,
        )
        return compile(text, str(path), "exec", dont_inherit=True)


def load_into(namespace: dict[str, Any]) -> None:
    """Run the frozen module's text in ``namespace``: its record classes and ``SCHEMAS``."""
    path = entry_path()
    try:
        exec(frozen_code(path), namespace)
    except Exception:
        # a cached text that does not run (damaged on disk): the models make it again; a
        # second failure is a real error and propagates
        with contextlib.suppress(OSError):
            path.unlink(missing_ok=True)
        exec(frozen_code(path), namespace)


load_into(globals())

RECORDS: dict[str, type[Record]] = {name: globals()[name] for name in SCHEMAS}
"""Every record class, by name."""


@functools.cache
def validator_for(name: str) -> SchemaValidator:
    """The validator of the model called ``name`` (``"Spec"``: a whole spec)."""
    return SchemaValidator(SCHEMAS[name])


Record.validator_for = staticmethod(validator_for)
