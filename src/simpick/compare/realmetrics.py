"""What the paper lacked when comparing a simulated IMU with a real one.

- yaw-rate gain: measured yaw rate over the kinematic (v_r - v_l) / track. A skid-steer
  robot slips when it turns, so the gain is below 1; how far below is exactly where
  engines differ (METHOD.md section 5).
- time-aligned errors: RMS difference of yaw rate and of longitudinal acceleration after
  the same low-pass on both signals (the raw 100 Hz signals are dominated by vibration
  that no rigid terrain reproduces sample by sample).
- vibration: distance between the real and simulated spectra (Welch PSD) of vertical
  acceleration, in decades, averaged over a frequency band.
- statistics over independent runs: a segment or window is not an independent sample (two
  windows of one run share its robot, terrain patch and calibration), so every figure is
  first averaged per run; intervals (BCa bootstrap of the mean) and paired engine verdicts
  (an exact sign-flip permutation test of the per-run mean difference) are given only from
  ``min_runs`` runs on. A two-sided sign-flip test over n runs cannot give p below 2 / 2^n,
  so under 6 runs no difference could ever be significant at 5 %: fewer runs say "too few
  runs" rather than a verdict.
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from simpick.imustats import yaw_rate_gain  # noqa: F401 - defined with the window statistics

# scipy.signal and scipy.stats are imported inside the functions that use them: scipy.stats takes about
# 2 s to import, and the planning (simpick.config: MIN_RUNS, LEVEL) and most jobs read this module
# without them.

LOWPASS_HZ = 2.0
PSD_BAND_HZ = (1.0, 40.0)  # up to the Nyquist frequency where the IMU rate is below 80 Hz
PSD_SEGMENT_S = 2.56  # Welch segment: 256 samples at 100 Hz, the same resolution at any rate


def heading_error(sim_mean_yaw_rate: float, real_mean_yaw_rate: float, duration: float) -> float:
    """|integral of (simulated - real) gyro z| over a window (rad): the heading the simulated robot
    gains or loses on the real one over ``duration`` s, from the two mean yaw rates."""
    return float(abs(sim_mean_yaw_rate - real_mean_yaw_rate) * duration)


def lowpass(signal: np.ndarray, rate_hz: float, cutoff_hz: float = LOWPASS_HZ) -> np.ndarray:
    """Zero-phase 4th-order Butterworth low-pass (the same filter on real and simulated data)."""
    from scipy.signal import butter, sosfiltfilt

    x = np.asarray(signal, float)
    sos = butter(4, cutoff_hz, fs=rate_hz, output="sos")
    padlen = min(len(x) - 1, 3 * (2 * len(sos) + 1))
    return sosfiltfilt(sos, x, padlen=padlen) if len(x) > 1 else x


def aligned_rmse(
    real: np.ndarray, sim: np.ndarray, rate_hz: float, cutoff_hz: float = LOWPASS_HZ, offset_free: bool = False
) -> float:
    """RMS difference of two equally sampled, time-aligned signals after the same low-pass;
    ``offset_free``: of the difference less its mean (a constant offset between them, such as an
    accelerometer bias or a slope's g sin(angle), does not count)."""
    n = min(len(real), len(sim))
    if n < 2:
        return float("nan")
    d = lowpass(real[:n], rate_hz, cutoff_hz) - lowpass(sim[:n], rate_hz, cutoff_hz)
    if offset_free:
        d = d - d.mean()
    return float(np.sqrt(np.mean(d * d)))


def psd_segment(rate_hz: float) -> int:
    """Samples per Welch segment at ``rate_hz`` (:data:`PSD_SEGMENT_S` seconds)."""
    return int(round(PSD_SEGMENT_S * rate_hz))


def psd(signal: np.ndarray, rate_hz: float, nperseg: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Welch power spectral density of the signal less its mean (so gravity and tilt drop out)."""
    from scipy.signal import welch

    x = np.asarray(signal, float)
    nperseg = psd_segment(rate_hz) if nperseg is None else nperseg
    return welch(x - x.mean(), fs=rate_hz, nperseg=int(min(nperseg, len(x))))


def psd_distance(real: np.ndarray, sim: np.ndarray, rate_hz: float, band: tuple[float, float] = PSD_BAND_HZ) -> float:
    """Mean |log10 PSD_sim - log10 PSD_real| over ``band`` (decades; 0 = same spectrum).

    Welch with 2.56 s segments; the mean is removed, so gravity and tilt do not count. The
    band ends at the Nyquist frequency of a slower IMU.
    """
    nper = int(min(psd_segment(rate_hz), len(real), len(sim)))
    if nper < 16:
        return float("nan")
    f, p_real = psd(real, rate_hz, nper)
    _, p_sim = psd(sim, rate_hz, nper)
    keep = (f >= band[0]) & (f <= band[1])
    tiny = 1e-12  # a perfectly still simulation has zero power: compare against a floor
    return float(np.mean(np.abs(np.log10(p_sim[keep] + tiny) - np.log10(p_real[keep] + tiny))))


# The statistics defaults, stated once: the config's ``statistics`` model (simpick.config.Statistics)
# takes them as its defaults, the rules pass its validated slice to every job, and a job called with
# none (a test, a script) gets them through statistics_settings.
MIN_RUNS = 6  # the smallest n whose sign-flip test can reach p < 0.05 (2 / 2^6 = 0.031)
LEVEL = 0.95  # confidence of the BCa intervals; verdicts need a sign-flip p below 1 - LEVEL


def statistics_settings(statistics: dict | None = None) -> tuple[int, float]:
    """(min_runs, level) of a job's ``statistics`` settings (the validated config slice); the
    defaults above for a key it does not give."""
    st = {"min_runs": MIN_RUNS, "level": LEVEL} | dict(statistics or {})
    return int(st["min_runs"]), float(st["level"])


def smallest_p(n: int) -> float:
    """The smallest two-sided p-value an exact sign-flip test over ``n`` pairs can give."""
    return min(1.0, 2.0 / 2.0**n) if n > 0 else 1.0


def per_run(values, runs=None) -> np.ndarray:
    """The finite values averaged per run (``runs`` labels each value; None: each value is a run)."""
    x = np.asarray(values, float)
    keys = np.arange(x.size) if runs is None else np.asarray(runs, dtype=object)
    finite = np.isfinite(x)
    if not finite.any():
        return np.empty(0)
    frame = pd.DataFrame({"run": keys[finite], "x": x[finite]})
    return frame.groupby("run", sort=True)["x"].mean().to_numpy(float)


def _bca(x: np.ndarray, level: float, seed: int) -> tuple[float, float]:
    from scipy.stats import bootstrap

    if np.ptp(x) <= 1e-12 * max(1.0, float(np.abs(x).max())):  # every run the same: nothing to resample
        return float(x.mean()), float(x.mean())

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a degenerate BCa falls back to the percentile interval below
        for method in ("BCa", "percentile"):
            res = bootstrap(
                (x,),
                np.mean,
                confidence_level=level,
                method=method,
                n_resamples=4999,
                random_state=np.random.default_rng(seed),
            )
            low, high = float(res.confidence_interval.low), float(res.confidence_interval.high)
            if np.isfinite(low) and np.isfinite(high):
                break
    return low, high


def mean_ci(
    values, runs=None, min_runs: int = MIN_RUNS, level: float = LEVEL, seed: int = 0
) -> tuple[float, float, float, int]:
    """(mean, low, high, n_runs): mean over runs (each run's values averaged first) and its BCa
    bootstrap interval, NaN below ``min_runs`` runs."""
    x = per_run(values, runs)
    if x.size == 0:
        return float("nan"), float("nan"), float("nan"), 0
    if x.size < max(int(min_runs), 2):
        return float(x.mean()), float("nan"), float("nan"), int(x.size)
    low, high = _bca(x, level, seed)
    return float(x.mean()), low, high, int(x.size)


def paired_test(a, b, runs=None, min_runs: int = MIN_RUNS, level: float = LEVEL, seed: int = 0) -> dict:
    """Is ``a`` really different from ``b``, over the runs both have (a pair per test)?

    Differences a - b are averaged per run; below ``min_runs`` runs the result has no p-value,
    no interval and the verdict ``too few runs``. Otherwise: an exact two-sided sign-flip
    permutation test of the mean difference (``scipy.stats.permutation_test``,
    ``permutation_type='samples'``; random sign flips, seeded, above 2^13 runs) and the BCa
    bootstrap interval of the mean difference. ``verdict`` is ``a`` (a is larger), ``b``,
    ``no clear difference`` or ``too few runs``.
    """
    from scipy.stats import permutation_test

    a, b = np.asarray(a, float), np.asarray(b, float)
    both = np.isfinite(a) & np.isfinite(b)
    keys = None if runs is None else np.asarray(runs, dtype=object)[both]
    d = per_run(a[both] - b[both], keys)
    out = {
        "mean": float(d.mean()) if d.size else float("nan"),
        "low": float("nan"),
        "high": float("nan"),
        "p_value": float("nan"),
        "n_runs": int(d.size),
        "verdict": "too few runs",
    }
    if d.size < max(int(min_runs), 2):
        return out
    if np.all(d == 0):
        out.update(low=0.0, high=0.0, p_value=1.0, verdict="no clear difference")
        return out
    res = permutation_test(
        (d, np.zeros_like(d)),
        lambda x, y, axis: np.mean(x - y, axis=axis),
        permutation_type="samples",
        alternative="two-sided",
        n_resamples=2**13,
        random_state=np.random.default_rng(seed),
    )
    low, high = _bca(d, level, seed)
    p = float(res.pvalue)
    out.update(
        low=low,
        high=high,
        p_value=p,
        verdict=("no clear difference" if p >= 1 - level else "a" if d.mean() > 0 else "b"),
    )
    return out
