"""Scoring rules of Farley, Wang & Marshall (2022), section 3.2 to section 4.

Everything here is a pure function: facts or measured figures in, scores out.
Scores lie in [0, 1], higher is better, and are combined with weights into a
total (paper section 4, Table 11).

Qualitative scores use the paper's printed fractions 0.667 and 0.333 rather
than 2/3 and 1/3, because Table 4 prints those and Gazebo's Table 11 total
(49.087) needs 0.667 (2/3 gives 49.086). The paper is not consistent here:
MORSE's printed scores times the weights give 32.145, while Table 11 prints
32.148, which is what exact 1/3 for its languages and UI scores would give.
No single convention reproduces all four printed totals.

Quantitative scores are ratios to the best subject:

* real-time factor: ``R_i / max_j R_j``. The paper prints Eq. 3 as
  ``min_j R_j / R_i``, but Table 11 is ``R / max`` (0.973 / 1.064 = 0.914);
  we follow the table, since a higher real-time factor is the better one.
* CPU efficiency (Eq. 4): ``min_j L_j / L_i``.
* IMU accuracy (Eq. 8): ``min_j E_j / E_i``.

Conventions shared by the three ratio scores (see ``_ratio_scores``):

* NaN or ``None`` means "not measured": that subject is left out of the
  min/max and gets a NaN score; :func:`weighted_table` then counts it as 0 and
  lists it in the ``excluded`` column.
* Negative or infinite inputs raise ``ValueError``.
* If every measured value is 0, all measured subjects score 1 (they tie).
* For the "smaller is better" scores, a 0 among positive values scores 1 and
  every positive value scores 0 (min/L with min = 0). For the real-time
  factor, a 0 among positive values scores 0.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import pandas as pd

METRICS: tuple[str, ...] = (
    "free",
    "open_source",
    "ros",
    "languages",
    "ui",
    "model_formats",
    "physics_engines",
    "real_time_factor",
    "cpu_average",
    "cpu_intense",
    "imu_angular",
    "imu_linear",
)

QUALITATIVE_METRICS: tuple[str, ...] = METRICS[:7]
QUANTITATIVE_METRICS: tuple[str, ...] = METRICS[7:]

METRIC_LABELS: dict[str, str] = {
    "free": "Free to use",
    "open_source": "Open source",
    "ros": "ROS integration",
    "languages": "Programming languages",
    "ui": "UI functionality",
    "model_formats": "Model format support",
    "physics_engines": "Physics engine support",
    "real_time_factor": "Real-time factor",
    "cpu_average": "Average-load CPU efficiency",
    "cpu_intense": "Intense-load CPU efficiency",
    "imu_angular": "IMU angular velocity accuracy",
    "imu_linear": "IMU linear acceleration accuracy",
}

# Paper section 4 / Table 11; they sum to 56.
DEFAULT_WEIGHTS: dict[str, float] = {
    "free": 4.0,
    "open_source": 2.0,
    "ros": 6.0,
    "languages": 3.0,
    "ui": 6.0,
    "model_formats": 4.0,
    "physics_engines": 3.0,
    "real_time_factor": 4.0,
    "cpu_average": 2.0,
    "cpu_intense": 2.0,
    "imu_angular": 10.0,
    "imu_linear": 10.0,
}

# The paper's rounded fractions (Table 4).
TWO_THIRDS = 0.667
ONE_THIRD = 0.333

ROS_SCORES: dict[str, float] = {"out_of_the_box": 1.0, "official_plugin": 0.8, "none": 0.0}
UI_SCORES: dict[str, float] = {
    "full": 1.0,
    "partial": TWO_THIRDS,
    "visualization": ONE_THIRD,
    "none": 0.0,
}


# --------------------------------------------------------------------------
# Qualitative rules (paper section 3.2)
# --------------------------------------------------------------------------


def score_bool(value: bool) -> float:
    """Free to use / open source: 1 if true, else 0."""
    if not isinstance(value, bool):
        raise ValueError(f"expected a boolean, got {value!r}")
    return 1.0 if value else 0.0


def score_ros(support: str) -> float:
    """ROS integration: ``out_of_the_box`` 1, ``official_plugin`` 0.8, ``none`` 0.

    ``official_plugin`` is an official plugin that has to be installed or
    enabled by hand (Table 3: "A built-in plugin provided").
    """
    try:
        return ROS_SCORES[support]
    except KeyError:
        raise ValueError(f"ROS support must be one of {sorted(ROS_SCORES)}, got {support!r}") from None


def _norm(names: Iterable[str]) -> set[str]:
    if isinstance(names, str):
        raise ValueError(f"expected a list of names, got the string {names!r}")
    return {str(n).strip().lower() for n in names}


_C_FAMILY = {"c/c++", "c", "c++"}


def score_languages(languages: Iterable[str]) -> float:
    """Programming languages score.

    How the rule is read (case-insensitive names):

    * "C/C++" is met by any of ``C/C++``, ``C`` or ``C++``.
    * 1 if C/C++, Python and MATLAB are all supported **and** at least one
      further language (anything other than C, C++, Python, MATLAB) is: the
      "and more" is taken as a condition. A simulator with exactly C/C++,
      Python and MATLAB therefore scores 0.667. Table 3 cannot tell this
      reading from "at least these three": both simulators that score 1
      (CoppeliaSim, Webots) also list Java.
    * 0.667 if C/C++ and Python (without the above).
    * 0.333 if C/C++ or Python.
    * 0 otherwise (e.g. only Lua, or only MATLAB).
    """
    langs = _norm(languages)
    has_c = bool(langs & _C_FAMILY)
    has_py = "python" in langs
    has_matlab = "matlab" in langs
    others = langs - _C_FAMILY - {"python", "matlab"}
    if has_c and has_py and has_matlab and others:
        return 1.0
    if has_c and has_py:
        return TWO_THIRDS
    if has_c or has_py:
        return ONE_THIRD
    return 0.0


def score_ui(level: str) -> float:
    """UI functionality: ``full`` 1, ``partial`` 0.667, ``visualization`` 0.333, ``none`` 0.

    "Full" means start, stop and step the simulation, see the scene, and add
    models at any time; ``partial`` is a subset of those controls.
    """
    try:
        return UI_SCORES[level]
    except KeyError:
        raise ValueError(f"UI level must be one of {sorted(UI_SCORES)}, got {level!r}") from None


def score_model_formats(formats: Iterable[str], urdf_sdf_via_manual_plugin: bool = False) -> float:
    """Model format support score (case-insensitive names).

    * 1 if URDF and SDF are both native and at least one other format is
      ("and more" read as a condition, as for languages; URDF + SDF alone
      scores 0.5).
    * 0.5 if URDF or SDF is native.
    * 0.25 if neither is native but URDF or SDF can be loaded through a
      plugin installed by hand (``urdf_sdf_via_manual_plugin``).
    * 0 otherwise.
    """
    fmts = _norm(formats)
    has_urdf = "urdf" in fmts
    has_sdf = "sdf" in fmts
    if has_urdf and has_sdf and (fmts - {"urdf", "sdf"}):
        return 1.0
    if has_urdf or has_sdf:
        return 0.5
    if urdf_sdf_via_manual_plugin:
        return 0.25
    return 0.0


def score_physics_engines(engines: Iterable[str]) -> float:
    """Physics engine support: 1 if more than one distinct engine, else 0."""
    return 1.0 if len(_norm(engines)) > 1 else 0.0


FACT_KEYS: tuple[str, ...] = (
    "free",
    "open_source",
    "ros",
    "languages",
    "ui",
    "model_formats",
    "urdf_sdf_via_manual_plugin",
    "physics_engines",
)


def qualitative_scores(facts: Mapping[str, Any]) -> dict[str, float]:
    """The seven qualitative scores of one subject from its fact record.

    ``facts`` must hold (other keys, e.g. ``printed`` or ``note``, are ignored)::

        free: bool
        open_source: bool
        ros: out_of_the_box | official_plugin | none
        languages: [str, ...]
        ui: full | partial | visualization | none
        model_formats: [str, ...]
        urdf_sdf_via_manual_plugin: bool
        physics_engines: [str, ...]
    """
    missing = [k for k in FACT_KEYS if k not in facts]
    if missing:
        raise ValueError(f"fact record lacks {', '.join(missing)}")
    plugin = facts["urdf_sdf_via_manual_plugin"]
    if not isinstance(plugin, bool):
        raise ValueError(f"urdf_sdf_via_manual_plugin must be a boolean, got {plugin!r}")
    return {
        "free": score_bool(facts["free"]),
        "open_source": score_bool(facts["open_source"]),
        "ros": score_ros(facts["ros"]),
        "languages": score_languages(facts["languages"]),
        "ui": score_ui(facts["ui"]),
        "model_formats": score_model_formats(facts["model_formats"], plugin),
        "physics_engines": score_physics_engines(facts["physics_engines"]),
    }


# --------------------------------------------------------------------------
# Quantitative scores (paper section 3.3)
# --------------------------------------------------------------------------


def _clean(values: Mapping[str, float | None], what: str) -> dict[str, float]:
    """Values as floats (None -> NaN), rejecting negatives and infinities."""
    out: dict[str, float] = {}
    for key, v in values.items():
        x = math.nan if v is None else float(v)
        if math.isinf(x):
            raise ValueError(f"{what} for {key!r} is infinite; use NaN to leave it out")
        if x < 0:
            raise ValueError(f"{what} for {key!r} is negative ({x}); it must be >= 0")
        out[key] = x
    return out


def _ratio_scores(values: Mapping[str, float | None], what: str, higher_is_better: bool) -> dict[str, float]:
    vals = _clean(values, what)
    measured = [v for v in vals.values() if not math.isnan(v)]
    if not measured:
        return {k: math.nan for k in vals}
    best = max(measured) if higher_is_better else min(measured)
    scores: dict[str, float] = {}
    for key, v in vals.items():
        if math.isnan(v):
            scores[key] = math.nan
        elif higher_is_better:
            # best == 0 means every measured value is 0: a tie.
            scores[key] = 1.0 if best == 0 else v / best
        elif v == 0:
            scores[key] = 1.0  # equal to the minimum (0), also when all are 0
        else:
            scores[key] = best / v
    return scores


def real_time_factor_scores(rtf: Mapping[str, float | None]) -> dict[str, float]:
    """Real-time factor score ``R_i / max_j R_j`` (higher is better).

    This is what Table 11 contains (e.g. CoppeliaSim 0.973 / 1.064 = 0.914),
    not Eq. 3 as printed (``min_j R_j / R_i``, which would rank the slowest
    simulator first). NaN/None entries are left out and score NaN; all zeros
    score 1; negative or infinite values raise ``ValueError``.
    """
    return _ratio_scores(rtf, "real-time factor", higher_is_better=True)


def efficiency_scores(load: Mapping[str, float | None]) -> dict[str, float]:
    """CPU efficiency score ``min_j L_j / L_i`` (Eq. 4); ``L`` is CPU load.

    NaN/None entries are left out and score NaN; a load of 0 scores 1 and then
    every positive load scores 0; negative or infinite loads raise
    ``ValueError``.
    """
    return _ratio_scores(load, "CPU load", higher_is_better=False)


def accuracy_scores(errors: Mapping[str, float | None]) -> dict[str, float]:
    """IMU accuracy score ``min_j E_j / E_i`` (Eq. 8); ``E`` is the Eq. 7 error.

    NaN/None entries are left out and score NaN; an error of 0 scores 1 and
    then every positive error scores 0; all errors 0 score 1; negative or
    infinite errors raise ``ValueError``.
    """
    return _ratio_scores(errors, "IMU error", higher_is_better=False)


# --------------------------------------------------------------------------
# Weighted total (paper section 4, Table 11)
# --------------------------------------------------------------------------


def weighted_table(scores: pd.DataFrame, weights: Mapping[str, float]) -> pd.DataFrame:
    """Weighted totals and ranking.

    ``scores`` has one row per subject and one column per key of
    :data:`METRICS` (extra columns are kept untouched). Returns a copy with

    * ``total``: sum over METRICS of ``weights[m] * score``, a NaN score
      counting as 0;
    * ``excluded``: comma-separated metric keys whose score was NaN in that
      row ("" if none), so a NaN never passes silently as a 0;
    * ``rank``: 1 = highest total; equal totals share the better rank.

    Rows are sorted by total, descending (stable for ties). A metric missing
    from ``scores`` or ``weights``, or a non-finite weight, raises
    ``ValueError`` naming the key.
    """
    for key in METRICS:
        if key not in scores.columns:
            raise ValueError(f"scores lack the metric column {key!r}")
        if key not in weights:
            raise ValueError(f"weights lack the metric {key!r}")
        if not math.isfinite(float(weights[key])):
            raise ValueError(f"weight for {key!r} is not finite: {weights[key]!r}")

    out = scores.copy()
    metric_scores = out[list(METRICS)].astype(float)
    w = pd.Series({k: float(weights[k]) for k in METRICS})
    out["total"] = metric_scores.fillna(0.0).mul(w, axis=1).sum(axis=1)
    nan_mask = metric_scores.isna()
    out["excluded"] = [",".join(k for k in METRICS if row[k]) for _, row in nan_mask.iterrows()]
    out = out.sort_values("total", ascending=False, kind="mergesort")
    out["rank"] = out["total"].rank(method="min", ascending=False).astype(int)
    return out
