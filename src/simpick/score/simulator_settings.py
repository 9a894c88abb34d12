"""The settings files a user pastes into each simulator (rule simulator_settings): every run profile in its
simulator's own format (:mod:`simpick.engines.simulator_files`), headed by what it is, the robot, its figures here
and the command that regenerates it; a calibrated profile's headed by the data it was fitted on and its held-out
figures, and a class's own file where its fit beats the pooled one (:func:`class_files`)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml
from pydantic import Field

from simpick.engines.catalog import load_catalog
from simpick.engines.simulators import model_name
from simpick.params import JobParams


class SimulatorSettingsParams(JobParams):
    """What rule simulator_settings' job reads: each run profile's full settings and the robot's wheel links."""

    profiles: dict[str, dict[str, Any]] = Field(
        description="profile -> its adapter's settings in full (the plan's, checked by the adapter's model)"
    )
    robot: str = Field(description="the robot's URDF <robot name>")
    wheel_links: list[str] = Field(description="the driven wheels' links (the files' <gazebo reference>)")


def read_fits(inputs: dict) -> dict[str, dict]:
    """simulator -> its calibration file (results/simulators/calibration/<simulator>.yaml)."""
    files = inputs.get("calibrations") or []
    files = [files] if isinstance(files, str) else list(files)
    return {Path(f).stem: yaml.safe_load(Path(f).read_text()) for f in files if Path(f).is_file()}


def exposed_settings_text(settings: Mapping[str, Any], entries: Mapping, title: list[str]) -> str:
    """A profile of a simulator without a settings file format (MORSE: a builder script sets its scene): each
    setting the profile states, as its user sets it (the catalog's exposed_as), with simpick's value and source."""
    lines = [f"# {line}" for line in title]
    for key, (_, entry) in entries.items():
        lines.append(f"{entry.exposed_as}")
        lines.append(f"    simpick {key} = {settings.get(key, entry.value)!r}; source: {entry.source}")
    return "\n".join(lines) + "\n"


def settings_files_job(inputs: dict, params: dict, output: str) -> None:
    """results/simulators/settings/: each run profile in its simulator's format (simpick.engines.simulator_files),
    headed by what it is, the robot, its flat-ground figures here and the command that regenerates it."""
    from simpick.engines import simulator_files as formats

    p = SimulatorSettingsParams.model_validate(params)
    catalog = load_catalog(inputs["catalog"])
    table = pd.read_csv(inputs["table"])
    out = Path(output)
    out.mkdir(parents=True, exist_ok=True)
    robot, wheels = p.robot, list(p.wheel_links)
    fits = read_fits(inputs)
    for profile, settings in p.profiles.items():
        simulator, variant = profile.rsplit("-", 1)
        sim = catalog.simulators[simulator]
        if variant == "calibrated":
            _calibrated_file(formats, sim, simulator, settings, fits.get(simulator), table, catalog, robot, wheels, out)
            continue
        row = table[(table.simulator == simulator) & (table.variant == variant)]
        r = row.iloc[0] if len(row) else None
        figures = "not measured"
        if r is not None and pd.notna(r.get("gain_flat")):
            figures = (
                f"yaw-rate gain on flat ground {r.gain_flat:.3f} ({r.gain_flat_min:.3f}-{r.gain_flat_max:.3f}; "
                f"Coulomb {r.gain_coulomb:.3f}), mechanics {r.mechanics} "
                f"({int(r.mechanics_cases - r.mechanics_failed)} of {int(r.mechanics_cases)} analytic cases)"
            )
            if pd.notna(r.get("gain_error")):
                figures += f"; real gain error {r.gain_error:.3f} ({r.gain_outcome})"
        title = [
            f"simpick settings: {sim.label}, {variant}, for {robot}",
            f"{sim.shipped.basis if variant == 'shipped' else sim.tuned.basis}",
            f"measured by simpick through {sim.simpick_build}: {figures}",
            REGENERATE,
        ]
        entries = catalog.entries(simulator, variant, robot)
        if sim.settings_format is None:  # no file format of its own: where its user sets each value
            texts = {"txt": exposed_settings_text(settings, entries, title)}
        else:
            texts = formats.write(sim.settings_format, sim.engine, settings, entries, title, wheels)
        for suffix, text in texts.items():
            (out / f"{profile}.{suffix}").write_text(text)


