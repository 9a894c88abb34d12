"""The benchmark across robots: which robots it runs and each robot's study config.

``config/robots.yaml`` names, per robot, the config files its own study is run with (over
``config.yaml``, in order, as ``--configfile`` would give them) and the settings given on top (as
``--config`` would). rules/robots.smk runs each robot's study as a Snakemake module of the
project's Snakefile with the config built here, so a robot's study in the benchmark is the study
its own command runs, and one robot's study stays rerunnable alone with that command.

Every problem of the list is reported with the file, the robot's field and the fix, before any
study is planned.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from simpick.config.load import duplicate_keys, merged
from simpick.errors import InputError

NAME = re.compile(r"^[a-z][a-z0-9_]*$")  # a robot's name: a rule-name prefix and a folder name
KEYS = {"configfiles", "config", "label"}


@dataclass(frozen=True)
class RobotStudy:
    """One robot of the benchmark: its name, the files and settings its study runs with, and the
    merged config (``config.yaml``, then each file, then the settings)."""

    name: str
    configfiles: tuple[str, ...]
    overrides: dict = field(default_factory=dict)
    config: dict = field(default_factory=dict)
    label: str = ""

    def settings(self) -> dict:
        """The settings given on top of the files, by dotted key (as the page lists them)."""
        return flatten(self.overrides)

    def command(self) -> str:
        """The command that runs this robot's study alone, in the project's folder."""
        words = ["snakemake --cores 2"] + [f"--configfile {f}" for f in self.configfiles]
        # Snakemake's --config takes top-level keys (a mapping value is merged into that block, as here)
        if self.overrides:
            words += ["--config"] + [f"{k}={_shell_value(v)}" for k, v in self.overrides.items()]
        return " ".join(words)


def _shell_value(value) -> str:
    text = yaml.safe_dump(value, default_flow_style=True).strip().removesuffix("...").strip()
    return text if re.fullmatch(r"[A-Za-z0-9_./:+-]+", text) else f"'{text}'"


def flatten(overrides: dict, prefix: str = "") -> dict:
    """``{"a": {"b": 1}}`` -> ``{"a.b": 1}``: each setting by its dotted key (the page lists them)."""
    out = {}
    for key, value in overrides.items():
        dotted = f"{prefix}{key}"
        if isinstance(value, dict) and value:
            out.update(flatten(value, dotted + "."))
        else:
            out[dotted] = value
    return out


def _check_file(path: Path, where: str, fix: str) -> None:
    """A config file a robot's study reads: there, a mapping, no key said twice (the study's own checks,
    here naming the robot's entry)."""
    if not path.is_file():
        raise InputError(where, f"{path} does not exist", fix)
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise InputError(str(path), f"cannot be read as YAML: {exc}", "correct its syntax") from None
    if not isinstance(data, dict):
        raise InputError(str(path), "is not a mapping of settings", "give it the form of config.yaml")
    twice = duplicate_keys(path)
    if twice:
        raise InputError(where, twice[0], "say each setting once")


def robot_studies(robots: dict, root: str | Path, source: str = "config/robots.yaml") -> dict[str, RobotStudy]:
    """name -> :class:`RobotStudy` for every robot of ``robots`` (the ``robots:`` block of
    ``source``), ``config.yaml`` and the config files relative to ``root`` (the studies' working
    directory, where a study of its own reads them too). Raises :class:`simpick.errors.InputError`
    naming ``source``, the robot's field and the fix for a bad entry."""
    root = Path(root)
    if not isinstance(robots, dict) or not robots:
        raise InputError(
            f"{source}, robots", "lists no robot", "give each robot a name with its configfiles and config"
        )
    _check_file(root / "config.yaml", f"{source}, robots", "run from the project's folder")
    studies = {}
    for name, entry in robots.items():
        where = f"{source}, robots.{name}"
        if not isinstance(name, str) or not NAME.match(name):
            raise InputError(
                where,
                "is not a usable robot name",
                "lower-case letters, digits and '_', starting with a letter (it names rules and folders)",
            )
        entry = entry or {}
        if not isinstance(entry, dict):
            raise InputError(where, f"is {entry!r}, not a mapping", "give configfiles: [...] and config: {...}")
        unknown = sorted(set(entry) - KEYS)
        if unknown:
            raise InputError(where, f"unknown field(s) {unknown}", f"use only {sorted(KEYS)}")
        files = entry.get("configfiles") or []
        if isinstance(files, str) or not isinstance(files, list):
            raise InputError(f"{where}.configfiles", f"is {files!r}, not a list", "write it as a list of paths")
        overrides = entry.get("config") or {}
        if not isinstance(overrides, dict):
            raise InputError(f"{where}.config", f"is {overrides!r}, not a mapping", "write settings as key: value")
        for i, f in enumerate(files):
            _check_file(
                root / f,
                f"{where}.configfiles[{i}]",
                "name a config file relative to the project's folder (e.g. config/robots/warthog.yaml)",
            )
        # as the robot's own study reads it: config.yaml, each file, the settings (simpick.config.load.merged)
        config = merged([root / "config.yaml", *(root / f for f in files)], overrides)
        # the robot's merged study config, plain: its own study validates it when planned (simpick.config.Study)
        label = str(entry.get("label") or (config.get("robot") or {}).get("label") or name)
        studies[name] = RobotStudy(name, tuple(str(f) for f in files), dict(overrides), config, label)
    return studies


def benchmark(config: dict, root: str | Path, source: str = "config/robots.yaml") -> tuple[dict[str, RobotStudy], dict]:
    """The benchmark's whole config, checked: its robots (:func:`robot_studies`) and how the page pools
    outcomes (``pooling.min_robots``, a whole number of robots of at least 2; default 2). Any other
    top-level key, or another key under ``pooling``, is an InputError naming ``source`` and the key."""
    from pydantic import ValidationError

    from simpick.report.robots import Pooling

    # Snakemake's config dict of config/robots.yaml: its two blocks checked here, the robots by robot_studies
    unknown = sorted(set(config) - {"robots", "pooling"})
    if unknown:
        raise InputError(f"{source}, {unknown[0]}", "is not a setting of the benchmark", "use robots and pooling only")
    raw = config.get("pooling") or {}  # Snakemake's config dict: validated as Pooling just below
    if not isinstance(raw, dict):
        raise InputError(f"{source}, pooling", f"holds {raw!r}", "give only min_robots: a whole number >= 2")
    try:
        pooling = Pooling.model_validate(raw)
    except ValidationError as exc:
        first = exc.errors()[0]
        key = ".".join(str(part) for part in ("pooling", *first["loc"]))
        raise InputError(
            f"{source}, {key}",
            f"is {first.get('input')!r}: {first['msg']}",
            "give only min_robots: a whole number >= 2",
        ) from None
    robots = config.get("robots")  # Snakemake's config dict: each entry checked by robot_studies
    return robot_studies(robots, root, source=source), pooling.model_dump()


def robots_params(robots: dict[str, RobotStudy], pooling: dict) -> dict:
    """Rule robots' params (:class:`simpick.report.robots.RobotsParams`), validated, as plain data (the
    settings as given: the page shows them, a whole number as such)."""
    from simpick.report.robots import RobotsParams

    shown = [
        {
            "name": s.name,
            "label": s.label,
            "command": s.command(),
            "settings": s.settings(),
            "configfiles": list(s.configfiles),
        }
        for s in robots.values()
    ]
    typed = RobotsParams.model_validate({"robots": shown, "pooling": pooling})
    return typed.model_dump(mode="json")
