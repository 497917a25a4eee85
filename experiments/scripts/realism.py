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
    "OXFORD_POSITIONS",
    "position_statistics",
    "oxford_walks",
    "simulated_position_walks",
    "position_table",
    "feature_spread",
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


def simulated_walkers(n: int = 6, *, seed: int = 0, duration_s: float = 150.0, hand_gain: float | None = 1.0) -> list[Recording]:
    """``n`` simulated flat-held walks (walking only, 50 Hz) of subjects drawn from ``seed``.

    ``hand_gain`` (default 1) replaces each subject's drawn
    :attr:`~gaitml.simulate.subject.Subject.hand_gain`: the two IFSM walkers these walks are
    compared with walk at about gain 1 (their ``|acc|`` standard deviations of 2.7 and 3.4 m/s^2
    lie in the gain-1 population's 2.7-4.0); the calm end of the gain range comes from other
    people (the Oxford ``InHand`` walks). None keeps the drawn gains.
    """
    import dataclasses

    from gaitml.simulate.dataset import simulate_recording
    from gaitml.simulate.subject import sample_subjects

    subjects = sample_subjects(n, seed=seed, pose="flat")
    if hand_gain is not None:
        subjects = [dataclasses.replace(s, hand_gain=float(hand_gain)) for s in subjects]
    return [simulate_recording(s, route="straight", modes=("walk",), duration_s=duration_s, seed=i) for i, s in enumerate(subjects)]


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


# ----------------------------------------------------------------------------------------------
# Carrying positions against the Oxford walks (issue 12)
# ----------------------------------------------------------------------------------------------
#: Simulated carrying position -> the Oxford position(s) of real walking it is compared with.
#: Oxford ``InHand`` (phone held in front, about 25 deg pitch) lies between the flat and the
#: tilted hand-held phone; ``NeckPouch`` and ``Armband`` have no simulated counterpart and the
#: ``belt`` has no real walking in ../shared/data.
OXFORD_POSITIONS = {
    "hand-flat": "InHand",
    "hand-tilted": "InHand",
    "front-pocket": "FrontPocket",
    "back-pocket": "BackPocket",
    "belt": None,
    "swinging-hand": "SwingingArm",
    "bag": "Purse",
}
#: Oxford users; the simulator's position parameters were chosen on the first two.
OXFORD_USERS = ("Jamie", "Carmelo", "Dario")
TUNING_USERS = ("Jamie", "Carmelo")
#: Per-position statistics in table order (axis-order-free; see :func:`position_statistics`).
POSITION_STATS = (
    "mag_mean_ms2",
    "mag_std_ms2",
    "mag_p5_ms2",
    "mag_p50_ms2",
    "mag_p95_ms2",
    "cadence_hz",
    "f_mag_per_cadence",
    "f_ax1_per_cadence",
    "f_ax2_per_cadence",
    "f_ax3_per_cadence",
    "var_share_1",
    "var_share_2",
    "var_share_3",
    "r_step",
    "r_stride",
)
#: Statistics the verdict of a position rests on (the magnitude, its rhythm and the axis spread).
VERDICT_STATS = ("mag_std_ms2", "mag_p5_ms2", "mag_p95_ms2", "f_mag_per_cadence", "var_share_1", "var_share_3", "r_step", "r_stride")
_WALK_FS_HZ = 50.0
#: Absolute tolerance added on each side of a real range, by statistic family.
_FLOOR = {"mag": 0.3, "cadence": 0.1, "f": 0.05, "var": 0.03, "r": 0.05}


def _dominant_hz(x: np.ndarray, fs: float) -> float:
    """Frequency (Hz) of the largest Welch peak of ``x`` within 0.3-6 Hz (8 s segments, 0.125 Hz bins)."""
    x = np.asarray(x, dtype=float) - np.mean(x)
    f, p = scipy.signal.welch(x, fs=fs, nperseg=min(len(x), int(8 * fs)))
    band = (f > 0.3) & (f < 6.0)
    return float(f[band][np.argmax(p[band])])


def _autocorr(x: np.ndarray, lag: int) -> float:
    x = np.asarray(x, dtype=float) - np.mean(x)
    if lag <= 0 or lag >= len(x):
        return float("nan")
    return float(np.dot(x[:-lag], x[lag:]) / np.dot(x, x) * len(x) / (len(x) - lag))


