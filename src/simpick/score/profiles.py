"""The simulators' profiles as the first page and the decision tree read them: per simulator its profiles
(shipped, tuned, calibrated: any variant the simulators' table names) on the real runs none was fitted on,
the best of them and its settings file (rule simulators' results/simulators/table.csv, simpick.score.simulators).

Nothing is measured or tested here: the figures are the table's; only the smallest error per simulator is
chosen, and each error set beside the robot's own run-to-run spread of its gain.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

# the columns the calibrated profiles bring (rule simulators): without them the table predates them
HELDOUT = "heldout_gain_error"
VARIANT_WORDS = {"shipped": "as shipped", "tuned": "as tuned", "calibrated": "as calibrated to this robot"}


def _num(x) -> float | None:
    try:
        x = float(x)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def _text(x) -> str:
    return "" if x is None or (isinstance(x, float) and math.isnan(x)) else str(x).strip()


def _truth(x) -> bool | None:
    """A CSV's boolean cell (True/False, true/false, 1/0) as a bool, None where empty."""
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    text = _text(x).lower()
    return {"true": True, "1": True, "1.0": True, "false": False, "0": False, "0.0": False}.get(text)


def settings_words(cell) -> str:
    """``friction_ratio=0.62; slip=0.1`` as a reader reads it: ``friction_ratio 0.62, slip 0.1``."""
    items = [s.strip() for s in _text(cell).replace(";", ",").split(",") if s.strip()]
    return ", ".join(s.replace("=", " ", 1) for s in items)


def _mechanics(r: dict) -> tuple[bool, str]:
    """Whether a row passes the analytic mechanics, and in words: a calibrated profile against the mechanics
    of its own parameters (``mechanics_own``), the others against the study's (``mechanics``)."""
    own = _text(r.get("mechanics_own"))
    if r["variant"] == "calibrated" and own:
        counted = re.match(r"\s*(pass\w*|fail\w*)\s+(\d+)\s*(?:/|of)\s*(\d+)", own, re.I)
        if counted:  # "passes 19/20": one case failed
            passed, cases = int(counted.group(2)), int(counted.group(3))
            passes = passed == cases if counted.group(1).lower().startswith("pass") else passed == 0
        else:  # "not validated"
            passes = own.lower().startswith("pass")
        # "passes 17/19; breaks mechanics its tuned profile keeps: ..." (rule simulators' words), the cases named
        # up to three (the simulators' section lists them all)
        head, sep, cases = own.partition("keeps: ")
        names = [c.strip() for c in cases.split(",") if c.strip()]
        if sep and len(names) > 3:
            own = f"{head}keeps: {', '.join(names[:3])} and {len(names) - 3} more"
        return passes, f"its own mechanics: {own}"
    cases, failed = _num(r.get("mechanics_cases")), _num(r.get("mechanics_failed"))
    passes = _text(r.get("mechanics")) == "pass"
    if cases is None:
        return passes, "mechanics not checked" if not _text(r.get("mechanics")) else _text(r.get("mechanics"))
    counted = f"{int(cases - (failed or 0))}/{int(cases)}"
    return passes, f"passes {counted}" if passes else f"fails {int(failed or 0)} of {int(cases)}"


def _files(folder: Path | None, link: str, simulator: str, variant: str, stem: str) -> list[dict[str, str]]:
    """The profile's settings files: found in the settings folder where the report has it, else named by the
    table's stem (``settings_file``, its extension unknown)."""
    if folder is not None and folder.is_dir():
        names = sorted(p.name for p in folder.glob(f"{simulator}-{variant}.*"))
        return [{"name": n, "href": f"{link}/{n}"} for n in names]
    if stem:
        return [{"name": Path(stem).name + ".*", "href": ""}]
    return []


def _model(path: str, link: str) -> dict[str, str] | None:
    """The profile's model file as the report links it: beside the settings folder's link (``link``)."""
    if not path:
        return None
    name = Path(path).name
    return {"name": name, "href": f"{link.rsplit('/', 1)[0]}/models/{name}"}


