"""Realism check: a simulated flat-held walk beside the two real ones.

The real reference is ``ifsm-flat-phone`` (paper 000's data: two people
walking 211 m with a Xiaomi 6 held flat, 50 Hz, 284 and 319 true steps).
For each recording :func:`gait_statistics` measures, on the acceleration
magnitude ``|acc|`` (m/s^2, gravity included):

- ``mag_mean_ms2``, ``mag_std_ms2``: mean and standard deviation of ``|acc|``;
- ``peak_ms2`` / ``trough_ms2``: mean of the per-step maxima / minima of
  ``|acc|`` smoothed by a centred moving average of N = 5 samples (paper 000's
  preprocessing); the maxima are the peaks found by ``scipy.signal.find_peaks``
  above ``g + 0.7`` m/s^2 at least 0.3 s apart (paper 003: 15 samples at
  50 Hz), the minima the lowest value between consecutive peaks;
- ``cadence_hz``: steps per second, (number of peaks - 1) / (time from the
  first to the last peak), which ignores standing at the start and end.

With these settings the detector finds exactly the published 284 and 319
steps in the two real files. :func:`realism_table` puts real 1, real 2 and a
simulated flat-held walk side by side with the accepted range: the span of
the two real values widened by 25 % of that span on each side (the magnitude
mean: 9.8 +/- 0.3 m/s^2). Run ``python -m gaitml.simulate.realism``.
"""

from __future__ import annotations

import functools
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.signal

from gaitml.consts import GRAVITY_MS2
from gaitml.recording import Recording
from gaitml.signal import moving_average

__all__ = ["gait_statistics", "count_peaks", "real_statistics", "realism_table", "reference_walk", "REAL_FILES", "main"]

#: The real flat-held walks (paper 000 data) below the shared data folder.
REAL_FILES = ("ifsm-flat-phone/acceleration_flat_holding_1.xlsx", "ifsm-flat-phone/acceleration_flat_holding_2.xlsx")
#: Statistics compared, in table order.
STATS = ("mag_mean_ms2", "mag_std_ms2", "peak_ms2", "trough_ms2", "cadence_hz")
#: Smoothing of |acc| before peak picking (paper 000: moving average N = 5).
SMOOTH_N = 5
#: Peak height above g for the realism statistics.
PEAK_ABOVE_G_MS2 = 0.7
#: Minimum peak distance (paper 003 sec. 2.2: sigma2 = 15 samples at 50 Hz).
MIN_PEAK_DISTANCE_S = 0.3
#: Widening of the real span on each side, as a fraction of the span.
WIDEN = 0.25


def count_peaks(
    recording: Recording,
    *,
    height_above_g_ms2: float = 2.0,
    min_distance_s: float = 0.25,
    smooth_n: int = SMOOTH_N,
) -> np.ndarray:
    """Sample indices of steps found by ``find_peaks`` on the smoothed ``|acc|``.

    Defaults: peaks at least ``2 m/s^2`` above g (paper 003 sec. 2.2, sigma1)
    and 0.25 s apart (running reaches 3.2 steps/s).
    """
    mag = moving_average(np.linalg.norm(recording.acc, axis=1), smooth_n)
    dist = max(1, int(round(min_distance_s * recording.sampling_rate_hz)))
    peaks, _ = scipy.signal.find_peaks(mag, height=GRAVITY_MS2 + height_above_g_ms2, distance=dist)
    return peaks


def gait_statistics(recording: Recording) -> dict[str, float]:
    """Magnitude mean/std, per-step peak/trough levels and cadence (see the module docstring)."""
    mag = np.linalg.norm(recording.acc, axis=1)
    sm = moving_average(mag, SMOOTH_N)
    peaks = count_peaks(recording, height_above_g_ms2=PEAK_ABOVE_G_MS2, min_distance_s=MIN_PEAK_DISTANCE_S)
    troughs = [sm[a:b].min() for a, b in zip(peaks[:-1], peaks[1:], strict=True)]
    fs = recording.sampling_rate_hz
    cadence = (len(peaks) - 1) / ((peaks[-1] - peaks[0]) / fs) if len(peaks) > 2 else float("nan")
    return {
        "mag_mean_ms2": float(mag.mean()),
        "mag_std_ms2": float(mag.std()),
        "peak_ms2": float(sm[peaks].mean()) if len(peaks) else float("nan"),
        "trough_ms2": float(np.mean(troughs)) if troughs else float("nan"),
        "cadence_hz": float(cadence),
        "n_peaks": int(len(peaks)),
    }


def reference_walk(*, duration_s: float = 150.0, seed: int = 0, subject=None) -> Recording:
    """A simulated flat-held walk (walking only) of the default :class:`Subject` at 50 Hz."""
    from gaitml.simulate.dataset import simulate_recording
    from gaitml.simulate.subject import Subject

    subj = subject if subject is not None else Subject()
    return simulate_recording(subj, route="straight", duration_s=duration_s, modes=("walk",), seed=seed)


@functools.lru_cache(maxsize=4)
def _real_statistics(root: str) -> tuple[dict, dict]:
    from gaitml.io import read_recording

    return tuple(gait_statistics(read_recording(Path(root) / f)) for f in REAL_FILES)


def real_statistics(shared_data: str | Path) -> list[dict[str, float]]:
    """:func:`gait_statistics` of the two real flat-held walks (cached per folder)."""
    return [dict(d) for d in _real_statistics(str(Path(shared_data).resolve()))]


def realism_table(shared_data: str | Path, *, simulated: Recording | None = None) -> pd.DataFrame:
    """Rows: statistics; columns: ``real_1, real_2, simulated, low, high, inside``."""
    real = real_statistics(shared_data)
    sim = gait_statistics(simulated if simulated is not None else reference_walk())
    rows = []
    for k in STATS:
        a, b = real[0][k], real[1][k]
        if k == "mag_mean_ms2":
            lo, hi = 9.8 - 0.3, 9.8 + 0.3
        else:
            span = abs(a - b)
            lo, hi = min(a, b) - WIDEN * span, max(a, b) + WIDEN * span
        rows.append(
            {"statistic": k, "real_1": a, "real_2": b, "simulated": sim[k], "low": lo, "high": hi, "inside": bool(lo <= sim[k] <= hi)}
        )
    return pd.DataFrame(rows).set_index("statistic")


def main(argv: list[str] | None = None) -> int:
    """Print the realism table; the argument is the shared data folder (default ../shared/data)."""
    argv = sys.argv[1:] if argv is None else argv
    root = Path(argv[0]) if argv else Path(__file__).resolve().parents[2].parent / "shared" / "data"
    if not (root / REAL_FILES[0]).exists():
        print(f"real data not found below {root}; pass the shared data folder as the argument.", file=sys.stderr)
        return 2
    tab = realism_table(root)
    with pd.option_context("display.float_format", "{:.3f}".format, "display.width", 120):
        print(tab.to_string())
    return 0 if tab["inside"].all() else 1


if __name__ == "__main__":
    raise SystemExit(main())
