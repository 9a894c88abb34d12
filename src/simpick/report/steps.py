"""The report's DRIVE section: the engines against the real robot of a DRIVE dataset (results/drive/<name>/,
rules/drive.smk), titled from the study's robot label ("against the real Clearpath Warthog").

Self-contained: :func:`drive_section` reads the tables into a context (None where no DRIVE comparison
exists, so a study without one has no section) and :func:`render_drive_section` renders it to HTML.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pandas as pd

from simpick.score.equivalence import pooled as over_all_terrains

TABLES = ("summary", "outcomes", "turning", "errors")


def _f(x: Any, digits: int = 3) -> str:
    try:
        x = float(x)
    except (TypeError, ValueError):
        return "–"
    return "–" if math.isnan(x) else f"{x:.{digits}g}"


def _ci(row: pd.Series, metric: str) -> str:
    mean, low, high = (row.get(f"{metric}_{k}") for k in ("mean", "low", "high"))
    if _f(low) == "–":
        return _f(mean)
    return f"{_f(mean)} [{_f(low)}, {_f(high)}]"


def read_tables(folder: str | Path) -> dict[str, pd.DataFrame] | None:
    """The DRIVE comparison's tables under ``folder`` (results/drive/<name>), None where it has none."""
    folder = Path(folder)
    if not all((folder / f"{t}.csv").is_file() for t in TABLES):
        return None
    return {t: pd.read_csv(folder / f"{t}.csv") for t in TABLES}


def drive_section(folder: str | Path, label: str, calibration: str | Path | None = None) -> dict | None:
    """The section's context from ``folder``'s tables; ``label``: the study's robot label (config
    ``robot.label``); ``calibration``: the DRIVE calibration's held-out turning table, where the study ran
    it (rules/report.smk passes it only then). None where the folder holds no DRIVE comparison."""
    tables = read_tables(folder)
    if tables is None:
        return None
    summary, outcomes, errors = tables["summary"], tables["outcomes"], tables["errors"]
    pooled = summary[summary.session == "all"]
    rows = [
        {
            "terrain": r.terrain_class,
            "engine": r.engine,
            "steps": int(r.steps),
            "failed": int(r.failed),
            "gain_real": _f(r.gain_real_median),
            "gain_sim": _f(r.gain_sim_median),
            "gain_error": _ci(r, "gain_error"),
            "gain_floor": _f(r.gain_floor_sd),
            "heading_error": _ci(r, "heading_error"),
            "speed_error": _ci(r, "speed_error"),
            "speed_floor": _f(r.speed_floor_sd),
            "start": f"{_f(r.start_dv_median_abs, 2)} m/s, {_f(r.start_dwz_median_abs, 2)} rad/s",
            "wall": _f(r.wall_time_per_step, 2),
        }
        for _, r in pooled.sort_values(["terrain_class", "engine"]).iterrows()
    ]
    scoped = over_all_terrains(outcomes)
    # per metric (in the table's order), the engines from the smallest mean error
    order = pd.Categorical(scoped.metric, categories=list(dict.fromkeys(scoped.metric)), ordered=True)
    scoped = scoped.assign(_order=order).sort_values(["_order", "mean"])
    verdict = [
        {
            "metric": o.label,
            "engine": o.engine,
            "outcome": o.outcome,
            "mean": _f(o["mean"]),
            "diff": f"{_f(o.diff_to_best)} [{_f(o.diff_low)}, {_f(o.diff_high)}]",
            "margin": _f(o.margin),
            "note": "" if pd.isna(o.note) else o.note,
        }
        for _, o in scoped.iterrows()
    ]
    turning = tables["turning"]
    per_session = turning[turning.session != "all"]
    reversed_steps = int(per_session.icp_reversed_steps.sum()) if "icp_reversed_steps" in per_session else None
    calibrated = _calibration_rows(Path(calibration)) if calibration else None
    failed = errors[errors.status != "ok"]
    failures = [f"{r.engine} {r.session}/{int(r.step):03d}: {r.reasons}" for r in failed.itertuples()][:50]
    return {
        "label": label,
        "steps": int(errors.case.nunique()),
        "sessions": int(errors.session.nunique()),
        "terrains": ", ".join(sorted(errors.terrain_class.unique())),
        "rows": rows,
        "outcomes": verdict,
        "unit": str(scoped.paired_by.iloc[0]) if len(scoped) and "paired_by" in scoped else "step",
        "failures": failures,
        "icp_reversed": reversed_steps,
        "calibration": calibrated,
    }


def _calibration_rows(path: Path) -> list[dict]:
    """The DRIVE calibration's held-out turning table (simpick.studies.calibration.steps.turning_table), one
    row per terrain and model with the configured and calibrated variants side by side."""
    table = pd.read_csv(path)
    rows = []
    for (terrain, engine), g in table.groupby(["terrain_class", "engine"], sort=True):
        v = g.set_index("variant")
        conf = v.loc["configured"] if "configured" in v.index else None
        cal = v.loc["calibrated"] if "calibrated" in v.index else None
        first = conf if conf is not None else cal
        rows.append(
            {
                "terrain": terrain,
                "engine": engine,
                "steps": int(first.held_out_turning_steps),
                "gain_real": _f(first.gain_real),
                "multiplier_real": _f(first.multiplier_real),
                "gain": " -> ".join(_f(x.gain_sim) for x in (conf, cal) if x is not None),
                "multiplier": " -> ".join(_f(x.multiplier_sim) for x in (conf, cal) if x is not None),
            }
        )
    return rows


def render_drive_section(folder: str | Path, label: str, calibration: str | Path | None = None) -> str | None:
    """The section alone as HTML, from the report's own template (templates/drive_section.html.j2, which
    the report includes); None where ``folder`` holds no DRIVE comparison."""
    import jinja2

    context = drive_section(folder, label, calibration)
    if context is None:
        return None
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(Path(__file__).parent / "templates")), autoescape=True)
    return env.get_template("drive_section.html.j2").render(drive=context)
