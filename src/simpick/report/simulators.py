"""The report's simulator section: each simulator as shipped and as tuned (results/simulators/table.csv), the
paper's weighted table with simulators as rows (weighted.csv), the files to paste (settings/), and the decision
tree's ROS 2 paths in words (tree.json). Read from the folder the rule names (params ``simulators``)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pandas as pd

from simpick.score.profiles import _text, spread_count
from simpick.score.tree import read_tree

OUTCOME_WORDS = {
    "best": "best",
    "equivalent": "equivalent to the best",
    "worse": "worse than the best",
    "undetermined": "undetermined",
    "not measurable": "not measurable",
    "too few runs": "too few runs",
}


def _text_or_dash(x) -> str:
    """A table's text cell, or a dash where it is empty."""
    return str(x) if isinstance(x, str) and x else "–"


def _f(x, digits: int = 3) -> str:
    try:
        x = float(x)
    except (TypeError, ValueError):
        return "–"
    return "–" if not math.isfinite(x) else f"{x:.{digits}f}"


def _judged(judged: int, available) -> str:
    """The held-out units a class's fits are judged on, "n of m" where the class holds out more (DRIVE's steps)."""
    try:
        available = int(available)
    except (TypeError, ValueError):
        return str(judged)
    return f"{judged} of {available}" if available > judged else str(judged)


def _with_interval(row: dict, column: str) -> str:
    """A per-class held-out error with its 95 % interval where the class had enough held-out runs for one."""
    low, high = _f(row.get(f"{column}_low")), _f(row.get(f"{column}_high"))
    interval = f" [{low}, {high}]" if "–" not in (low, high) else ""
    return f"{_f(row.get(column))}{interval}"


DEMANDING = ("closeness", "mechanics")  # the questions answered with their most demanding answer


def leaf_for(tree: dict, fixed: dict[str, str]) -> dict:
    """The leaf reached with ``fixed`` answers, the most demanding answer to closeness and mechanics, and
    "no need" (the last answer) to every other question."""
    node = tree["nodes"][tree["root"]]
    while node["kind"] == "question":
        labels = [a["label"] for a in node["answers"]]
        q = node["question"]
        label = fixed.get(q) if fixed.get(q) in labels else (labels[0] if q in DEMANDING else labels[-1])
        node = tree["nodes"][next(a for a in node["answers"] if a["label"] == label)["next"]]
    return node


def ros_paths(tree: dict, labels: dict[str, str]) -> list[dict[str, str]]:
    """Each ROS 2 answer of the tree and the simulators its most demanding path on physics leaves."""
    answers = []
    for node in tree["nodes"].values():
        if node.get("question") == "ros":
            answers += [a["label"] for a in node["answers"] if a["label"] not in answers]
    out = []
    for label in answers:
        leaf = leaf_for(tree, {"ros": label})
        names = [labels.get(e, e) for e in leaf.get("engines", [])]
        # the profile each simulator's leaf names (simpick.score.profiles.name_profiles), where the tree has them
        profiles = leaf.get("profiles") or []
        out.append(
            {
                "answer": label,
                "leaf": "; ".join(p["text"] for p in profiles) if profiles else (", ".join(names) or "none"),
                "closest": [p["closest"] for p in profiles if p.get("closest")],
            }
        )
    return out


def _model_link(path) -> str:
    """The report's link to a model that opens as it is (the table's ``model_file``; empty where none)."""
    return f"../simulators/models/{Path(str(path)).name}" if isinstance(path, str) and path else ""


def _model_note(note) -> str:
    """The words beside a model's link (the table's ``model_note``: empty where the simulator's own loader opens it
    in the tests, "fields checked; not opened in <simulator> here" where none installs)."""
    return note if isinstance(note, str) else ""


