"""Loading a config: its problems in words, duplicate keys in a YAML file, the plain mapping the
plan reads, validate_or_exit for the Snakefile, and read_study for every other entry point (the
command-line helpers, the tests), so that all of them read a config the same way."""

from __future__ import annotations

import sys
from pathlib import Path

from pydantic import BaseModel, ValidationError

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

    class Loader(getattr(yaml, "CSafeLoader", yaml.SafeLoader)):  # libyaml's parser: read when a run plans
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


def configured(block: BaseModel) -> list[str]:
    """The names an ``engines`` or ``baselines`` block configures, in the registry's order."""
    return [name for name in type(block).model_fields if name in block.model_fields_set]


def entry_settings(block: BaseModel, name: str) -> dict:
    """An entry of an ``engines`` or ``baselines`` block: its adapter's settings in full, as plain data (an
    empty entry: the adapter's defaults)."""
    return (getattr(block, name) or get_engine(name).settings_model()).model_dump(mode="json")


def plain(study: Study, config: dict) -> dict:
    """The validated settings as plain data, every default filled in: what the plan reads and the
    jobs receive (rules/common.smk), so a default lives in its model alone. The ``engines`` and
    ``baselines`` blocks keep the configured entries, in the config's order, each with its adapter's
    settings in full (an empty entry: the adapter's defaults)."""
    data = study.model_dump(mode="json")
    for section in ("engines", "baselines"):
        block = getattr(study, section)
        data[section] = {
            name: entry_settings(block, name)
            for name in (config.get(section) or {})  # the raw config: its order, which the typed block does not keep
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


def merged(paths: list | tuple, overrides: dict | None = None) -> dict:
    """The YAML files in order, each updating the one before key by key at every depth, then
    ``overrides``: how Snakemake combines ``configfile``, ``--configfile`` and ``--config``
    (snakemake.utils.update_config), so a helper reads what the workflow would."""
    import yaml

    def update(base: dict, new: dict) -> dict:
        for key, value in new.items():
            base[key] = update(dict(base.get(key) or {}), value) if isinstance(value, dict) else value
        return base

    config: dict = {}
    for path in paths:
        try:
            data = yaml.safe_load(Path(path).read_text()) or {}
        except OSError as exc:
            sys.exit(f"simpick: cannot read the config file {path}: {exc.strerror}; give an existing file")
        except yaml.YAMLError as exc:
            sys.exit(f"simpick: the config file {path} is not valid YAML: {exc}")
        if not isinstance(data, dict):
            sys.exit(f"simpick: the config file {path} holds no mapping of settings; write `key: value` lines")
        update(config, data)
    return update(config, overrides or {})


def read_study(paths: list | tuple = ("config.yaml",), overrides: dict | None = None) -> tuple[Study, dict]:
    """The typed study and its plain settings (:func:`plain`) from config files, checked exactly as
    the Snakefile checks them: a duplicate key or a bad value stops with one line per problem."""
    config = merged(paths, overrides)
    study = validate_or_exit(config, source="config " + " + ".join(str(p) for p in paths), files=paths)
    return study, plain(study, config)
