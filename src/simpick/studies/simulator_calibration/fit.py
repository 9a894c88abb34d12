"""The least-squares machinery: the settings as the optimiser sees them (:class:`Axis`), the units a fit is
judged on (:class:`Units`), the bounded fit by scipy or mujoco.sysid (:func:`least_squares_fit`), its
intervals, and the probe of a fitted value's distance from a step of the engine (:func:`step_margins`)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from simpick.studies.simulator_calibration.space import SearchSetting

# a failed replay (the health checks) counts as this gain residual: the fit steers away from it
FAILED_RESIDUAL = 1.0
# a setting whose column of the Jacobian moves the residuals by less than this over its whole range, or that lies
# along a direction whose singular value is below RELATIVE_SINGULAR of the largest, is unidentifiable from the runs
MIN_SENSITIVITY, RELATIVE_SINGULAR = 0.01, 0.01
# a run's gain moving by more than this within one Jacobian step is a jump of the engine's (DART's friction box
# locking, PyBullet's), not a slope: the linearised interval is then no measure of what the runs fix
JUMP = 0.2
# A fitted value this close to a step of the engine's response is no calibration: a setting whose gain jumps within
# 2 % of it (DART's friction box in gz-physics locks the Husky's turn between a <mu2>/<mu> of 0.74 and 0.78) would
# turn differently in the user's simulator for any rounding of the value, another step size or another version.
# Each fitted value is stepped by STEP_MARGIN of itself both ways; a run's gain moving by more than STEP_GAIN there
# (about seven times what the anisotropic Coulomb slope moves it, 0.7 per unit of ratio) is a step.
STEP_MARGIN, STEP_GAIN = 0.02, 0.1
Z95 = 1.959964  # a normal 95 % interval


class Axis:
    """A fitted setting as the optimiser sees it: u in [0, 1] over its bounds (over their logarithms for a log
    setting), so that one Jacobian step and one trust region suit every setting."""

    def __init__(self, name: str, setting: SearchSetting):
        self.name, self.low, self.high, self.log = name, *map(float, setting.bounds), bool(setting.log)

    def to_u(self, x: float) -> float:
        if self.log:
            return math.log(x / self.low) / math.log(self.high / self.low)
        return (x - self.low) / (self.high - self.low)

    def to_x(self, u: float) -> float:
        u = min(max(float(u), 0.0), 1.0)
        if self.log:
            return self.low * (self.high / self.low) ** u
        return self.low + u * (self.high - self.low)

    def dx_du(self, u: float) -> float:
        return self.to_x(u) * math.log(self.high / self.low) if self.log else self.high - self.low


class Units:
    """The real units a fit is judged on: per unit its run (``class/run``), its real gain, and how the engine
    gives its simulated gain for a set of adapter settings (``simulate``: settings -> gains, NaN where failed)."""

    def __init__(self, runs: list[str], real: np.ndarray, names: list[str], simulate, describe: dict):
        self.runs, self.real, self.names, self.simulate, self.describe = (
            runs,
            np.asarray(real, float),
            names,
            simulate,
            describe,
        )
        counts = pd.Series(runs).value_counts()
        # each run weighs alike (the judged figure is a mean over runs of each run's mean over its units)
        self.weights = np.array([1.0 / math.sqrt(counts[r]) for r in runs])

    def residuals(self, sims: np.ndarray) -> np.ndarray:
        r = np.where(np.isfinite(sims), sims - self.real, FAILED_RESIDUAL)
        return r * self.weights

    def error(self, sims: np.ndarray) -> float:
        """The judged figure on these units: each run's mean |simulated - real gain| over its healthy units, then
        the mean over runs (simpick.compare.realmetrics.mean_ci, as the table's held-out columns)."""
        return self.error_ci(sims, 10**9, 0.95, 0)[0]

    def error_interval(self, sims: np.ndarray, min_runs: int, level: float, seed: int) -> tuple[float, float]:
        """The BCa interval of :meth:`error` over the runs, as the table's held-out column gives it (NaN below
        ``min_runs`` runs)."""
        return self.error_ci(sims, min_runs, level, seed)[1:]

    def error_ci(self, sims: np.ndarray, min_runs: int, level: float, seed: int) -> tuple[float, float, float]:
        """(:meth:`error`, its interval's low and high ends); NaN where no unit ran."""
        from simpick.compare.realmetrics import mean_ci

        ok = np.isfinite(sims)
        if not ok.any():
            return math.nan, math.nan, math.nan
        mean, low, high, _ = mean_ci(
            np.abs(sims - self.real)[ok], np.asarray(self.runs, object)[ok], min_runs, level, seed
        )
        return mean, low, high


def least_squares_fit(
    units: Units,
    axes: list[Axis],
    base: dict,
    start: dict,
    max_nfev: int,
    diff_step: float,
    noise: float,
    scan: int = 0,
    optimizer: str = "scipy",
):
    """Bounded least squares of the units' per-run gain residuals over the ``axes`` settings, the others ``base``,
    from ``start``, by ``optimizer`` (:data:`OPTIMIZERS`): scipy.optimize.least_squares (trf), or MuJoCo's own
    system identification (mujoco.sysid.optimize, its optimizer "mujoco"), both in the axes' u coordinates with
    ``max_nfev`` evaluations of the residuals and a finite-difference Jacobian of ``diff_step`` of each setting's
    range (scipy's forward, inward at a bound; mujoco.sysid's mujoco.minimize.jacobian_fd, away from the nearer
    bound), every evaluation cached and recorded. A setting whose column of the Jacobian at the start moves the
    residuals by less than MIN_SENSITIVITY over its whole range is not fitted (kept at its start: these runs cannot
    tell its values apart). Returns a dict: the optimum's settings, its gains and error, the first evaluation's
    (the start), the evaluations, the optimizer's report, and per setting its 95 % interval from the Jacobian at
    the optimum, or why it has none: scipy's covariance (J^T J)^-1 s^2 with a normal quantile,
    mujoco.sysid.calculate_intervals' (Student's t over the residuals' degrees of freedom) mapped from u to the
    setting's units; s^2 the residual variance, or ``noise`` squared (a normal quantile) where the runs leave no
    degree of freedom. ``scan``: first the first setting at as many points evenly over its bounds, the optimizer
    then starting from the one of the lowest sum of squares (the start included): an engine whose gain jumps with
    it (PyBullet's), where a local fit from the tuned value stays in the jump it starts in."""
    if optimizer not in OPTIMIZERS:
        raise ValueError(f"unknown optimizer {optimizer!r}; known: {sorted(OPTIMIZERS)}")
    evaluations: list[tuple[dict, np.ndarray]] = []
    cache: dict[tuple, np.ndarray] = {}
    u_start = {a.name: min(max(a.to_u(start[a.name]), 1e-6), 1 - 1e-6) for a in axes}

    def sims(at: dict) -> np.ndarray:
        """The units' simulated gains with the settings at ``at`` (name -> u; the others at the start)."""
        u = {**u_start, **at}
        key = tuple(round(float(u[a.name]), 6) for a in axes)
        if key not in cache:
            x = {a.name: a.to_x(u[a.name]) for a in axes}
            cache[key] = np.asarray(units.simulate({**base, **x}), float)
            evaluations.append((x, cache[key]))
        return cache[key]

    def residuals(active: list[Axis], points) -> np.ndarray:
        """The residuals at each column of ``points`` (the ``active`` settings' u), a column each."""
        columns = np.asarray(points, float).reshape(len(active), -1).T
        return np.stack([units.residuals(sims({a.name: v for a, v in zip(active, c)})) for c in columns], axis=1)

    def jacobian(active: list[Axis], u) -> np.ndarray:
        u = np.asarray(u, float).ravel()
        r0 = residuals(active, u)
        if optimizer == "mujoco.sysid":  # the finite differences mujoco.minimize.least_squares itself takes
            from mujoco import minimize

            box = [np.zeros((len(active), 1)), np.ones((len(active), 1))]
            point = u.reshape(-1, 1)
            return minimize.jacobian_fd(lambda p: residuals(active, p), point, r0, np.float64(diff_step), 0, box)[0]
        out = np.empty((r0.shape[0], len(active)))
        for j in range(len(active)):
            step = diff_step if u[j] + diff_step <= 1.0 else -diff_step
            v = u.copy()
            v[j] += step
            out[:, j] = (residuals(active, v)[:, 0] - r0[:, 0]) / step
        return out

    first = sims({})
    if scan:
        lead = axes[0].name
        points = [u_start[lead], *np.linspace(1e-6, 1 - 1e-6, scan)]
        best = min(points, key=lambda v: float(np.sum(units.residuals(sims({lead: v})) ** 2)))
        u_start[lead] = float(best)
    start_sensitivity = np.linalg.norm(jacobian(axes, [u_start[a.name] for a in axes]), axis=0)
    unidentifiable = {
        a.name: f"the gain moves {s:.4f} over its whole range at the start; kept at its start"
        for a, s in zip(axes, start_sensitivity)
        if s < MIN_SENSITIVITY
    }
    active = [a for a in axes if a.name not in unidentifiable]
    if not active:  # nothing moves the gain at the start: the first is fitted all the same (judged at the optimum)
        active = axes[:1]
        unidentifiable.pop(active[0].name)
    u0 = np.array([u_start[a.name] for a in active])
    u, J, report = OPTIMIZERS[optimizer](
        lambda p: residuals(active, p), lambda v: jacobian(active, v), u0, [a.name for a in active], max_nfev
    )
    u = np.clip(np.asarray(u, float), 0.0, 1.0)
    optimum = {**u_start, **{a.name: float(v) for a, v in zip(active, u)}}
    at = sims(optimum)
    r = residuals(active, u)[:, 0]
    m, n = J.shape
    dof = m - n
    s2 = float(r @ r) / dof if dof > 0 else noise**2
    sensitivity = np.linalg.norm(J, axis=0)
    if n > m:
        unidentifiable.update({a.name: "more settings than runs" for a in active[m:]})
    for a, s, column in zip(active, sensitivity, J.T):
        if s < MIN_SENSITIVITY:
            unidentifiable.setdefault(a.name, f"the gain moves {s:.4f} over its whole range at the optimum")
        jump = float(np.max(np.abs(column)) * diff_step)
        if jump > JUMP:
            unidentifiable.setdefault(
                a.name,
                f"a run's gain jumps by {jump:.3f} within the Jacobian's step at the optimum (a step, not a slope)",
            )
    scaled = J / np.where(sensitivity > 0, sensitivity, 1.0)
    _, singular, vt = np.linalg.svd(scaled, full_matrices=False)
    for k, sv in enumerate(singular):
        if sv < RELATIVE_SINGULAR * singular[0]:
            for a, load in zip(active, vt[k]):
                if abs(load) > 0.5:
                    unidentifiable.setdefault(a.name, "its column is near-collinear with another's")
    bounds_of = _sysid_intervals if optimizer == "mujoco.sysid" else _normal_intervals
    intervals, intervals_from = bounds_of(active, u, J, r, dof, noise)
    parameters = {}
    column = {a.name: j for j, a in enumerate(active)}
    for a, s0 in zip(axes, start_sensitivity):
        x = a.to_x(optimum[a.name])
        j = column.get(a.name)
        entry = {
            "value": _rs(x),
            "bounds": [a.low, a.high],
            "log": a.log,
            "sensitivity": _r(float(sensitivity[j] if j is not None else s0)),
        }
        if j is not None and a.name not in unidentifiable and not all(map(math.isfinite, intervals[j][1:])):
            unidentifiable[a.name] = "its interval is unbounded (J^T J singular along it)"
        if a.name in unidentifiable:
            entry.update(identifiable=False, why=f"unidentifiable from these runs: {unidentifiable[a.name]}")
        else:
            sd, low, high = intervals[j]
            entry.update(identifiable=True, sd=_rs(sd), interval=[_rs(low), _rs(high)])
        if optimum[a.name] <= 1e-3 or optimum[a.name] >= 1 - 1e-3:
            entry["at_bound"] = "low" if optimum[a.name] <= 1e-3 else "high"
        parameters[a.name] = entry
    return {
        "settings": {a.name: a.to_x(optimum[a.name]) for a in axes},
        "gains": at,
        "error": units.error(at),
        "start_gains": first,
        "start_error": units.error(first),
        "evaluations": evaluations,
        "parameters": parameters,
        "intervals_from": intervals_from,
        "fitted": [a.name for a in active],
        "residual_sd": math.sqrt(s2),
        "residual_sd_from": f"the residuals ({dof} degrees of freedom)"
        if dof > 0
        else f"no degree of freedom ({m} runs, {n} settings): the real robot's run-to-run spread {noise}",
        "report": {**report, "engine_evaluations": len(evaluations)},
    }


def _scipy_least_squares(residuals, jacobian, u0: np.ndarray, names: list[str], max_nfev: int):
    """scipy.optimize.least_squares (trf) over u in [0, 1]: (the optimum, the Jacobian there, its report)."""
    import scipy
    from scipy.optimize import least_squares

    result = least_squares(
        lambda u: residuals(u)[:, 0],
        u0,
        jac=jacobian,
        bounds=(0.0, 1.0),
        method="trf",
        max_nfev=max_nfev,
        x_scale=1.0,
        xtol=0.01,
        ftol=1e-3,
    )
    u = np.clip(result.x, 0.0, 1.0)
    report = {
        "name": "scipy.optimize.least_squares",
        "method": "trf, bounded",
        "version": scipy.__version__,
        # trf takes a new Jacobian after each accepted step, the first at the start
        "iterations": max(int(result.njev or 1) - 1, 0),
        "evaluations": int(result.nfev),
        "jacobians": int(result.njev or 0),
        "status": int(result.status),
        "message": str(result.message),
    }
    return u, jacobian(u), report


# mujoco.minimize.least_squares' regularizer (its Levenberg-Marquardt mu, added to J^T J over u): from the J^T J
# diagonal of the least sensitive setting the fit keeps (MIN_SENSITIVITY squared), a decade per rejected step
# (Marquardt's factor). MuJoCo's defaults, 1e-6 and 10^0.1, damp a step at all (mu a tenth of J^T J: 0.2 for the
# Husky's ratio, its column 1.5) only after some 50 rejected steps, each an evaluation that replays every training
# segment.
SYSID_MU = {"mu_min": MIN_SENSITIVITY**2, "mu_factor": 10.0}


def _sysid_least_squares(residuals, jacobian, u0: np.ndarray, names: list[str], max_nfev: int):
    """MuJoCo's own system identification over u in [0, 1]: mujoco.sysid.optimize with its optimizer "mujoco"
    (mujoco.minimize.least_squares: Gauss-Newton steps in the box, a Levenberg-Marquardt regularizer, Armijo's
    test), a mujoco.sysid ParameterDict of the settings (nominal the start), the residuals' Jacobian from
    mujoco.minimize.jacobian_fd: (the optimum, the optimizer's own Jacobian there, its report).

    Its iterations are bounded by ``max_iters``, its evaluations are not (each rejected step evaluates again):
    ``max_nfev`` bounds them as it bounds scipy's, ``max_nfev - 1`` iterations of one evaluation each after the
    start's. Once they are spent, a further step's residuals are infinite without an engine run, which the
    optimizer's Armijo test rejects until it stops at its last accepted point (its own "insufficient reduction")."""
    import io

    import mujoco
    from mujoco import sysid

    if not hasattr(sysid, "optimize"):  # mujoco.sysid imports nothing where one of the extra's packages is missing
        raise ImportError(
            "mujoco.sysid cannot be imported without its optional packages (absl-py, colorama, tabulate, ...): "
            "install simpick's dependencies, which include mujoco[sysid] (pip install -c constraints.txt -e .)"
        )
    m = residuals(u0).shape[0]
    spent = {"evaluations": 0, "refused": 0, "jacobians": 0}

    def residual_fn(x, params):  # mujoco.sysid's signature: the settings are x itself, in ``names``' order
        points = np.asarray(x, float).reshape(len(u0), -1)
        if spent["evaluations"] + points.shape[1] > max_nfev:
            spent["refused"] += points.shape[1]
            out = np.full((m, points.shape[1]), np.inf)
        else:
            spent["evaluations"] += points.shape[1]
            out = residuals(points)
        return [out if np.ndim(x) > 1 else out[:, 0]], [], []

    params = sysid.ParameterDict(
        {name: sysid.Parameter(name, nominal=float(v), min_value=0.0, max_value=1.0) for name, v in zip(names, u0)}
    )
    trace = io.StringIO()

    def jac(x, r):  # mujoco.minimize.jacobian_fd's, outside the budget: a Jacobian is one per iteration
        spent["jacobians"] += 1
        return jacobian(x[:, 0])

    fitted, result = sysid.optimize(
        params,
        residual_fn,
        optimizer="mujoco",
        verbose=False,
        max_iters=max(max_nfev - 1, 0),
        jacobian=jac,
        xtol=0.01,
        output=trace,
        **SYSID_MU,
    )
    u = np.array([float(fitted[name].value.item()) for name in names])
    lines = [line for line in trace.getvalue().splitlines() if line.startswith("Terminated")]
    message = lines[-1] if lines else ""
    if spent["refused"]:
        message += f" (its {max_nfev} evaluations spent: {spent['refused']} more refused without an engine run)"
    J = np.asarray(result.jac, float) if result.jac is not None else jacobian(u)
    report = {
        "name": "mujoco.sysid.optimize",
        "method": "optimizer 'mujoco': mujoco.minimize.least_squares, bounded",
        "version": mujoco.__version__,
        # the optimizer's log: one entry per accepted step, and the end point's
        "iterations": len(result.extras.get("objective", [None])) - 1,
        "evaluations": spent["evaluations"],
        "jacobians": spent["jacobians"],
        "message": message,
    }
    return u, J, report


OPTIMIZERS = {"scipy": _scipy_least_squares, "mujoco.sysid": _sysid_least_squares}


def _normal_intervals(active: list[Axis], u: np.ndarray, J: np.ndarray, r: np.ndarray, dof: int, noise: float):
    """Per active setting (sd, low, high) in its units: the covariance (J^T J)^-1 s^2 over u, where every setting
    spans [0, 1] (in the settings' own units a compliance of 1e10 beside a ratio of 0.5 leaves J^T J singular to
    machine precision, and its inverse gave a zero-width interval), a normal 95 % interval u +- 1.96 sd mapped to the
    setting's units (over the logarithm for a log setting) and clipped to the bounds (the linearisation does not know
    them); sd in the setting's units at the optimum (sd over u times dx/du)."""
    s2 = float(r @ r) / dof if dof > 0 else noise**2
    cov = np.linalg.pinv(J.T @ J) * s2
    out = []
    for j, (a, v) in enumerate(zip(active, u)):
        sd_u = math.sqrt(max(float(cov[j, j]), 0.0))
        out.append((sd_u * a.dx_du(v), a.to_x(v - Z95 * sd_u), a.to_x(v + Z95 * sd_u)))
    source = "the residuals" if dof > 0 else f"the real robot's run-to-run spread {noise} (no degree of freedom)"
    return out, f"the Jacobian at the optimum: (J^T J)^-1 s^2, s^2 from {source}; 95 % normal, clipped to the bounds"


def _sysid_intervals(active: list[Axis], u: np.ndarray, J: np.ndarray, r: np.ndarray, dof: int, noise: float):
    """Per active setting (sd, low, high) in its units: mujoco.sysid.calculate_intervals at the optimum (95 %, its
    half-widths over u: Student's t over the residuals' degrees of freedom, s^2 from the residuals), u +- the
    half-width mapped to the setting's units (over the logarithm for a log setting) and clipped to the bounds.
    Without a degree of freedom it has no s^2: the real robot's spread ``noise`` stands for it, a normal quantile."""
    if dof > 0:
        from mujoco import sysid

        sigma, half = sysid.calculate_intervals([r], J, alpha=0.05)
        source = f"mujoco.sysid.calculate_intervals at the optimum: 95 %, Student's t with {dof} degrees of freedom"
    else:
        sigma = np.linalg.pinv(J.T @ J) * noise**2
        half = Z95 * np.sqrt(np.maximum(np.diag(sigma), 0.0))
        source = f"the Jacobian at the optimum, s the real robot's run-to-run spread {noise} (no degree of freedom): "
        source += "95 % normal"
    out = []
    for j, (a, v) in enumerate(zip(active, u)):
        sd = math.sqrt(max(float(sigma[j, j]), 0.0)) * a.dx_du(v)
        h = float(half[j])
        out.append((sd, a.to_x(v - h), a.to_x(v + h)) if math.isfinite(h) else (sd, math.nan, math.nan))
    return out, source + "; u +- the half-width in each setting's units, clipped to the bounds"


def step_margins(units: Units, base: dict, settings: dict, gains: np.ndarray, axes: list[Axis], fitted) -> dict:
    """Per fitted setting, the units' gains with it STEP_MARGIN of its value lower and higher (within its bounds),
    the others at the optimum ``settings``: the largest change of a unit's gain from the optimum's ``gains`` and
    whether that is a step (more than STEP_GAIN): two engine evaluations a setting."""
    out = {}
    for a in axes:
        if a.name not in fitted:
            continue
        x = float(settings[a.name])
        probes = sorted(
            {min(max(x * (1 - STEP_MARGIN), a.low), a.high), min(max(x * (1 + STEP_MARGIN), a.low), a.high)}
        )
        moved = []
        for value in probes:
            if value == x:
                continue
            at = np.asarray(units.simulate({**base, **settings, a.name: value}), float)
            both = np.isfinite(at) & np.isfinite(gains)
            # a run that fails on one side of the value and not the other is a step too
            moved.append(float(np.max(np.abs(at[both] - gains[both]))) if both.all() else math.inf)
        largest = max(moved) if moved else 0.0
        out[a.name] = {
            "probed": [_rs(v) for v in probes],
            "largest_gain_change": _r(largest) if math.isfinite(largest) else "a run failed",
            "step": bool(largest > STEP_GAIN),
        }
    return out


def _r(x: float) -> float | None:
    """A gain, an error or a share as the files give it: 4 decimals."""
    return round(float(x), 4) if x is not None and math.isfinite(float(x)) else None


def _rs(x: float) -> float | None:
    """A setting's value as the files give it: 4 significant digits, so that a compliance of 2e-6 (softCFM) or a
    slip of 1.23e-3 keeps its value, which 4 decimals would round to 0 or by 2 %."""
    return float(f"{float(x):.4g}") if x is not None and math.isfinite(float(x)) else None