def simulators_section(folder: str, weights: dict[str, float]) -> dict[str, Any] | None:
    folder_path = Path(folder)
    table_path = folder_path / "table.csv"
    if not table_path.is_file():
        return None
    table = pd.read_csv(table_path)
    labels = dict(zip(table.simulator, table.label))
    rows = []
    for r in table.to_dict("records"):
        ran = str(r.get("status", "")).startswith("run")
        settings = (
            sorted(p.name for p in (folder_path / "settings").glob(f"{r['simulator']}-{r['variant']}.*")) if ran else []
        )
        rows.append(
            {
                "simulator": r["simulator"],
                "label": r["label"],
                "variant": r["variant"],
                "engine": "" if pd.isna(r.get("engine")) else r["engine"],
                "ran": ran,
                "status": r.get("status", ""),
                "mechanics": r.get("mechanics") if ran else "",
                "mechanics_text": (
                    f"{int(r['mechanics_cases'] - r['mechanics_failed'])} of {int(r['mechanics_cases'])}"
                    if ran and pd.notna(r.get("mechanics_cases"))
                    else "–"
                ),
                "gain_flat": _f(r.get("gain_flat")),
                "gain_range": f"{_f(r.get('gain_flat_min'))}-{_f(r.get('gain_flat_max'))}" if ran else "",
                "gain_coulomb": _f(r.get("gain_coulomb")),
                "gain_error": _f(r.get("gain_error")),
                "gain_interval": f"[{_f(r.get('gain_error_low'))}, {_f(r.get('gain_error_high'))}]" if ran else "",
                "gain_outcome": OUTCOME_WORDS.get(str(r.get("gain_outcome")), "") if ran else "",
                "gain_diff": _f(r.get("gain_diff_to_best")),
                "heading_error": _f(r.get("heading_error")),
                "heading_outcome": OUTCOME_WORDS.get(str(r.get("heading_outcome")), "") if ran else "",
                "runs_failed": int(r["runs_failed"]) if ran and pd.notna(r.get("runs_failed")) else 0,
                # on the real runs no profile was fitted on (tables with calibrated profiles)
                "heldout_error": _f(r.get("heldout_gain_error")),
                "heldout_interval": (
                    f"[{_f(r.get('heldout_gain_error_low'))}, {_f(r.get('heldout_gain_error_high'))}]"
                    if ran and "heldout_gain_error" in r
                    else ""
                ),
                "mechanics_own": str(r.get("mechanics_own") or "") if r["variant"] == "calibrated" and ran else "",
                # the same error on the runs the calibration fitted on: a fit must fall below the tuned row's here
                "train_error": _f(r.get("train_gain_error")),
                "fitted": _text(r.get("fitted_parameters")) if r["variant"] == "calibrated" and ran else "",
                "parts": _text(r.get("fit_parts")) if r["variant"] == "calibrated" and ran else "",
                "settings": [f"../simulators/settings/{name}" for name in settings],
                "model": _model_link(r.get("model_file")) if ran else "",
                "model_note": _model_note(r.get("model_note")) if ran else "",
            }
        )
    weighted = []
    wpath = folder_path / "weighted.csv"
    if wpath.is_file():
        w = pd.read_csv(wpath)
        for r in w.sort_values("total", ascending=False).to_dict("records"):
            weighted.append(
                {
                    "simulator": r["engine"],
                    "label": labels.get(r["engine"], r["engine"]),
                    "total": _f(r["total"], 2),
                    "rank": int(r["rank"]) if "rank" in r else None,
                }
            )
    per_class = []
    if (folder_path / "per_class.csv").is_file():
        for r in pd.read_csv(folder_path / "per_class.csv").to_dict("records"):
            held = int(r["heldout_runs"]) if pd.notna(r.get("heldout_runs")) else 0
            stem = Path(str(r["settings_file"])).name if pd.notna(r.get("settings_file")) else ""
            files = sorted(p.name for p in (folder_path / "settings").glob(f"{stem}.*")) if stem else []
            per_class.append(
                {
                    "label": r["label"],
                    "terrain_class": r["terrain_class"],
                    # the training units the class's fit replayed, of how many the class has where fewer (DRIVE)
                    "train_runs": _judged(
                        int(r["train_fitted"]) if pd.notna(r.get("train_fitted")) else int(r.get("train_runs") or 0),
                        r.get("train_runs"),
                    ),
                    "real_gain": _f(r.get("real_gain")),
                    "class_settings": _text_or_dash(r.get("class_settings")),
                    "pooled_settings": _text_or_dash(r.get("pooled_settings")),
                    "engine_gain": _f(r.get("engine_gain")),
                    # the units judged, and of how many the class holds out where the fit judges fewer (DRIVE)
                    "heldout_runs": _judged(held, r.get("heldout_available")),
                    "spread": _f(r.get("class_spread")),
                    "spread_runs": spread_count(r),
                    "train_tuned": _f(r.get("tuned_train_error")),
                    "train_pooled": _f(r.get("pooled_train_error")),
                    "train_class": _f(r.get("class_train_error")),
                    "class_error": _with_interval(r, "class_fit_error") if held else "–",
                    "pooled_error": _with_interval(r, "pooled_fit_error") if held else "–",
                    "settings": [f"../simulators/settings/{name}" for name in files],
                    "model": _model_link(r.get("model_file")),
                    "model_note": _model_note(r.get("model_note")),
                }
            )
    tree = read_tree(str(folder_path / "tree.json")) if (folder_path / "tree.json").is_file() else None
    return {
        "rows": rows,
        "per_class": per_class,
        "variants": sorted(set(table.variant.astype(str))),
        "heldout": "heldout_gain_error" in table.columns and table.heldout_gain_error.notna().any(),
        "weighted": weighted,
        "ros_paths": ros_paths(tree, labels) if tree else [],
        "not_run": sorted({r["label"]: r["status"] for r in rows if not r["ran"]}.items()),
        "weights_total": sum(weights.values()),
        "coulomb": _f(table.gain_coulomb.dropna().iloc[0]) if table.gain_coulomb.notna().any() else "–",
    }