def simulator_answer(
    table: pd.DataFrame | None,
    settings: str | Path | None = None,
    link: str = "../simulators/settings",
    spread: float | None = None,
) -> dict[str, Any]:
    """Which simulator, as shipped, tuned and calibrated, reproduces the robot on its real runs, and with which
    settings file: from the simulators' table (rule simulators, results/simulators/table.csv) alone, any
    variant its rows name. Per simulator its profiles and the best of them, the simulators by that best;
    ``settings``: the settings folder (links ``link``/<file>); ``spread``: the robot's run-to-run spread of
    its gain where the table has no ``real_spread`` (the verdict's gain margin).

    The error is the held-out gain error (``heldout_gain_error``: on the real runs no profile was fitted on)
    where the table has it, else the gain error over every real run (a table from before the calibrated
    profiles: shipped and tuned were chosen without real data, so every run judges them held out). The best
    profile of a simulator is its smallest error among the profiles that pass their mechanics, else its
    smallest error, named as failing. Nothing is computed that the table does not hold but the choice of the
    smallest and the ratio to the spread."""
    empty = {
        "given": False,
        "heldout": False,
        "metric": "gain error",
        "spread": None,
        "variants": [],
        "calibrated": False,
        "no_calibrated": "",
        "simulators": [],
        "by_variant": {},
        "lead": None,
    }
    if table is None or table.empty or "variant" not in table:
        return empty | {"why_none": "the study ran no simulator profile"}
    heldout = HELDOUT in table.columns and pd.to_numeric(table[HELDOUT], errors="coerce").notna().any()
    key = HELDOUT if heldout else "gain_error"
    if "real_spread" in table.columns and pd.to_numeric(table.real_spread, errors="coerce").notna().any():
        spread = _num(pd.to_numeric(table.real_spread, errors="coerce").dropna().max())
    folder = Path(settings) if settings else None
    variants = list(dict.fromkeys(str(v) for v in table.variant))
    by_sim: dict[str, dict[str, Any]] = {}
    for r in table.to_dict("records"):
        sim = by_sim.setdefault(
            str(r["simulator"]),
            {
                "simulator": str(r["simulator"]),
                "label": str(r["label"]),
                "engine": _text(r.get("engine")),
                "profiles": [],
                "not_run": [],
            },
        )
        status = _text(r.get("status"))
        if not status.startswith("run"):
            sim["not_run"].append({"variant": str(r["variant"]), "why": status.removeprefix("not run: ")})
            continue
        passes, mechanics = _mechanics(r)
        error = _num(r.get(key))
        low, high = _num(r.get(f"{key}_low")), _num(r.get(f"{key}_high"))
        within = _truth(r.get("within_spread")) if heldout else None
        if within is None and error is not None and spread is not None:
            within = error <= spread
        settable = _text(r.get("turning_settable"))
        sim["profiles"].append(
            {
                "variant": str(r["variant"]),
                "words": VARIANT_WORDS.get(str(r["variant"]), str(r["variant"])),
                "error": error,
                "low": low,
                "high": high,
                "runs": _num(r.get("heldout_runs") if heldout else r.get("n_runs")),
                "spread_ratio": None if error is None or not spread else error / spread,
                "within": within,
                "heading": _num(r.get("heldout_heading_error" if heldout else "heading_error")),
                "passes": passes,
                "mechanics": mechanics,
                # the first page's words: the count alone (the cases it breaks are in the simulators' section)
                "mechanics_short": mechanics.split(";")[0].replace("its own mechanics: passes", "own mechanics"),
                "settings": settings_words(r.get("calibrated_settings")),
                "settable": settable,
                # a simulator whose settings cannot move the turning: said of its calibrated profile
                "not_settable": (
                    settable.removeprefix("no:").strip()
                    if settable.startswith("no") and str(r["variant"]) == "calibrated"
                    else ""
                ),
                "files": _files(folder, link, str(r["simulator"]), str(r["variant"]), _text(r.get("settings_file"))),
                # the model that opens as it is in the simulator, where simpick writes one (rule simulator_models)
                "model": _model(_text(r.get("model_file")), link),
            }
        )
    simulators = []
    for sim in by_sim.values():
        measured = [p for p in sim["profiles"] if p["error"] is not None]
        passing = [p for p in measured if p["passes"]]
        best = min(passing or measured, key=lambda p: p["error"], default=None)
        order = {v: i for i, v in enumerate(variants)}
        sim["profiles"].sort(key=lambda p: order.get(p["variant"], len(order)))
        simulators.append(sim | {"best": best, "ran": bool(sim["profiles"])})
    simulators.sort(
        key=lambda s: (
            s["best"] is None,
            not (s["best"] or {}).get("passes", False),
            (s["best"] or {}).get("error") or 0,
        )
    )
    by_variant = {}
    for v in variants:
        candidates = [(s, p) for s in simulators for p in s["profiles"] if p["variant"] == v and p["error"] is not None]
        passing = [c for c in candidates if c[1]["passes"]]
        if candidates:
            s, p = min(passing or candidates, key=lambda c: c[1]["error"])
            by_variant[v] = {"label": s["label"], "simulator": s["simulator"], **p}
    lead = next(
        ({"label": s["label"], "simulator": s["simulator"], **s["best"]} for s in simulators if s["best"]), None
    )
    return {
        "given": lead is not None,
        "why_none": ""
        if lead is not None
        else (
            f"no profile's {'held-out ' if heldout else ''}yaw-rate gain error could be measured on these real data"
            if any(s["profiles"] for s in simulators)
            else "no simulator profile ran in this study"
        ),
        "heldout": heldout,
        "metric": "held-out gain error" if heldout else "gain error",
        "spread": spread,
        # the table's columns: the variants some simulator ran
        "variants": [v for v in variants if v in by_variant],
        "calibrated": any(p["variant"] == "calibrated" for s in simulators for p in s["profiles"]),
        "no_calibrated": _why_no_calibrated(table, variants, heldout),
        "simulators": simulators,
        "by_variant": by_variant,
        "lead": lead,
    }


