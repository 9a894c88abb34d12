"""results/simulators/per_class.csv (rule simulators): per simulator and terrain class, the class's own calibrated
fit beside the pooled one, both judged on the class's held-out runs, with the class's spread and each fit's training
error; the calibration files (simpick.studies.simulator_calibration) hold the figures, this module lays them out."""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd

from simpick.engines.simulators import model_name
from simpick.score.simulator_settings import class_files, class_settings, settings_text


def per_class_table(
    fits: dict[str, dict],
    catalog,
    model_files: dict[str, str] | None = None,
    model_notes: dict[str, str] | None = None,
) -> pd.DataFrame:
    """results/simulators/per_class.csv: per simulator and terrain class, the class's own fit beside the pooled
    one, both judged on the class's held-out runs (as the held-out table replays them); ``model_files``: profile
    -> its model's path, beside which a class with a file of its own has its model (rule simulator_models), and
    ``model_notes`` what the report says beside it (SimulatorsParams.model_notes)."""
    rows = []
    for simulator, fit in fits.items():
        pooled = settings_text(fit.get("settings") or {})
        files = class_files(fit)
        model = (model_files or {}).get(model_name(simulator, "calibrated"))
        note = (model_notes or {}).get(model_name(simulator, "calibrated"), "")
        for cls, e in (fit.get("per_class") or {}).items():
            held = e.get("heldout") or {}
            rows.append(
                {
                    "simulator": simulator,
                    "label": catalog.simulators[simulator].label if simulator in catalog.simulators else simulator,
                    "terrain_class": cls,
                    "train_runs": len(e.get("runs") or []),
                    # of them, the ones its own fit replayed (DRIVE: a few representative steps); none without a fit
                    "train_fitted": e.get("fitted_runs", len(e.get("runs") or [])),
                    "real_gain": e.get("real_gain"),
                    "pooled_settings": pooled,
                    "class_settings": settings_text(class_settings(e)),
                    "placed_by": e.get("placed_by"),
                    "engine_gain": e.get("engine_gain"),
                    "pooled_engine_gain": e.get("pooled_engine_gain"),
                    "reached": e.get("reached"),
                    "class_spread": e.get("class_spread"),
                    "spread_runs": e.get("spread_runs"),
                    # how the spread was taken: over its runs' gains, or (DRIVE) over pairs of similar steps
                    "spread_basis": e.get("spread_basis") or "standard deviation of its runs' real gains",
                    "tuned_train_error": e.get("tuned_train_error"),
                    "pooled_train_error": e.get("pooled_train_error"),
                    "class_train_error": e.get("train_error"),
                    "heldout_runs": held.get("runs", 0),
                    "heldout_available": held.get("available", held.get("runs", 0)),
                    "heldout_real_gain": held.get("real_gain"),
                    "class_fit_error": held.get("class_fit_error"),
                    "class_fit_error_low": _end(held.get("class_fit_error_interval"), 0),
                    "class_fit_error_high": _end(held.get("class_fit_error_interval"), 1),
                    "pooled_fit_error": held.get("pooled_fit_error"),
                    "pooled_fit_error_low": _end(held.get("pooled_fit_error_interval"), 0),
                    "pooled_fit_error_high": _end(held.get("pooled_fit_error_interval"), 1),
                    "settings_file": f"results/simulators/settings/{model_name(simulator, 'calibrated')}-{cls}"
                    if cls in files
                    else "",
                    "model_file": _class_model(model, cls) if cls in files and model else "",
                    "model_note": note if cls in files and model else "",
                }
            )
    return pd.DataFrame(rows, columns=PER_CLASS_COLUMNS)


def _end(interval, i: int) -> float:
    """One end of a fit's interval (NaN where the class had too few held-out runs for one)."""
    return float(interval[i]) if interval and interval[i] is not None else math.nan


def _class_model(model: str, cls: str) -> str:
    """The path of a terrain class's model beside its calibrated profile's (``<profile>-<class>``)."""
    path = Path(model)
    return str(path.with_name(f"{path.stem}-{cls}{path.suffix}"))


PER_CLASS_COLUMNS = [
    "simulator",
    "label",
    "terrain_class",
    "train_runs",
    "train_fitted",
    "real_gain",
    "pooled_settings",
    "class_settings",
    "placed_by",
    "engine_gain",
    "pooled_engine_gain",
    "reached",
    "class_spread",
    "spread_runs",
    "spread_basis",
    "tuned_train_error",
    "pooled_train_error",
    "class_train_error",
    "heldout_runs",
    "heldout_available",
    "heldout_real_gain",
    "class_fit_error",
    "class_fit_error_low",
    "class_fit_error_high",
    "pooled_fit_error",
    "pooled_fit_error_low",
    "pooled_fit_error_high",
    "settings_file",
    "model_file",
    "model_note",
]