# no double hyphen: the line heads XML comments too
REGENERATE = "regenerate: snakemake -c 2 results/simulators/settings (docs/simulators.md)"


def _num(x) -> str:
    return f"{float(x):.3f}" if x is not None and np.isfinite(float(x)) else "n/a"


def calibrated_header(sim, simulator: str, fit: dict, row) -> list[str]:
    """The head of a calibrated profile's settings file: what it was fitted on, the fit, its held-out figures
    beside the real robot's spread and its mechanics, and the command that regenerates it."""
    f = fit.get("fit") or {}
    lines = [
        f"simpick settings: {sim.label}, calibrated, for {fit.get('robot')}",
        f"fitted on {fit.get('source')}: training runs {_runs(fit.get('train_runs'))}; the turning ones of "
        f"{', '.join(f.get('classes') or [])} ({_runs(f.get('real_runs'))}) give the real steady yaw-rate gain "
        f"{_num(f.get('real_gain'))}; held out: {_runs(fit.get('test_runs'))}",
    ]
    if fit.get("searchable"):
        fitted = fitted_parameters(fit)
        ran = f.get("optimizer") or {}
        by = f" by {ran['name']} {ran.get('version', '')}".rstrip() if ran.get("name") else ""
        lines.append(
            f"fit: least squares of the training runs' gain residuals{by} ({len(f.get('trials') or [])} engine "
            f"evaluations), {fitted}; training gain error tuned {_num(f.get('train_error_tuned'))}, "
            f"calibrated {_num(f.get('train_error'))}; kept {f.get('kept')}: "
            + ", ".join(f"{k} = {v}" for k, v in (fit.get("settings") or {}).items())
        )
        if f.get("parts"):
            lines.append(f"share of the training error's fall: {fit_parts(fit)}")
        lines += [f"as {sim.label} sets it: {text}" for text in (fit.get("exposed") or {}).values()]
    else:
        lines.append(f"no setting fitted: {fit.get('why_not')}; these are the tuned settings, the best it reaches")
    if row is not None:
        runs = int(row["heldout_runs"]) if pd.notna(row.get("heldout_runs")) else 0
        lines.append(
            f"held out: gain error {_num(row.get('heldout_gain_error'))} [{_num(row.get('heldout_gain_error_low'))}, "
            f"{_num(row.get('heldout_gain_error_high'))}] over {runs} runs against the robot's own "
            f"spread {_num(row.get('real_spread'))} (within: {row.get('within_spread')}); heading error "
            f"{_num(row.get('heldout_heading_error'))} rad; mechanics of its own parameters: {row.get('mechanics_own')}"
        )
    lines.append(REGENERATE)
    return [line.replace("--", "-") for line in lines]


def fitted_parameters(fit: dict) -> str:
    """Each setting the fit searched, as the table and the header give it (:func:`_parameter`), ``; ``-joined."""
    return "; ".join(_parameter(k, e) for k, e in ((fit.get("fit") or {}).get("parameters") or {}).items())


def fit_parts(fit: dict) -> str:
    """The contact's and the actuator's share of what the fit gained on its training runs, in words (the fit's
    ``parts``: simpick.studies.simulator_calibration.part_shares)."""
    words = []
    for part, e in ((fit.get("fit") or {}).get("parts") or {}).items():
        if not e.get("settings"):
            words.append(f"{part}: none searched")
        elif e.get("share") is None:
            words.append(f"{part}: {e.get('why_none', 'no share')}")
        else:
            alone = _num(e.get("train_error"))
            words.append(f"{part} ({', '.join(e['settings'])}) {_num(e['share'])} (training error alone {alone})")
    return "; ".join(words)


