"""The rows every comparison writes, whatever its source: a trace's run (timing, health, versions)
and its per-axis statistics against the reference's (Eq. 7 terms).
"""

from __future__ import annotations

from simpick.compare import metrics

RUN_COLUMNS = [
    "engine",
    "terrain",
    "motion",
    "test",
    "sim_time",
    "wall_time",
    "cpu_time",
    "steps",
    "steps_per_s",
    "real_time_factor",
    "status",
    "reasons",
    "engine_version",
    "config_hash",
]


def run_row(meta: dict) -> dict:
    """What a trace's metadata says about its run: timing, health, versions (any source; a field
    a hand-made trace lacks is left empty)."""
    health, nan = meta["health"], float("nan")
    steps, wall = meta.get("steps", nan), meta.get("wall_time", nan)
    return {
        "engine": meta["engine"],
        "terrain": meta.get("terrain"),
        "motion": meta.get("motion"),
        "test": case_test(meta),
        "sim_time": meta.get("sim_time", nan),
        "wall_time": wall,
        "cpu_time": meta.get("cpu_time", nan),
        "steps": steps,
        "steps_per_s": steps / wall if wall else nan,
        "real_time_factor": meta.get("real_time_factor"),
        "status": health["status"],
        "reasons": "; ".join(health["reasons"]),
        "engine_version": meta.get("engine_version", ""),
        "config_hash": meta.get("config_hash", ""),
    }


def case_test(meta: dict) -> str:
    """The test a trace is of (TRACE_KEYS' ``test``; for a trace without it, its segment or terrain/motion)."""
    return meta.get("test") or meta.get("segment") or f"{meta.get('terrain')}/{meta.get('motion')}"


def axis_rows(meta: dict, stats: dict | None, reference: dict | None) -> list[dict]:
    """Per quantity and axis: the simulated mean and range (``stats``, None for a failed run), the
    reference's (None where the test has none) and the Eq. 7 axis errors between them."""
    nan = float("nan")
    rows = []
    for quantity in ("angular", "linear"):
        errors = (
            metrics.axis_errors(stats[quantity], reference[quantity])
            if stats is not None and reference is not None
            else {}
        )
        for axis in metrics.AXES:
            sim = stats[quantity][axis] if stats is not None else {"mean": nan, "range": nan}
            ref = reference[quantity][axis] if reference is not None else {"mean": nan, "range": nan}
            e = errors.get(axis) or {"range_error": nan, "mean_error": nan, "total_error": nan}
            rows.append(
                {
                    "engine": meta["engine"],
                    "terrain": meta.get("terrain"),
                    "motion": meta.get("motion"),
                    "test": case_test(meta),
                    "quantity": quantity,
                    "axis": axis,
                    "mean": sim["mean"],
                    "range": sim["range"],
                    "status": meta["health"]["status"],
                    "ref_mean": ref["mean"],
                    "ref_range": ref["range"],
                    "source": (reference or {}).get("source") or "",
                    **e,
                }
            )
    return rows


DETAIL_COLUMNS = [
    "engine",
    "terrain",
    "motion",
    "test",
    "quantity",
    "axis",
    "mean",
    "range",
    "status",
    "ref_mean",
    "ref_range",
    "source",
    "range_error",
    "mean_error",
    "total_error",
]
