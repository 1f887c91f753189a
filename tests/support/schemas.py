"""The published JSON Schemas (raykit/io/schemas/) as a validator sees them: a version's file
refers to the definitions it shares with the other version (scene-common.schema.json) by its
``$id``, so every file is registered under its own."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
from referencing import Registry, Resource

SCHEMAS = Path(__file__).resolve().parents[2] / "raykit/io/schemas"


def schema_validator(name: str) -> jsonschema.Draft202012Validator:
    """A validator of ``raykit/io/schemas/<name>``, its references to the others resolved."""
    documents = {path.name: json.loads(path.read_text()) for path in SCHEMAS.glob("*.json")}
    registry = Registry().with_resources(
        (document["$id"], Resource.from_contents(document)) for document in documents.values()
    )
    return jsonschema.Draft202012Validator(documents[name], registry=registry)
