"""The paper's quantitative metrics (Farley et al. 2022, section 3.3); the window statistics (Eq. 5-6)
are defined in :mod:`simpick.imustats`, which the real data's segments share.

Eq. 5: per-axis mean. Eq. 6: range, which the paper takes as (mean of the top 1 % of
samples) - (mean of the bottom 1 %), to discount the odd erratic sample. Eq. 7: the IMU
error of a test, summed over axes, |range_sim - range_real| + |mean_sim - mean_real|;
summed over tests for an engine. Eq. 2: real-time factor = total simulated time / total
wall time.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

import pandas as pd

# Eq. 5-6, part of the paper's metrics (metrics.trace_stats for the comparison's callers)
from simpick.imustats import AXES, TRIM_FRACTION, axis_stats, trace_stats, trimmed_range  # noqa: F401


def axis_errors(
    sim: Mapping[str, Mapping[str, float]], real: Mapping[str, Mapping[str, float]]
) -> dict[str, dict[str, float]]:
    """Per-axis Eq. 7 terms of one test; ``sim``/``real`` map axis -> {'range', 'mean'}."""
    if set(sim) != set(real):
        raise ValueError(f"sim axes {sorted(sim)} differ from real axes {sorted(real)}")
    out = {}
    for axis in sim:
        range_error = abs(float(sim[axis]["range"]) - float(real[axis]["range"]))
        mean_error = abs(float(sim[axis]["mean"]) - float(real[axis]["mean"]))
        out[axis] = {"range_error": range_error, "mean_error": mean_error, "total_error": range_error + mean_error}
    return out


def eq7_sum(errors: Iterable[float]) -> float:
    """Eq. 7's one aggregation, wherever its errors are added up: axes into a test, a run's windows
    or tests into the run, tests into an engine's total. Exactly rounded (math.fsum), so the order
    of the rows cannot change a total."""
    return math.fsum(float(e) for e in errors)


def eq7_per_run(rows: pd.DataFrame, keys: list[str], quantities: Iterable[str] = ("angular", "linear")) -> pd.DataFrame:
    """Eq. 7 per run (``keys``: e.g. engine, terrain class, run): the ``error_<quantity>`` of its
    rows (windows, segments, tests) summed with :func:`eq7_sum`; one row per run, columns ``keys``
    and the summed errors."""
    cols = [f"error_{q}" for q in quantities]
    if rows.empty:
        return pd.DataFrame(columns=[*keys, *cols])
    return rows.groupby(keys)[cols].agg(eq7_sum).reset_index()


def test_error(sim: Mapping[str, Mapping[str, float]], real: Mapping[str, Mapping[str, float]]) -> float:
    """Eq. 7 for one test and one quantity: the sum of the per-axis errors."""
    return eq7_sum(e["total_error"] for e in axis_errors(sim, real).values())


def real_time_factor(sim_times: Iterable[float], wall_times: Iterable[float]) -> float:
    """Eq. 2: sum of simulated time over sum of wall time, over all tests."""
    sim, wall = math.fsum(sim_times), math.fsum(wall_times)
    if wall <= 0:
        raise ValueError("real_time_factor needs a positive total wall time")
    return sim / wall


UNITS = {"angular": "rad/s", "linear": "m/s^2"}


def eq7_totals(per_test: pd.DataFrame, engines: Iterable[str] | None = None) -> pd.DataFrame:
    """Eq. 7 per engine and quantity, summed over tests (columns engine, test, status,
    error_angular, error_linear; one row per engine and test).

    An engine that failed a test would look better for missing its error, so the totals
    cover only the tests every engine completed, and name the others as excluded.
    """
    engines = sorted(set(per_test.engine) if engines is None else engines)
    ok = per_test[per_test.status == "ok"]
    tested = [e for e in engines if (per_test.engine == e).any()]
    common = set.intersection(*(set(ok[ok.engine == e].test) for e in tested)) if tested else set()
    excluded = ";".join(sorted(set(per_test.test) - common))
    tests = sorted(common)
    rows = []
    for engine in engines:
        good = ok[(ok.engine == engine) & ok.test.isin(common)]
        for quantity, unit in UNITS.items():
            rows.append(
                {
                    "engine": engine,
                    "quantity": quantity,
                    "error": eq7_sum(good[f"error_{quantity}"]) if tests else float("nan"),
                    "unit": unit,
                    "n_tests": len(tests),
                    "tests": ";".join(tests),
                    "excluded": excluded,
                }
            )
    return pd.DataFrame(rows, columns=["engine", "quantity", "error", "unit", "n_tests", "tests", "excluded"])