def spread_count(row: dict) -> str:
    """What a class's spread was taken over: its runs' count, or "<n> pairs" where it is DRIVE's step-to-step
    repeatability over pairs of steps of similar command (per_class.csv's spread_basis)."""
    n = int(_num(row.get("spread_runs")) or 0)
    return f"{n} pairs" if "pairs" in _text(row.get("spread_basis")) else str(n)


def class_answer(
    per_class: pd.DataFrame | None,
    table: pd.DataFrame | None,
    settings: str | Path | None = None,
    link: str = "../simulators/settings",
) -> list[dict[str, Any]]:
    """Per terrain class with held-out runs, the calibrated file that turned closest to the robot on them: among
    the simulators whose calibrated profile passes the mechanics of its own parameters, each one's pooled
    calibrated file and its class file where the class has one, judged on the class's held-out runs (per_class.csv,
    rule simulators), with the class's own spread beside it. A class's held-out runs are few (their number is
    given): a hint per class, beside the table's judgement over every held-out run."""
    if per_class is None or per_class.empty or table is None or table.empty:
        return []
    calibrated = table[table.variant.astype(str) == "calibrated"]
    passing = {str(r["simulator"]) for r in calibrated.to_dict("records") if _mechanics(r)[0]}
    labels = dict(zip(table.simulator.astype(str), table.label.astype(str)))
    models = {str(r["simulator"]): _text(r.get("model_file")) for r in calibrated.to_dict("records")}
    folder = Path(settings) if settings else None
    out = []
    for cls, rows in per_class.groupby("terrain_class", sort=True):
        options = []
        for r in rows.to_dict("records"):
            sim = str(r["simulator"])
            if sim not in passing or not (_num(r.get("heldout_runs")) or 0):
                continue
            own = _text(r.get("settings_file"))
            spread = _num(r.get("class_spread"))
            # the pooled file always, and the class's own where it has one: each judged on the class's runs
            for stem, column, model, fit in (
                (f"{sim}-calibrated", "pooled_fit_error", models.get(sim, ""), "the pooled fit"),
                *(
                    [(Path(own).name, "class_fit_error", _text(r.get("model_file")), "its class's own fit")]
                    if own
                    else []
                ),
            ):
                error = _num(r.get(column))
                if error is None:
                    continue
                files = (
                    [{"name": n, "href": f"{link}/{n}"} for n in sorted(p.name for p in folder.glob(f"{stem}.*"))]
                    if folder is not None and folder.is_dir()
                    else [{"name": f"{stem}.*", "href": ""}]
                )
                options.append(
                    {
                        "terrain_class": str(cls),
                        "simulator": sim,
                        "label": labels.get(sim, sim),
                        "fit": fit,
                        "error": error,
                        # its 95 % interval where the class has statistics.min_runs held-out runs, else None
                        "low": _num(r.get(f"{column}_low")),
                        "high": _num(r.get(f"{column}_high")),
                        "runs": int(_num(r.get("heldout_runs")) or 0),
                        "spread": spread,
                        "spread_runs": spread_count(r),
                        "spread_ratio": error / spread if spread else None,
                        "files": files,
                        "model": _model(model, link),
                    }
                )
        if options:
            out.append(min(options, key=lambda o: o["error"]))
    return out