def position_statistics(recording: Recording, steps_t_s: np.ndarray | None = None) -> dict[str, float]:
    """Axis-order-free walking statistics of one recording, from its first to its last true step.

    - ``mag_*``: mean, standard deviation and 5th/50th/95th percentiles of ``|acc|`` (m/s^2);
    - ``cadence_hz``: true steps per second (Oxford: foot switches; simulated: the true steps);
    - ``f_mag_per_cadence``: the dominant frequency of ``|acc|`` over the cadence (1 = the step
      frequency, 0.5 = the stride frequency);
    - ``f_ax{1,2,3}_per_cadence``: the same per phone axis, the axes ordered by decreasing variance
      (phones sit differently, so the axes are compared by rank, not by name);
    - ``var_share_{1,2,3}``: each axis's share of the total acceleration variance, sorted
      (1 = largest);
    - ``r_step`` / ``r_stride``: the autocorrelation of ``|acc|`` at a lag of one step / one stride
      (step and stride regularity, Moe-Nilssen & Helbostad 2004, J. Biomech. 37:121); a phone on
      one leg or arm repeats per stride, so ``r_stride`` exceeds ``r_step`` there.
    """
    st = np.asarray(recording.reference["steps_t_s"] if steps_t_s is None else steps_t_s, dtype=float)
    fs = recording.sampling_rate_hz
    i0, i1 = int(np.ceil(st[0] * fs)), int(np.floor(st[-1] * fs))
    acc = recording.acc[i0:i1]
    mag = np.linalg.norm(acc, axis=1)
    cad = (len(st) - 1) / (st[-1] - st[0])
    var = acc.var(axis=0)
    order = np.argsort(var)[::-1]
    share = var[order] / var.sum()
    out = {
        "mag_mean_ms2": float(mag.mean()),
        "mag_std_ms2": float(mag.std()),
        "mag_p5_ms2": float(np.percentile(mag, 5)),
        "mag_p50_ms2": float(np.percentile(mag, 50)),
        "mag_p95_ms2": float(np.percentile(mag, 95)),
        "cadence_hz": float(cad),
        "f_mag_per_cadence": _dominant_hz(mag, fs) / cad,
    }
    for r, ax in enumerate(order, start=1):
        out[f"f_ax{r}_per_cadence"] = _dominant_hz(acc[:, ax], fs) / cad
    for r, v in enumerate(share, start=1):
        out[f"var_share_{r}"] = float(v)
    out["r_step"] = _autocorr(mag, int(round(fs / cad)))
    out["r_stride"] = _autocorr(mag, int(round(2 * fs / cad)))
    return out


@functools.lru_cache(maxsize=2)
def _oxford_walks(root: str) -> tuple:
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder

    out = []
    for d in list_oxford_folders(Path(root) / "oxford-step-counter"):
        rec = read_oxford_folder(d, sampling_rate_hz=_WALK_FS_HZ)
        if rec.meta.get("surface") != "Hard":
            continue  # one surface: the carpet walks exist for InHand only
        out.append(rec)
    return tuple(out)


def oxford_walks(shared_data: str | Path) -> list[Recording]:
    """The Oxford walks on the hard floor, resampled to 50 Hz (cached per folder)."""
    return list(_oxford_walks(str(Path(shared_data).resolve())))


def simulated_position_walks(position: str, *, n: int = 6, seed: int = 0, duration_s: float = 90.0) -> list[Recording]:
    """``n`` simulated subjects walking (walk mode only, straight route) with the phone at ``position``."""
    from gaitml.simulate import simulate_dataset

    return simulate_dataset(n, duration_s, ("walk",), seed=seed, positions=(position,))


def feature_spread(recordings: list[Recording]) -> pd.Series:
    """Interquartile range across the 1.5 s windows (50 % overlap) of each of the 52 features, pooled
    over ``recordings`` (walking part only: from the first to the last true step)."""
    from gaitml.features import extract_features

    tabs = []
    for rec in recordings:
        st = rec.reference["steps_t_s"]
        fs = rec.sampling_rate_hz
        part = rec.slice(int(np.ceil(st[0] * fs)), int(np.floor(st[-1] * fs)))
        tabs.append(extract_features(part, subset="all52", length_s=1.5, overlap=0.5))
    f = pd.concat(tabs, ignore_index=True)
    return f.quantile(0.75) - f.quantile(0.25)


