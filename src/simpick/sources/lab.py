"""The lab source: the paper's tests (terrain x motion of the config) on generated terrain strips,
compared with the paper's real statistics (Farley et al. 2022, Tables 8-9; simpick.inputs.reference)."""

from __future__ import annotations

from simpick.sources.base import canonical, engine_params, unit_params

KIND = DRIVEN = "lab"
GROUP = "terrain"
MEM_MB = 400


# --- planning ---

def cases(config: dict) -> list[tuple[str, str]]:
    """Every terrain x every motion of the config."""
    return [(t, m) for t in config["terrains"] for m in config["motions"]]


def lab_params(config: dict, engine: str, terrain: str, motion_name: str) -> dict:
    """Everything one lab-study simulation depends on, and nothing else."""
    return engine_params(config, engine) | canonical(
        {
            "terrain": terrain,
            "motion_name": motion_name,
            "motion": config["motions"][motion_name],
        }
    )


def case_inputs(config: dict, source: str, spec: dict, group: str, names: list[str]) -> dict:
    return {"urdf": config["robot"]["urdf"], "terrain": f"results/terrains/{group}.json"}


def case_params(config: dict, source: str, spec: dict, engine: str, group: str, names: list[str]) -> dict:
    (name,) = names  # a lab case is one job
    return unit_params(lab_params(config, engine, group, name), DRIVEN, source, names)


def compare_inputs(config: dict, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"published": config["reference"]["published"]}


def compare_settings(config: dict) -> dict:
    return {}


# --- jobs ---

def prepare_case(urdf: str, inputs: dict, params: dict, name: str):
    """A lab test: the motion's constant command over the generated terrain strip."""
    from simpick.inputs.terrain import load
    from simpick.simulate.run import Case, Recording, run_case, scenario_from

    motion = params["motion"]
    case = Case(engine=params["engine"], terrain=params["terrain"], motion=name,
                v=motion["v"], w=motion["w"], duration=motion["duration"], start=tuple(motion["start"]))
    which = {"terrain": case.terrain, "motion": case.motion, "test": f"{case.terrain}/{case.motion}"}

    def run():
        scenario = scenario_from(params, urdf, load(inputs["terrain"]))
        return run_case(case, scenario, params["robot"]["track"], Recording.from_params(params))

    return which, run


PER_TEST_COLUMNS = ["engine", "terrain", "motion", "test", "run", "kind", "status", "reasons", "error_angular",
                    "error_linear"]


def compare(traces: list[str], inputs: dict, params: dict):
    """The lab tests against the paper's real statistics (simpick.inputs.reference, ``inputs["published"]``):
    per engine, test, quantity and axis (``detail``), and Eq. 7 per test where the paper has a
    reference (``per_test``; a failed run of such a test is a failed row)."""
    import pandas as pd

    from simpick.compare import metrics
    from simpick.inputs.published import load_published
    from simpick.inputs.reference import lab_reference
    from simpick.tables import DETAIL_COLUMNS, RUN_COLUMNS, axis_rows, case_test, run_row
    from simpick.simulate.traces import read_trace

    reference = lab_reference(load_published(inputs["published"]))
    detail, per_test, runs = [], [], []
    for path in traces:
        frame, meta = read_trace(path)
        runs.append(run_row(meta))
        ok = meta["health"]["status"] == "ok"
        ref = reference.get((meta["terrain"], meta["motion"]))
        rows = axis_rows(meta, metrics.trace_stats(frame) if ok else None, ref)
        detail += rows
        if ref is None:
            continue
        test = case_test(meta)
        row = {"engine": meta["engine"], "terrain": meta["terrain"], "motion": meta["motion"], "test": test,
               "run": test, "kind": "lab", "status": meta["health"]["status"],
               "reasons": "; ".join(meta["health"]["reasons"])}
        if ok:
            row.update({f"error_{q}": metrics.eq7_sum(r["total_error"] for r in rows if r["quantity"] == q)
                        for q in ("angular", "linear")})
        per_test.append(row)
    return (pd.DataFrame(per_test, columns=PER_TEST_COLUMNS), pd.DataFrame(detail, columns=DETAIL_COLUMNS),
            pd.DataFrame(runs, columns=RUN_COLUMNS))