def _parameter(name: str, entry: dict) -> str:
    """A fitted setting as the header gives it: its value and 95 % interval, or why the runs cannot fix it."""
    if not entry.get("identifiable"):
        return f"{name} {entry.get('value')} ({entry.get('why')})"
    low, high = entry.get("interval") or [None, None]
    bound = f", at its {entry['at_bound']} bound" if entry.get("at_bound") else ""
    return f"{name} {entry.get('value')} [{low}, {high}]{bound}"


def _runs(runs, most: int = 12) -> str:
    """Runs named one by one up to ``most``; beyond that (DRIVE's steps) their number and where the split is."""
    runs = list(runs or [])
    if len(runs) <= most:
        return ", ".join(runs) or "none"
    return f"{len(runs)} (listed in results/simulators/calibration/split.csv and the fit's file)"


# a class's own settings get a file of their own where one differs from the pooled fit's by at least this much: the
# friction ratio by this much, any other setting by this share of the pooled value
CLASS_FILE_RATIO = 0.01


def class_settings(entry: dict) -> dict:
    """A class's own fitted settings (its fit's ``settings``; an entry of the friction ratio alone, from before
    the classes fitted every setting, as that)."""
    if entry.get("settings"):
        return dict(entry["settings"])
    return {"friction_ratio": entry["friction_ratio"]} if entry.get("friction_ratio") is not None else {}


def settings_text(settings: dict) -> str:
    """Settings in words: ``name = value``, ``, ``-joined."""
    return ", ".join(f"{k} = {v}" for k, v in settings.items())


def _differs(name: str, own, pooled) -> bool:
    if own is None:
        return False
    if pooled is None:
        return True
    if isinstance(own, str) or isinstance(pooled, str):  # a required choice (Webots' friction_direction "wheel")
        return own != pooled
    scale = 1.0 if name == "friction_ratio" else abs(float(pooled))
    return abs(float(own) - float(pooled)) >= CLASS_FILE_RATIO * scale


# how a class's held-out runs were judged, by the first key of their cases (simpick.studies.simulator_calibration.units)
HELDOUT_CASES = {
    "segments": "their turning segments replayed",
    "windows": "their first turning windows of the full replay, each run replayed from rest",
    "steps": "their steps replayed from the warm-up",
}


def class_header(sim, simulator: str, fit: dict, terrain: str, entry: dict) -> list[str]:
    """The head of a class's calibrated file: what it was fitted on, its engine fit, and both fits on the
    class's held-out runs (what the held-out figure replays of them)."""
    held = entry.get("heldout") or {}
    lines = [
        f"simpick settings: {sim.label}, calibrated for {terrain}, for {fit.get('robot')}",
        f"fitted on {fit.get('source')}, {terrain} only: training runs {_runs(entry.get('runs'))}, real steady "
        f"yaw-rate gain {_num(entry.get('real_gain'))}; {entry.get('placed_by')}: "
        f"{settings_text(class_settings(entry))}, engine gain {_num(entry.get('engine_gain'))} (the pooled fit's "
        f"{settings_text(fit.get('settings') or {}) or 'tuned settings'})",
    ]
    if held:
        lines.append(
            f"held out: {held.get('runs')} {terrain} runs, real gain {_num(held.get('real_gain'))}; the engine's "
            f"gain on them, this file {_num(held.get('class_fit_gain'))} (error "
            f"{_num(held.get('class_fit_error'))}), the pooled fit {_num(held.get('pooled_fit_gain'))} (error "
            f"{_num(held.get('pooled_fit_error'))}): "
            + (
                HELDOUT_CASES.get(
                    next(iter(held.get("cases") or {}), ""), "a steady-turn case, not a replay of those runs"
                )
            )
        )
    else:
        lines.append(f"held out: no {terrain} run that turns under a steady command: not judged")
    lines.append(REGENERATE)
    return [line.replace("--", "-") for line in lines]


