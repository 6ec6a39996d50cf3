"""The JSON Schema of the spec format, generated from the pydantic models (one source of truth).
``schemas/robospec.schema.json`` is this text; a test keeps the two equal."""

from __future__ import annotations

import json
from typing import Any

SCHEMA_ID = "https://robospec.dev/schemas/robospec.schema.json"


def spec_schema() -> dict[str, Any]:
    from robospec.model.spec import Spec

    schema = Spec.model_json_schema()
    return {"$schema": "https://json-schema.org/draft/2020-12/schema", "$id": SCHEMA_ID, **schema}


def schema_text() -> str:
    return json.dumps(spec_schema(), indent=2, ensure_ascii=False) + "\n"
