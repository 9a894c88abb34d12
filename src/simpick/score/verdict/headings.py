"""Whether an engine's turning depends on the robot's heading: each model's yaw-rate gain on every
turning test against a heading-independent reference model's, with the test's seeded start heading.

A diagnostic of one engine artefact (a gain with a period in the heading), kept apart from the
metrics that rank engines."""

from __future__ import annotations

import numpy as np
import pandas as pd

HEADING_COLUMNS = [
    "model",
    "test",
    "terrain_class",
    "run",
    "start_heading_deg",
    "yaw_rate_gain_sim",
    "yaw_rate_gain_reference",
    "gain_ratio",
]
HEADING_REFERENCE = "coulomb"  # heading-independent by construction: the same command's gain on any heading


def heading_spread(per_test: pd.DataFrame, reference: str = HEADING_REFERENCE) -> pd.DataFrame:
    """Each model's yaw-rate gain on every turning test against the reference model's gain on the
    same test (``gain_ratio``), with the test's seeded start heading: on flat isotropic ground the
    ratio should not depend on the heading, so its spread over the tests' headings shows an engine
    whose turning does (PyBullet: 90-degree period). Empty without the reference model."""
    need = {"yaw_rate_gain_sim", "start_heading_deg", "engine", "test"}
    if not need <= set(per_test.columns) or reference not in set(per_test.engine):
        return pd.DataFrame(columns=HEADING_COLUMNS)
    ok = per_test[(per_test.status == "ok") & np.isfinite(pd.to_numeric(per_test.yaw_rate_gain_sim, errors="coerce"))]
    ref = ok[ok.engine == reference].set_index("test").yaw_rate_gain_sim.astype(float)
    rows = []
    for r in ok[ok.engine != reference].to_dict("records"):
        g_ref = ref.get(r["test"], float("nan"))
        rows.append(
            {
                "model": r["engine"],
                "test": r["test"],
                "terrain_class": r.get("terrain_class"),
                "run": r.get("run"),
                "start_heading_deg": float(r["start_heading_deg"]),
                "yaw_rate_gain_sim": float(r["yaw_rate_gain_sim"]),
                "yaw_rate_gain_reference": g_ref,
                "gain_ratio": float(r["yaw_rate_gain_sim"]) / g_ref if g_ref else float("nan"),
            }
        )
    return pd.DataFrame(rows, columns=HEADING_COLUMNS)
