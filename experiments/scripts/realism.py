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
mean: 9.8 +/- 0.3 m/s^2). Run ``python -m experiments.scripts.realism`` from the repository root.

Window-to-window variability (:func:`window_variability`): the coefficient
of variation (std / |mean| across the windows of one recording) of the window
features ``acc_mag__var``, ``acc_mag__max`` and ``acc_mag__min``
(:func:`gaitml.features.extract_features`, ``acc_mag`` is ``|acc| - g``) at
0.5 s and 1.5 s windows with 50 % overlap, on the walking part only (from the
first to the last step peak, so standing at the ends does not count). It
measures how different one window's view of the same walk is from the next:
with 0.5 s windows (about one step) it is the step-to-step variability of
the gait and the phone, which decides how well a short window recognises the
motion mode (paper 003 sec. 3.3, Table 2). :func:`variability_table` compares
the two real walks with several simulated flat-held walkers (their median
and range) on the same accepted range (real span widened by 25 %).
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

__all__ = [
    "gait_statistics",
    "count_peaks",
    "real_statistics",
    "realism_table",
    "reference_walk",
    "plot_comparison",
    "window_variability",
    "real_window_variability",
    "simulated_walkers",
    "variability_table",
    "REAL_FILES",
    "VARIABILITY_WINDOWS_S",
    "VARIABILITY_FEATURES",
    "main",
]

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
#: Window lengths (s) and overlap of the window-variability statistics (paper 003 sec. 3.3).
VARIABILITY_WINDOWS_S = (0.5, 1.5)
VARIABILITY_OVERLAP = 0.5
#: Window features whose across-window CV is compared.
VARIABILITY_FEATURES = ("acc_mag__var", "acc_mag__max", "acc_mag__min")


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


def window_variability(recording: Recording) -> dict[str, float]:
    """Across-window CV (std / |mean|) of :data:`VARIABILITY_FEATURES` at 0.5 and 1.5 s windows.

    Only the walking part counts: the recording is cut from the first to the
    last step peak (:func:`count_peaks` with the realism settings). Keys are
    ``cv_<feature>_<length>s``, e.g. ``cv_acc_mag__var_0.5s``.
    """
    from gaitml.features import extract_features

    pk = count_peaks(recording, height_above_g_ms2=PEAK_ABOVE_G_MS2, min_distance_s=MIN_PEAK_DISTANCE_S)
    walk = recording.slice(int(pk[0]), int(pk[-1]) + 1) if len(pk) > 2 else recording
    out = {}
    for length_s in VARIABILITY_WINDOWS_S:
        feats = extract_features(walk, length_s=length_s, overlap=VARIABILITY_OVERLAP)
        for f in VARIABILITY_FEATURES:
            x = feats[f].to_numpy(float)
            out[f"cv_{f}_{length_s:g}s"] = float(x.std() / abs(x.mean()))
    return out


@functools.lru_cache(maxsize=4)
def _real_window_variability(root: str) -> tuple[dict, dict]:
    from gaitml.io import read_recording

    return tuple(window_variability(read_recording(Path(root) / f)) for f in REAL_FILES)


def real_window_variability(shared_data: str | Path) -> list[dict[str, float]]:
    """:func:`window_variability` of the two real flat-held walks (cached per folder)."""
    return [dict(d) for d in _real_window_variability(str(Path(shared_data).resolve()))]


def simulated_walkers(n: int = 6, *, seed: int = 0, duration_s: float = 150.0) -> list[Recording]:
    """``n`` simulated flat-held walks (walking only, 50 Hz) of subjects drawn from ``seed``."""
    from gaitml.simulate.dataset import simulate_recording
    from gaitml.simulate.subject import sample_subjects

    return [
        simulate_recording(s, route="straight", modes=("walk",), duration_s=duration_s, seed=i)
        for i, s in enumerate(sample_subjects(n, seed=seed, pose="flat"))
    ]


