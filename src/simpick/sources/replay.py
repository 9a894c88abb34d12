"""The replay source: every run of a dataset folder (BorealTC layout; simpick.real.datasets), imported to
the canonical form (rules/real.smk), driven by its recorded wheel speeds and compared with the
real log window by window (simpick.compare.real.replay_compare)."""

from __future__ import annotations

from simpick.sources.base import canonical, log_path, real_params, unit_params

KIND = DRIVEN = "replay"
GROUP = "terrain_class"
MEM_MB = 800  # a whole run's trace and log in memory


# --- planning ---

def cases(dataset) -> list[tuple[str, str]]:
    """(terrain class, run) of every run of an opened dataset folder (simpick.real.datasets)."""
    return [(r.terrain_class, r.run) for r in dataset.runs]


def case_inputs(config: dict, source: str, spec: dict, group: str, names: list[str]) -> dict:
    (name,) = names  # a replay is never batched: one log per job
    return {"urdf": config["robot"]["urdf"], "log": log_path(source, group, name)}


def case_params(config: dict, source: str, spec: dict, engine: str, group: str, names: list[str]) -> dict:
    return unit_params(real_params(config, engine, group), DRIVEN, source, names)


def compare_inputs(config: dict, source: str, spec: dict, cases: list[tuple[str, str]]) -> dict:
    return {"logs": [log_path(source, c, run) for c, run in cases]}


def compare_settings(config: dict) -> dict:
    return canonical({"track": config["robot"]["track"], "window": config["real_data"]["window"]})


# --- jobs ---

def read_log(path: str):
    """A canonical log (simpick.real.logs.read_canonical): what a replayed case is driven by."""
    from simpick.real.logs import read_canonical

    return read_canonical(path)


def simulate(log, urdf: str, params: dict, duration: float | None = None):
    """One run driven by its recorded wheel speeds on ``params["engine"]``, the first ``duration``
    seconds (all of it when None): simpick.simulate.real.replay_log. The calibration replays through here."""
    from simpick.simulate.real import replay_log
    return replay_log(log, urdf, params, duration=duration)


def prepare_case(urdf: str, inputs: dict, params: dict, name: str):
    """A replayed run (a dataset folder's or an own log) driven by its recorded wheel speeds."""
    log = read_log(inputs["log"])
    run = str(log.meta["run_id"])
    which = {"terrain": params["terrain_class"], "motion": f"replay-{run}", "test": f"{params['terrain_class']}-{run}",
             "dataset": log.meta.get("dataset"), "run": run}
    return which, lambda: simulate(log, urdf, params)


def compare(traces: list[str], inputs: dict, params: dict):
    """Every replayed run against its real log, window by window (simpick.compare.real.replay_compare)."""
    from simpick.compare.real import replay_compare
    return replay_compare(list(inputs["logs"]), traces, params)