def class_files(fit: dict | None) -> dict[str, dict]:
    """terrain class -> its own fit, for the classes whose settings, fitted on the engine, differ from the pooled
    fit's (:data:`CLASS_FILE_RATIO`) and turn closer to the class's training runs than the pooled fit does
    (``improves``: training runs alone)."""
    if not fit or not fit.get("searchable"):
        return {}
    pooled = fit.get("settings") or {}
    return {
        c: e
        for c, e in (fit.get("per_class") or {}).items()
        if pooled
        and e.get("engine_gain") is not None
        and e.get("improves", True)
        and any(_differs(k, v, pooled.get(k)) for k, v in class_settings(e).items())
    }


def calibrated_settings(engine: str, settings: Mapping[str, Any], fit: dict) -> dict[str, dict]:
    """A calibrated profile's full adapter settings per file (its name's tail): ``""`` its tuned ``settings`` with
    the fit's over them, ``"-<class>"`` those with a class's own settings over them, for each class with a file of its
    own (:func:`class_files`). The settings files and the models (rule simulator_models) are written from these."""
    from simpick.engines import get_engine

    model = get_engine(engine).settings_model
    pooled = model.model_validate({**settings, **(fit.get("settings") or {})}).model_dump(mode="json")
    out = {"": pooled}
    # a class's fit ran with the settings its search space requires beside the ratio (fit.fixed, Gazebo's wheels'
    # <mu2> raised to their <mu>), also where the pooled fit was not kept and the pooled file has none of them
    fixed = dict((fit.get("fit") or {}).get("fixed") or {})
    for cls, entry in class_files(fit).items():
        own = model.model_validate({**pooled, **fixed, **class_settings(entry)})
        out[f"-{cls}"] = own.model_dump(mode="json")
    return out


def _calibrated_file(formats, sim, simulator, settings, fit, table, catalog, robot, wheels, out: Path) -> None:
    """A calibrated profile's file: its tuned settings with the fit's over them, in the simulator's format."""
    from simpick.engines.catalog import Setting

    if fit is None:
        return
    fitted = dict(fit.get("settings") or {})
    variants = calibrated_settings(sim.engine, settings, fit)
    settings = variants[""]
    entries = dict(catalog.entries(simulator, "calibrated", robot))
    for key, value in fitted.items():
        text = (fit.get("exposed") or {}).get(key, "not exposed")
        entries[key] = ("calibrated", Setting(value=value, exposed_as=text, source=f"fitted: {fit.get('source')}"))
    row = table[(table.simulator == simulator) & (table.variant == "calibrated")]
    header = calibrated_header(sim, simulator, fit, row.iloc[0].to_dict() if len(row) else None)
    files = [("", settings, entries, header)]
    for cls, entry in class_files(fit).items():  # a class whose own fit differs: a file of its own
        own = {}
        for key, value in class_settings(entry).items():  # each of the class's own values, said as the pooled's
            text = str((fit.get("exposed") or {}).get(key, "not exposed"))
            text = text.replace(str(fitted.get(key)), str(value)) if fitted.get(key) is not None else text
            own[key] = (
                "calibrated",
                Setting(value=value, exposed_as=text, source=f"fitted: {fit.get('source')}, {cls}"),
            )
        files.append(
            (
                f"-{cls}",
                variants[f"-{cls}"],
                {**entries, **own},
                class_header(sim, simulator, fit, cls, entry),
            )
        )
    for tail, values, named, head in files:
        if sim.settings_format is None:  # no file format of its own (MORSE): where its user sets each value
            texts = {"txt": exposed_settings_text(values, named, head)}
        else:
            texts = formats.write(sim.settings_format, sim.engine, values, named, head, wheels)
        for suffix, text in texts.items():
            (out / f"{model_name(simulator, 'calibrated')}{tail}.{suffix}").write_text(text)