def variability_table(shared_data: str | Path, *, simulated: list[Recording] | None = None) -> pd.DataFrame:
    """Rows: window-variability statistics; columns ``real_1, real_2, sim_median, sim_min, sim_max, low, high, inside``.

    ``simulated`` defaults to :func:`simulated_walkers` (6 subjects, seed 0);
    ``inside`` says whether the simulated median lies in the real span widened
    by 25 % on each side; ``near`` whether it lies within 0.8 x the smaller
    and 1.25 x the larger real value (the looser check for statistics whose
    two real values happen to be almost equal). Single walkers may fall
    outside: people differ (``sim_min``, ``sim_max``).
    """
    real = real_window_variability(shared_data)
    sims = [window_variability(r) for r in (simulated if simulated is not None else simulated_walkers())]
    rows = []
    for k in real[0]:
        a, b = real[0][k], real[1][k]
        span = abs(a - b)
        lo, hi = min(a, b) - WIDEN * span, max(a, b) + WIDEN * span
        v = np.array([s[k] for s in sims])
        med = float(np.median(v))
        rows.append(
            {
                "statistic": k,
                "real_1": a,
                "real_2": b,
                "sim_median": med,
                "sim_min": float(v.min()),
                "sim_max": float(v.max()),
                "low": lo,
                "high": hi,
                "inside": bool(lo <= med <= hi),
                "near": bool(0.8 * min(a, b) <= med <= 1.25 * max(a, b)),
            }
        )
    return pd.DataFrame(rows).set_index("statistic")


def plot_comparison(shared_data: str | Path, path: str | Path, *, seconds: float = 6.0, start_s: float = 20.0) -> Path:
    """PNG of ``|acc|`` (raw and N = 5 smoothed) of real 1, real 2 and the simulated walk, same scale.

    The simulated panel marks the true step events (``reference['steps_t_s']``).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gaitml.io import atomic_path, read_recording

    recs = [read_recording(Path(shared_data) / f) for f in REAL_FILES] + [reference_walk()]
    names = ["real 1 (ifsm file 1)", "real 2 (ifsm file 2)", "simulated (default subject, flat)"]
    fig, axes = plt.subplots(3, 1, figsize=(9, 7), sharex=True, sharey=True)
    for ax, rec, name in zip(axes, recs, names, strict=True):
        a, b = int(start_s * rec.sampling_rate_hz), int((start_s + seconds) * rec.sampling_rate_hz)
        t = rec.t_s[a:b] - start_s
        mag = np.linalg.norm(rec.acc, axis=1)
        ax.plot(t, mag[a:b], lw=0.8, color="0.6", label="|acc|")
        ax.plot(t, moving_average(mag, SMOOTH_N)[a:b], lw=1.4, label="smoothed N=5")
        if "steps_t_s" in rec.reference:
            ts = rec.reference["steps_t_s"]
            ts = ts[(ts >= start_s) & (ts < start_s + seconds)] - start_s
            ax.vlines(ts, 3, 20, colors="C3", lw=0.8, linestyles=":", label="true step")
        ax.set_title(name, fontsize=10)
        ax.set_ylabel("m/s$^2$")
        ax.axhline(GRAVITY_MS2, color="k", lw=0.5)
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("s")
    fig.tight_layout()
    out = Path(path)
    with atomic_path(out, suffix=".png") as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return out


def main(argv: list[str] | None = None) -> int:
    """Print the realism table.

    Usage: ``python -m experiments.scripts.realism [SHARED_DATA] [--plot PNG]``
    (SHARED_DATA defaults to ../shared/data beside the repository).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    plot = None
    if "--plot" in argv:
        i = argv.index("--plot")
        if i + 1 >= len(argv):
            print("--plot needs a PNG path.", file=sys.stderr)
            return 2
        plot = argv[i + 1]
        del argv[i : i + 2]
    root = Path(argv[0]) if argv else Path(__file__).resolve().parents[2].parent / "shared" / "data"
    if not (root / REAL_FILES[0]).exists():
        print(f"real data not found below {root}; pass the shared data folder as the argument.", file=sys.stderr)
        return 2
    tab = realism_table(root)
    var = variability_table(root)
    with pd.option_context("display.float_format", "{:.3f}".format, "display.width", 140):
        print(tab.to_string())
        print()
        print(var.to_string())
    if plot:
        print(f"figure: {plot_comparison(root, plot)}", file=sys.stderr)
    return 0 if tab["inside"].all() and var["near"].all() else 1


if __name__ == "__main__":
    raise SystemExit(main())
