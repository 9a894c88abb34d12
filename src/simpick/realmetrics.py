"""What the paper lacked when comparing a simulated IMU with a real one.

- yaw-rate gain: measured yaw rate over the kinematic (v_r - v_l) / track. A skid-steer
  robot slips when it turns, so the gain is below 1; how far below is exactly where
  engines differ (METHOD.md section 5).
- time-aligned errors: RMS difference of yaw rate and of longitudinal acceleration after
  the same low-pass on both signals (the raw 100 Hz signals are dominated by vibration
  that no rigid terrain reproduces sample by sample).
- vibration: distance between the real and simulated spectra (Welch PSD) of vertical
  acceleration, in decades, averaged over a frequency band.
- bootstrap confidence intervals over runs, and over paired differences between engines,
  so a report can say whether one engine is really closer than another.
"""

from __future__ import annotations

import numpy as np

LOWPASS_HZ = 2.0
PSD_BAND_HZ = (1.0, 40.0)  # up to the Nyquist frequency where the IMU rate is below 80 Hz
PSD_SEGMENT_S = 2.56  # Welch segment: 256 samples at 100 Hz, the same resolution at any rate


def yaw_rate_gain(yaw_rate: np.ndarray, v_left: np.ndarray, v_right: np.ndarray, track: float,
                  min_kinematic: float = 0.05) -> float:
    """Least-squares gain through the origin of measured over kinematic yaw rate.

    Only samples whose kinematic yaw rate exceeds ``min_kinematic`` rad/s count; NaN if none.
    """
    kinematic = (np.asarray(v_right, float) - np.asarray(v_left, float)) / track
    yaw = np.asarray(yaw_rate, float)
    turning = np.abs(kinematic) > min_kinematic
    if not turning.any():
        return float("nan")
    k, y = kinematic[turning], yaw[turning]
    return float(np.dot(y, k) / np.dot(k, k))


def lowpass(signal: np.ndarray, rate_hz: float, cutoff_hz: float = LOWPASS_HZ) -> np.ndarray:
    """Zero-phase 4th-order Butterworth low-pass (the same filter on real and simulated data)."""
    from scipy.signal import butter, sosfiltfilt

    x = np.asarray(signal, float)
    sos = butter(4, cutoff_hz, fs=rate_hz, output="sos")
    padlen = min(len(x) - 1, 3 * (2 * len(sos) + 1))
    return sosfiltfilt(sos, x, padlen=padlen) if len(x) > 1 else x


def aligned_rmse(real: np.ndarray, sim: np.ndarray, rate_hz: float, cutoff_hz: float = LOWPASS_HZ) -> float:
    """RMS difference of two equally sampled, time-aligned signals after the same low-pass."""
    n = min(len(real), len(sim))
    if n < 2:
        return float("nan")
    d = lowpass(real[:n], rate_hz, cutoff_hz) - lowpass(sim[:n], rate_hz, cutoff_hz)
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


def psd_distance(real: np.ndarray, sim: np.ndarray, rate_hz: float,
                 band: tuple[float, float] = PSD_BAND_HZ) -> float:
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


def bootstrap_ci(values, level: float = 0.95, resamples: int = 2000, seed: int = 0) -> tuple[float, float, float]:
    """(mean, low, high): percentile bootstrap of the mean over independent runs."""
    x = np.asarray([v for v in values if np.isfinite(v)], float)
    if x.size == 0:
        return (float("nan"),) * 3
    if x.size == 1:
        return float(x[0]), float("nan"), float("nan")
    rng = np.random.default_rng(seed)
    means = x[rng.integers(0, x.size, size=(resamples, x.size))].mean(axis=1)
    alpha = (1 - level) / 2
    return float(x.mean()), float(np.quantile(means, alpha)), float(np.quantile(means, 1 - alpha))


def paired_difference_ci(a, b, level: float = 0.95, resamples: int = 2000,
                         seed: int = 0) -> tuple[float, float, float]:
    """Bootstrap CI of mean(a - b) over runs both engines completed: excludes 0 -> a real difference."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    both = np.isfinite(a) & np.isfinite(b)
    return bootstrap_ci(a[both] - b[both], level, resamples, seed)
