"""The calibration summary: per engine and terrain class (and pooled over classes), the held-out
errors before and after calibration with intervals over runs, paired tests of the change, the
winners; the job that writes it with the units, the parameters found and the turning tables."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import yaml

from simpick.compare.realmetrics import paired_test
from simpick.inputs.robot import load_robot
from simpick.studies.calibration.intervals import interval_over_runs, stats_of
from simpick.studies.calibration.turning import target_table, turning_table
from simpick.tables import write_csv

POOLED = "all classes"  # the summary's pooled rows: every class's units, each class calibrated on its own


def _change_verdict(test: dict, min_runs: int) -> str:
    """A change judged by the paired sign-flip test over runs (simpick.compare.realmetrics.paired_test of
    calibrated against configured): improved, worse, no clear difference, or too few runs."""
    if test["verdict"] == "too few runs":
        return f"too few runs ({test['n_runs']} < {min_runs})"
    return {"a": "worse", "b": "improved"}.get(test["verdict"], test["verdict"])


def _summary_row(g: pd.DataFrame, runs: pd.Series, min_runs: int, level: float) -> dict:
    """One engine and set over the units in ``g`` (as configured and as calibrated), with intervals
    over the independent runs named by ``runs`` (one key per unit), and the change (calibrated
    minus configured, per unit) judged by a paired test over runs."""
    conf = g[g.variant == "configured"].set_index("unit")
    cal = g[g.variant == "calibrated"].set_index("unit")
    run_of = dict(zip(g.unit, runs))
    row = {
        "n_units": len(conf),
        "n_runs": len({run_of[u] for u in conf.index}),
        "n_failed_configured": int((conf.status != "ok").sum()),
        "n_failed_calibrated": int((cal.status != "ok").sum()),
    }
    for variant, frame in (("configured", conf), ("calibrated", cal)):
        for fig in ("objective", "error_yaw_rate", "error_accel_x"):
            ok = frame[fig].notna()
            mean, lo, hi = interval_over_runs(
                frame.loc[ok, fig].to_numpy(), [run_of[u] for u in frame.index[ok]], min_runs, level
            )
            row.update({f"{fig}_{variant}": mean, f"{fig}_{variant}_low": lo, f"{fig}_{variant}_high": hi})
    common = conf.index.intersection(cal.index)
    keys = [run_of[u] for u in common]
    test = paired_test(
        cal.loc[common, "objective"].to_numpy(), conf.loc[common, "objective"].to_numpy(), keys, min_runs, level
    )
    mean = test["mean"]
    row.update(
        {
            "change": mean,
            "change_low": test["low"],
            "change_high": test["high"],
            "change_p": test["p_value"],
            "change_verdict": _change_verdict(test, min_runs),
        }
    )
    return row


def _normalised(frame: pd.DataFrame) -> pd.DataFrame:
    """Each class's objectives divided by that class's mean configured objective over every model
    (per set): a change pooled across classes is then a share of the class's own error, and models
    stay comparable (the objective of snow is about ten times asphalt's on the committed segments;
    unnormalised, snow would decide every pooled figure)."""
    conf = frame[frame.variant == "configured"]
    scale = conf.groupby(["terrain_class", "set"])["objective"].mean()
    keys = pd.MultiIndex.from_arrays([frame.terrain_class, frame.set])
    return frame.assign(objective=frame.objective.to_numpy() / scale.reindex(keys).to_numpy())


def _winners(out: pd.DataFrame, evals: pd.DataFrame, min_runs: int, level: float) -> pd.DataFrame:
    """Per class (and pooled) and set: the model with the smallest mean objective as configured and
    as calibrated, named only where a paired test over runs separates it from the runner-up
    (otherwise ``no separation`` or ``too few runs``); ranks only from ``min_runs`` runs on."""
    for variant in ("configured", "calibrated"):
        out[f"rank_{variant}"] = pd.array([pd.NA] * len(out), dtype="Int64")
        out[f"winner_{variant}"] = ""
    for (cls, set_), g in out.groupby(["terrain_class", "set"]):
        enough = g[g.n_runs >= min_runs]
        for variant in ("configured", "calibrated"):
            col = f"objective_{variant}"
            out.loc[enough.index, f"rank_{variant}"] = enough[col].rank(method="min").astype("Int64")
            ranked = g.dropna(subset=[col]).sort_values(col)
            if len(ranked) < 2:
                verdict = ranked.engine.iloc[0] if len(ranked) == 1 and len(enough) == 1 else "–"
            elif len(enough) < len(g):
                verdict = f"too few runs ({int(g.n_runs.min())} < {min_runs})"
            else:
                best, second = ranked.engine.iloc[0], ranked.engine.iloc[1]
                units = evals[evals.set == set_]
                if cls != POOLED:
                    units = units[units.terrain_class == cls]
                else:  # normalised by each class's configured objective, as the pooled rows are
                    units = _normalised(units)
                units = units[units.variant == variant]
                units = units.assign(
                    key=units.terrain_class + "/" + units.unit.astype(str),
                    runkey=units.terrain_class + "/" + units.run.astype(str),
                )
                wide = units.pivot_table(index="key", columns="engine", values="objective")
                if best not in wide or second not in wide:
                    out.loc[g.index, f"winner_{variant}"] = "no paired comparison"
                    continue
                run_of = units.drop_duplicates("key").set_index("key").runkey.reindex(wide.index)
                t = paired_test(wide[best].to_numpy(), wide[second].to_numpy(), run_of.to_numpy(), min_runs, level)
                verdict = best if t["verdict"] == "b" else f"{best} and {second} not separated (p {t['p_value']:.2g})"
            out.loc[g.index, f"winner_{variant}"] = verdict
    return out


def summarise(evals: pd.DataFrame, best: dict[tuple[str, str], dict], statistics: dict | None = None) -> pd.DataFrame:
    """Per class, engine, set and variant: mean objective and errors with BCa intervals over runs
    (none below ``statistics.min_runs`` runs), the change against as configured judged by a paired
    sign-flip test over runs (``change_verdict``: improved, worse, no clear difference, too few
    runs), and the models' rank and winner in the class as configured and as calibrated (none below
    ``min_runs`` runs; a winner only where the paired test separates it from the runner-up).
    Then the same over every class pooled (terrain_class ``POOLED``), on per-class normalised
    objectives (``normalised`` true: each class's objective over its mean as configured over every
    model, so a change is a share of each class's own error): a class has only a few runs (BorealTC 4-8, so 2-4
    test runs), too few for an interval, while the runs of all classes together may be enough; a
    run is named by class and run there, since run numbers repeat across classes."""
    min_runs, level = stats_of(statistics)
    rows = []
    for (cls, engine, set_), g in evals.groupby(["terrain_class", "engine", "set"], sort=True):
        row = {
            "terrain_class": cls,
            "engine": engine,
            "set": set_,
            "normalised": False,
            **_summary_row(g, g.run, min_runs, level),
        }
        found = best.get((engine, cls), {})  # the calibrate job's best.yaml (a result file, not params)
        row["parameters"] = "; ".join(f"{k}={v:.4g}" for k, v in (found.get("parameters") or {}).items())
        row["parameters_configured"] = "; ".join(f"{k}={v:.4g}" for k, v in (found.get("as_configured") or {}).items())
        rows.append(row)
    if evals.terrain_class.nunique() > 1:
        for (engine, set_), g in _normalised(evals).groupby(["engine", "set"], sort=True):
            # units are unique within a class only: pool under class-qualified names
            g = g.assign(unit=g.terrain_class + "/" + g.unit.astype(str))
            rows.append(
                {
                    "terrain_class": POOLED,
                    "engine": engine,
                    "set": set_,
                    "normalised": True,
                    **_summary_row(g, g.unit.str.rsplit("/", n=1).str[0] + "/" + g.run.astype(str), min_runs, level),
                    "parameters": "",
                    "parameters_configured": "",
                }
            )
    out = pd.DataFrame(rows)
    if out.empty:
        return out
    return _winners(out, evals, min_runs, level)


def summary_job(
    evals: list[str],
    bests: list[str],
    split: str,
    outputs: dict,
    statistics: dict | None = None,
    turning: dict | None = None,
    urdf: str | None = None,
) -> None:
    """Rule calibration_summary: the summary, the units, the parameters found and, with ``turning``
    (the robot's track, the engines, calibration.target), the held-out turning table and the
    target's verdict; the wheels' geometric separation comes from ``urdf``."""
    frame = pd.concat([pd.read_csv(p, dtype={"run": str, "unit": str}) for p in evals], ignore_index=True)
    best = {}
    for path in bests:
        b = yaml.safe_load(Path(path).read_text())
        best[(b["engine"], b["terrain_class"])] = b
    summary = summarise(frame, best, statistics)
    write_csv(summary, outputs["summary"])
    write_csv(frame, outputs["units"])
    params = pd.DataFrame(
        [
            {
                "engine": e,
                "terrain_class": c,
                "parameter": k,
                "calibrated": v,
                "as_configured": b["as_configured"].get(k),
                "best_trial": b["best_trial"],
                "n_trials": b["n_trials"],
                "train_objective_configured": b["configured_objective"],
                "train_objective_calibrated": b["best_objective"],
            }
            for (e, c), b in sorted(best.items())
            for k, v in b["parameters"].items()
        ]
    )
    write_csv(params, outputs["parameters"])
    if "turning" in outputs:
        separation = load_robot(urdf).track  # the controller's wheel_separation (geometric)
        table = turning_table(frame, best, float(turning["track"]), separation, turning["target"], statistics)
        write_csv(table, outputs["turning"])
        write_csv(
            target_table(frame, table, list(turning["engines"]), turning["target"], statistics), outputs["target"]
        )