def _why_no_calibrated(table: pd.DataFrame, variants: list[str], heldout: bool) -> str:
    """Why the table has no calibrated profile that ran ('' where it has one)."""
    if "calibrated" not in variants:
        why = "this study's simulators' table has no calibrated rows: it was written before the calibrated profiles"
        if not heldout:
            why += " (nor held-out columns), so the errors are over all the real data"
        return why
    ran = table.status.astype(str).str.startswith("run")
    if (ran & (table.variant == "calibrated")).any():
        return ""
    if not ran.any():  # no profile ran at all: the answer's own reason says so, nothing to add about calibration
        return ""
    # the simulators that ran some profile: why their calibrated one did not (the others' rows say why they ran none)
    rows = table[(table.variant == "calibrated") & table.simulator.isin(table.simulator[ran])]
    reasons = sorted({str(s).removeprefix("not run: ") for s in rows.status})
    return "no calibrated profile ran in this study: " + "; ".join(reasons)


# --------------------------------------------------------------------------
# The simulators' tree: the profile each leaf's answers ask for
# --------------------------------------------------------------------------


def _profile_text(label: str, p: dict) -> str:
    """``Gazebo Classic, calibrated: friction_ratio 0.62 (settings file results/simulators/settings/...)``."""
    text = f"{label}, {p['variant']}" + (f": {p['settings']}" if p.get("settings") else "")
    files = [f["href"] or f["name"] for f in p.get("files") or []]
    return text + (f" (settings file {', '.join(files)})" if files else "")


def name_profiles(tree: dict, table, settings: str | None = None, link: str = "results/simulators/settings") -> dict:
    """The simulators' tree (leaves of simulators, not profiles) with, per leaf, the profile of each of its
    simulators that the leaf's answers ask for (``profiles``): where the path asks for closeness to the real
    robot, the simulator's calibrated profile (the closest of its profiles on the held-out runs that passes the
    mechanics of its own parameters: simpick.score.profiles), with its settings and file; elsewhere its tuned
    profile, the set-up that passes mechanics as the simulator's users set it, and the calibrated one beside it
    as ``closest``. ``table``: the simulators' table (results/simulators/table.csv) as a frame; ``settings``: its
    settings folder. A simulator without a calibrated row keeps its tuned profile on every path."""
    found = simulator_answer(table, settings, link=link)
    by_sim = {s["simulator"]: s for s in found["simulators"]}
    for node in tree["nodes"].values():
        if node["kind"] != "leaf":
            continue
        close = any(step["question"] == "closeness" and step["answer"] != "No" for step in node.get("path", []))
        named = []
        for simulator in node["engines"]:
            s = by_sim.get(simulator)
            if s is None or not s["profiles"]:
                continue
            variants = {p["variant"]: p for p in s["profiles"]}
            calibrated = variants.get("calibrated")
            usable = calibrated is not None and calibrated["passes"] and not calibrated["not_settable"]
            tuned = variants.get("tuned") or s["best"] or s["profiles"][0]
            chosen = calibrated if close and usable else tuned
            entry = {
                "simulator": simulator,
                "variant": chosen["variant"],
                "settings": chosen["settings"],
                "files": [f["href"] or f["name"] for f in chosen["files"]],
                "text": _profile_text(s["label"], chosen),
            }
            if usable and chosen is not calibrated:
                entry["closest"] = _profile_text(s["label"], calibrated)
            elif calibrated is not None and not usable:
                entry["closest"] = (
                    f"{s['label']}: no calibrated profile to name ("
                    + (
                        f"its turning is not settable: {calibrated['not_settable']}"
                        if calibrated["not_settable"]
                        else calibrated["mechanics"]
                    )
                    + ")"
                )
            named.append(entry)
        node["profiles"] = named
    tree["profiles"] = {
        "calibrated": found.get("calibrated", False),
        "why_not": found.get("no_calibrated", ""),
        "closeness_asked": any(q["key"] == "closeness" and q["asked"] for q in tree.get("questions", [])),
    }
    return tree
