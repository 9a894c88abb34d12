"""Loading a config: its problems in words, duplicate keys in a YAML file, the plain mapping the
plan reads, and validate_or_exit for the Snakefile."""

from __future__ import annotations

import sys
from pathlib import Path

from pydantic import ValidationError

from simpick.config.study import Study
from simpick.engines import get_engine
from simpick.errors import validation_problems


def problems(config: dict) -> list[str]:
    """Human-readable lines, one per problem; empty when the config is valid."""
    try:
        Study.model_validate(config)
    except ValidationError as exc:
        return [f"{key}: {problem}" for key, problem in validation_problems(exc)]
    return []


def duplicate_keys(path: str | Path) -> list[str]:
    """YAML quietly keeps the last of two equal keys; a config must not say a thing twice."""
    import yaml

    found: list[str] = []

    class Loader(yaml.SafeLoader):
        pass

    def mapping(loader, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = loader.construct_object(key_node, deep=deep)
            if key in seen:
                found.append(
                    f"{path}, line {key_node.start_mark.line + 1}: key {key!r} appears twice "
                    "in the same block (YAML would silently keep the last one)"
                )
            seen.add(key)
        return yaml.SafeLoader.construct_mapping(loader, node, deep)

    Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, mapping)
    try:
        yaml.load(Path(path).read_text(), Loader=Loader)
    except (OSError, yaml.YAMLError) as exc:
        found.append(f"{path}: cannot be read as YAML: {exc}")
    return found


def plain(study: Study, config: dict) -> dict:
    """The validated settings as plain data, every default filled in: what the plan reads and the
    jobs receive (rules/common.smk), so a default lives in its model alone. The ``engines`` and
    ``baselines`` blocks keep the configured entries, in the config's order, each with its adapter's
    settings in full (an empty entry: the adapter's defaults)."""
    data = study.model_dump(mode="json")
    for section in ("engines", "baselines"):
        block = getattr(study, section)
        data[section] = {
            name: (getattr(block, name) or get_engine(name).settings_model()).model_dump(mode="json")
            for name in (config.get(section) or {})
            if name in block.model_fields_set
        }
    return data


def validate_or_exit(config: dict, source: str = "config", files: list | tuple = ()) -> Study:
    """The validated, typed study settings (defaults filled in); a bad config stops the run with
    one line per problem. The rules pass slices of this object, not of the raw dict, to the jobs
    (``statistics`` so far: every summary that gives an interval or a verdict reads it)."""
    found = [line for f in files for line in duplicate_keys(f)] + problems(config)
    if found:
        print(f"simpick: the {source} has {len(found)} problem(s):", file=sys.stderr)
        for line in found:
            print(f"  - {line}", file=sys.stderr)
        sys.exit(1)
    return Study.model_validate(config)
