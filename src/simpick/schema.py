"""The JSON schema of the study config, generated from the pydantic models of :mod:`simpick.config`.

``schemas/config.schema.json`` is committed for editors and for users who validate a config
without simpick (Snakemake workflow catalogue convention); ``make schema`` regenerates it, and
``tests/test_schema.py`` fails when it is out of step with the models. The workflow itself
checks the config with the models (:func:`simpick.config.validate_or_exit`), whose messages
name the key and the fix.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

SCHEMA = Path("schemas") / "config.schema.json"


# YAML 1.1 (PyYAML, which Snakemake reads configs with) reads 1.0e6 as a string, and the models
# take a numeric string for a number (pydantic's lax mode): so does the schema.
NUMERIC_STRING = r"^\s*[-+]?(\d+(\.\d*)?|\.\d+)([eE][-+]?\d+)?\s*$"


def lax_numbers(node):
    """Each ``{"type": "number"|"integer", ...}`` also accepts a numeric string."""
    if isinstance(node, list):
        return [lax_numbers(v) for v in node]
    if not isinstance(node, dict):
        return node
    node = {k: lax_numbers(v) for k, v in node.items()}
    if node.get("type") in ("number", "integer"):
        keep = {k: node.pop(k) for k in ("title", "description", "default") if k in node}
        return {**keep, "anyOf": [node, {"type": "string", "pattern": NUMERIC_STRING}]}
    return node


def config_schema() -> dict:
    from simpick.config import Study

    schema = lax_numbers(Study.model_json_schema(mode="validation"))
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "description": "simpick study config (config.yaml); generated from simpick.config.Study by "
        "`make schema`, do not edit by hand",
        **schema,
    }


def schema_text() -> str:
    return json.dumps(config_schema(), indent=1, sort_keys=True) + "\n"


def main(argv: list[str]) -> int:
    """``python -m simpick.schema [PATH]``: write the schema (default schemas/config.schema.json)."""
    target = Path(argv[0]) if argv else SCHEMA
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(schema_text())
    print(f"simpick: wrote {target}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