def _summary(stats: list[dict]) -> dict[str, tuple[float, float, float]]:
    """Per statistic: (median, min, max) over recordings."""
    df = pd.DataFrame(stats)
    return {k: (float(df[k].median()), float(df[k].min()), float(df[k].max())) for k in POSITION_STATS}


def position_table(
    shared_data: str | Path,
    *,
    positions: tuple[str, ...] | None = None,
    heldout: str = "Dario",
    n_sim: int = 8,
    seed: int = 0,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Simulated vs real walking per carrying position, with one Oxford user held out.

    Returns ``(table, verdicts)``. ``table`` has one row per (position, statistic) with the
    real tuning users' median and range (``real_tune``, ``tune_lo``, ``tune_hi``), the held-out
    user's median (``real_heldout``), the simulated median and 5-95 % range over ``n_sim``
    simulated subjects (``sim``, ``sim_lo``, ``sim_hi``), ``tune_ok`` (the simulated median lies
    in the tuning users' range widened by 25 % of the range plus a floor (0.3 m/s^2 for the
    magnitude, 0.1 /s for the cadence, 0.05 for frequency ratios and correlations, 0.03 for
    variance shares) on each side) and ``heldout_ok``
    (the same test on the held-out user's range) and ``heldout_covered`` (the held-out user's median
    lies in the simulated 5-95 % range plus the floor: the user is inside the simulated population).
    ``verdicts``: one row per position with the number of verdict statistics (:data:`VERDICT_STATS`)
    passing each test and the verdict ``match`` (every verdict statistic passes on the tuning users
    and, held out, passes ``heldout_ok`` or ``heldout_covered``), ``partial`` (at least 3/4 do) or
    ``no match``.
    The 52 features' spread is a row ``feature_iqr_ratio`` (median over features of the simulated
    over the real IQR) with ``feature_iqr_within_2x`` (fraction of features within a factor 2).
    """
    from gaitml.simulate import POSITIONS

    walks = oxford_walks(shared_data)
    positions = tuple(POSITIONS) if positions is None else tuple(positions)
    rows, verdicts = [], []
    for pos in positions:
        ox = OXFORD_POSITIONS.get(pos)
        real = [r for r in walks if r.meta.get("position") == ox] if ox else []
        sims = simulated_position_walks(pos, n=n_sim, seed=seed)
        sim_stats = [position_statistics(r) for r in sims]
        sdf = pd.DataFrame(sim_stats)
        tune = [position_statistics(r) for r in real if r.meta.get("user") in TUNING_USERS]
        held = [position_statistics(r) for r in real if r.meta.get("user") == heldout]
        n_ok_tune = n_ok_held = n_cov_held = 0
        for k in POSITION_STATS:
            row = {"position": pos, "oxford": ox or "-", "statistic": k}
            row["sim"] = float(sdf[k].median())
            row["sim_lo"], row["sim_hi"] = float(sdf[k].quantile(0.05)), float(sdf[k].quantile(0.95))
            floor = _FLOOR[k.split("_")[0]]
            for name, group in (("tune", tune), ("heldout", held)):
                if not group:
                    row[f"real_{name}"] = row[f"{name}_lo"] = row[f"{name}_hi"] = float("nan")
                    row[f"{name}_ok"] = None
                    continue
                vals = np.array([g[k] for g in group])
                lo, hi = vals.min(), vals.max()
                pad = WIDEN * (hi - lo) + floor
                row[f"real_{name}"] = float(np.median(vals))
                row[f"{name}_lo"], row[f"{name}_hi"] = float(lo), float(hi)
                row[f"{name}_ok"] = bool(lo - pad <= row["sim"] <= hi + pad)
            # is the held-out user inside the simulated population (its 5-95 % range plus the floor)?
            rh = row["real_heldout"]
            row["heldout_covered"] = None if not held else bool(row["sim_lo"] - floor <= rh <= row["sim_hi"] + floor)
            if k in VERDICT_STATS:
                n_ok_tune += bool(row["tune_ok"])
                n_ok_held += bool(row["heldout_ok"])
                n_cov_held += bool(row["heldout_covered"])
            rows.append(row)
        if real:
            ratio = feature_spread(sims) / feature_spread(real).replace(0, np.nan)
            ratio = ratio.dropna()
            frac = float(((ratio >= 0.5) & (ratio <= 2.0)).mean())
            rows.append({"position": pos, "oxford": ox, "statistic": "feature_iqr_ratio", "sim": float(ratio.median()), "heldout_ok": None})
            rows.append({"position": pos, "oxford": ox, "statistic": "feature_iqr_within_2x", "sim": frac, "heldout_ok": None})
        n_v = len(VERDICT_STATS)
        if not real:
            verdict = "no real data"
        elif not held:
            verdict = (
                "match (tuning users only)"
                if n_ok_tune == n_v
                else ("partial (tuning users only)" if n_ok_tune >= 0.75 * n_v else "no match")
            )
        else:
            worst = min(n_ok_tune, max(n_ok_held, n_cov_held))
            verdict = "match" if worst == n_v else ("partial" if worst >= 0.75 * n_v else "no match")
        verdicts.append(
            {
                "position": pos,
                "oxford": ox or "-",
                "real_walks_tune": len(tune),
                "real_walks_heldout": len(held),
                "tune_ok": f"{n_ok_tune}/{n_v}" if tune else "-",
                "heldout_ok": f"{n_ok_held}/{n_v}" if held else "-",
                "heldout_covered": f"{n_cov_held}/{n_v}" if held else "-",
                "verdict": verdict,
            }
        )
    return pd.DataFrame(rows), pd.DataFrame(verdicts)


def main(argv: list[str] | None = None) -> int:
    """Print the realism table.

    Usage: ``python -m experiments.scripts.realism [SHARED_DATA] [--plot PNG]``
    (SHARED_DATA defaults to ../shared/data beside the repository);
    ``python -m experiments.scripts.realism --positions [SHARED_DATA] [--heldout USER] [--markdown]``
    prints the per-position table against the Oxford walks instead.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--positions" in argv:
        return _main_positions([a for a in argv if a != "--positions"])
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


def _markdown(df: pd.DataFrame) -> str:
    """A pipe table (floats with 2 decimals, NaN / None as '-')."""

    def cell(v) -> str:
        if v is None or (isinstance(v, float) and not np.isfinite(v)):
            return "-"
        if isinstance(v, float | np.floating):
            return f"{v:.2f}"
        return str(v)

    lines = ["| " + " | ".join(df.columns) + " |", "|" + "---|" * len(df.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join(lines)


def _main_positions(argv: list[str]) -> int:
    heldout, markdown = "Dario", False
    if "--heldout" in argv:
        i = argv.index("--heldout")
        if i + 1 >= len(argv) or argv[i + 1] not in OXFORD_USERS:
            print(f"--heldout needs one of {', '.join(OXFORD_USERS)}.", file=sys.stderr)
            return 2
        heldout = argv[i + 1]
        del argv[i : i + 2]
    if "--markdown" in argv:
        markdown = True
        argv.remove("--markdown")
    root = Path(argv[0]) if argv else Path(__file__).resolve().parents[2].parent / "shared" / "data"
    if not (root / "oxford-step-counter").is_dir():
        print(f"the Oxford data are not below {root}; pass the shared data folder as the argument.", file=sys.stderr)
        return 2
    tab, verdicts = position_table(root, heldout=heldout)
    cols = [
        "position",
        "oxford",
        "statistic",
        "real_tune",
        "tune_lo",
        "tune_hi",
        "real_heldout",
        "sim",
        "sim_lo",
        "sim_hi",
        "tune_ok",
        "heldout_ok",
        "heldout_covered",
    ]
    tab = tab.reindex(columns=cols)
    if markdown:
        print(_markdown(tab))
        print()
        print(_markdown(verdicts))
    else:
        with pd.option_context("display.float_format", "{:.2f}".format, "display.width", 200, "display.max_rows", 500):
            print(tab.to_string(index=False))
            print()
            print(verdicts.to_string(index=False))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
