"""Short-window variability: does the simulator get noisier like real walking when the window shrinks?

Paper 003 sec. 3.3 (Table 2) recognises the motion mode from windows of
0.5-1.5 s; a 0.5 s window holds about one step, so its 52 time-domain features
(sec. 3.2, subset ``all52``) vary more from window to window than those of a
1.5 s window. A simulator that trains or tests a classifier should reproduce
how much more. For every recording (walking part only: first to last step
peak of ``|acc|``, the cut of :mod:`experiments.scripts.realism`) and feature
this module measures

``ratio = sd(0.5 s) / sd(1.5 s)``

where ``sd(w)`` is the standard deviation of the feature across the windows
of width ``w`` (50 % overlap, :func:`gaitml.features.make_windows`) of that
recording. For a mean of independent samples it is sqrt(3) (three times
fewer samples); a feature that does not change between windows has no ratio
(NaN). Recordings:

- real, flat-held: IFSM files 1 (male, 1.77 m) and 2 (female, 1.58 m),
  paper 000's data, 50 Hz;
- real, in hand: the 12 Oxford step counter ``*_Hard_InHand_*`` recordings
  (3 users, 3 phones), read at 100 Hz, anti-alias filtered and decimated to
  50 Hz (``scipy.signal.decimate``, zero phase). The phone is tilted (gravity
  on z about 0.91 of ``|g|`` against 0.99 in IFSM), so axis-specific values are
  less comparable than IFSM's;
- simulated: :func:`gaitml.simulate.simulate_dataset` with 8 subjects, walk
  only, 50 Hz, route ``rectangle`` (4 long legs, the geometry closest to
  IFSM's 4-corridor loop), 150 s, seed 0.

How to read :func:`ratio_table`: per feature the ratios of IFSM 1, IFSM 2,
the Oxford median and the simulated median (with min-max over the walkers);
``diff_pct`` = real reference (median of the three real values) / simulated
median - 1; ``flag`` marks a difference above 30 % with all real values on the
same side of the simulated median (``REAL>SIM``: real walking gets noisier
than the simulator when the window shrinks). A ratio that agrees means the
simulator scales with window length like real walking; it does not say that
the absolute window-to-window dispersion agrees (the ratio cancels a
dispersion that is wrong by the same factor at both widths).

:func:`step_shape_table` holds what is behind it: statistics of the step
segments (peak to peak of ``|acc|``): the standard deviation across steps of
the per-step skewness and (Fisher) kurtosis of ``|acc|``, of the per-step
minimum of the forward (y) acceleration divided by std(y) over the walk, and
the coefficient of variation of the per-step peak excursion ``peak - g``.
``real_over_sim`` = median of the real values / simulated median.

Measured figures: ``experiments/scripts/README.md``.

Run ``python -m experiments.scripts.shortwin DATA_DIR [--out DIR] [--subjects N]``
(DATA_DIR: the shared data folder, e.g. ``../shared/data``); ``--out`` writes
``ratio.csv``, ``step_shape.csv`` and ``per_recording.csv``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.signal

from experiments.scripts.realism import MIN_PEAK_DISTANCE_S, PEAK_ABOVE_G_MS2, REAL_FILES, count_peaks
from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.recording import Recording

__all__ = [
    "FLAG_PCT",
    "OVERLAP",
    "WINDOWS_S",
    "main",
    "per_recording_table",
    "ratio_summary",
    "ratio_table",
    "real_walks",
    "simulated_walks",
    "step_shape_statistics",
    "step_shape_table",
    "walking_part",
    "window_dispersion",
]

#: Short and long window (s); paper 003 sec. 3.3 compares 0.5-1.5 s and chooses 1.5 s.
WINDOWS_S = (0.5, 1.5)
#: Window overlap (the package default, gaitml.features.WINDOW_OVERLAP; paper 003 does not state one).
OVERLAP = 0.5
#: Sampling rate of the comparison (IFSM's native rate; Oxford is decimated to it).
RATE_HZ = 50.0
#: A difference above this (%) with all real values on one side is flagged.
FLAG_PCT = 30.0
#: Oxford folders compared (hard floor, phone in hand) below the shared data folder.
OXFORD_DIR = "oxford-step-counter/optimisation/data"
OXFORD_PATTERN = "_Hard_InHand_"
#: Simulated walkers: route, duration and seed of the comparison.
SIM_ROUTE = "rectangle"
SIM_DURATION_S = 150.0
SIM_SEED = 0
SIM_SUBJECTS = 8
#: Groups in table order; a recording's group is ``meta['shortwin_group']``.
REAL_GROUPS = ("IFSM1", "IFSM2", "Oxford")
SIM_GROUP = "sim"
GROUP_KEY = "shortwin_group"
#: Step segments shorter than this (samples) are skipped.
MIN_STEP_SAMPLES = 8
#: Step-shape statistics, in table order.
STEP_STATS = ("step_skew_sd", "step_kurt_sd", "step_ymin_sd_over_ystd", "step_peak_cv")


def walking_part(recording: Recording) -> Recording:
    """The recording from its first to its last step peak of ``|acc|`` (as in the realism check)."""
    pk = count_peaks(recording, height_above_g_ms2=PEAK_ABOVE_G_MS2, min_distance_s=MIN_PEAK_DISTANCE_S)
    return recording.slice(int(pk[0]), int(pk[-1]) + 1) if len(pk) > 2 else recording


def window_dispersion(
    recording: Recording,
    *,
    windows_s: tuple[float, float] = WINDOWS_S,
    overlap: float = OVERLAP,
    subset: str = "all52",
    walk_only: bool = True,
) -> pd.DataFrame:
    """Across-window standard deviation of every feature at a short and a long window, and their ratio.

    Parameters
    ----------
    recording : Recording
    windows_s : (short, long)
        Window lengths in s.
    overlap : float
        Window overlap fraction.
    subset : str
        Feature subset of :func:`gaitml.features.extract_features`.
    walk_only : bool
        Cut to :func:`walking_part` first.

    Returns
    -------
    DataFrame
        Index: feature names; columns ``sd_short``, ``sd_long``, ``ratio``
        (``sd_short / sd_long``; NaN where the feature does not change between
        long windows: sd below 1e-9 x (1 + |mean|)).
    """
    from gaitml.features import extract_features, make_windows

    short_s, long_s = windows_s
    if not 0 < short_s < long_s:
        raise InputError(f"`windows_s` must be (short, long) with 0 < short < long, got {windows_s}.")
    rec = walking_part(recording) if walk_only else recording
    sd, mean = {}, {}
    for w in (short_s, long_s):
        win = make_windows(rec, w, overlap, min_label_fraction=0.0)
        if len(win) < 3:
            raise InputError(f"{rec.name}: {len(win)} windows of {w:g} s in {rec.duration_s:.1f} s of walking; at least 3 are needed.")
        feats = extract_features(rec, win, subset=subset)
        sd[w], mean[w] = feats.std(ddof=0), feats.mean()
    flat = sd[long_s] <= 1e-9 * (1.0 + mean[long_s].abs())
    ratio = (sd[short_s] / sd[long_s]).where(~flat)
    return pd.DataFrame({"sd_short": sd[short_s], "sd_long": sd[long_s], "ratio": ratio})


def step_shape_statistics(recording: Recording, *, walk_only: bool = True) -> dict[str, float]:
    """Step-to-step variability of the waveform of the step segments (peak to peak of ``|acc|``).

    Returns ``step_skew_sd`` and ``step_kurt_sd`` (sd across steps of the skewness
    and Fisher kurtosis of ``|acc|`` in the step), ``step_ymin_sd_over_ystd`` (sd of
    the per-step minimum of acc y, the forward axis of a flat-held phone, over the
    std of acc y in the walk), ``step_peak_cv`` (sd / mean of the peak excursion
    ``|acc| - g`` at the step peaks) and ``n_steps``. Peaks: :func:`count_peaks`
    with the realism settings (0.7 m/s^2 above g, 0.3 s apart).
    """
    rec = walking_part(recording) if walk_only else recording
    pk = count_peaks(rec, height_above_g_ms2=PEAK_ABOVE_G_MS2, min_distance_s=MIN_PEAK_DISTANCE_S)
    keep = np.diff(pk) >= MIN_STEP_SAMPLES
    if len(pk) < 2 or keep.sum() < 3:
        raise InputError(f"{rec.name}: {int(keep.sum()) if len(pk) > 1 else 0} step segments found; at least 3 are needed (is it a walk?).")
    mag = np.linalg.norm(rec.acc, axis=1)
    y = rec.acc[:, 1]
    # moments of every segment [pk[i], pk[i+1]) at once (segments are contiguous)
    seg, n = mag[pk[0] : pk[-1]], np.diff(pk)
    starts = pk[:-1] - pk[0]
    dev = seg - np.repeat(np.add.reduceat(seg, starts) / n, n)
    m2, m3, m4 = (np.add.reduceat(dev**k, starts)[keep] / n[keep] for k in (2, 3, 4))
    skew = m3 / m2**1.5  # population skewness (scipy.stats.skew, bias=True)
    kurt = m4 / m2**2 - 3.0  # Fisher kurtosis (scipy.stats.kurtosis, bias=True)
    ymin = np.minimum.reduceat(y[pk[0] : pk[-1]], starts)[keep]
    excursion = mag[pk[:-1][keep]] - GRAVITY_MS2
    return {
        "step_skew_sd": float(skew.std()),
        "step_kurt_sd": float(kurt.std()),
        "step_ymin_sd_over_ystd": float(ymin.std() / y.std()),
        "step_peak_cv": float(excursion.std() / excursion.mean()),
        "n_steps": int(keep.sum()),
    }


def _tag(recording: Recording, group: str) -> Recording:
    return recording.replace(meta={**recording.meta, GROUP_KEY: group})


def real_walks(data_dir: str | Path, *, oxford: bool = True) -> list[Recording]:
    """The real walks at 50 Hz: IFSM files 1 and 2, then (``oxford=True``) the Oxford hard-floor in-hand ones.

    ``meta['shortwin_group']`` is ``IFSM1``, ``IFSM2`` or ``Oxford``. Raises
    :class:`InputError` when a file is missing below ``data_dir``.
    """
    from gaitml.io import read_recording
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder

    root = Path(data_dir)
    hint = "pass the shared data folder (e.g. ../shared/data) as DATA_DIR"
    out = []
    for group, rel in zip(REAL_GROUPS[:2], REAL_FILES, strict=True):
        if not (root / rel).is_file():
            raise InputError(f"shortwin needs {rel} below {root}, which is missing; {hint}.")
        out.append(_tag(read_recording(root / rel), group))
    if oxford:
        folders = [d for d in list_oxford_folders(root / OXFORD_DIR) if OXFORD_PATTERN in d.name]
        if not folders:
            raise InputError(f"shortwin needs the Oxford *{OXFORD_PATTERN}* folders in {root / OXFORD_DIR}, none found; {hint}.")
        for d in folders:
            r = read_oxford_folder(d, sampling_rate_hz=2 * RATE_HZ)
            acc = scipy.signal.decimate(r.acc, 2, axis=0, zero_phase=True)  # anti-alias (Chebyshev I), 100 -> 50 Hz
            out.append(Recording.from_arrays(acc, RATE_HZ, meta={**r.meta, GROUP_KEY: "Oxford"}))
    return out


def simulated_walks(n_subjects: int = SIM_SUBJECTS, *, seed: int = SIM_SEED) -> list[Recording]:
    """``n_subjects`` simulated flat-held walks (walk only, 50 Hz, route ``rectangle``, 150 s)."""
    from gaitml.simulate.dataset import simulate_dataset

    if n_subjects < 1:
        raise InputError(f"`n_subjects` must be >= 1, got {n_subjects}.")
    recs = simulate_dataset(
        n_subjects=n_subjects, modes=("walk",), sampling_rate_hz=RATE_HZ, seed=seed, route=SIM_ROUTE, duration_s=SIM_DURATION_S
    )
    return [_tag(r, SIM_GROUP) for r in recs]


def _group(recording: Recording) -> str:
    g = recording.meta.get(GROUP_KEY)
    if g not in (*REAL_GROUPS, SIM_GROUP):
        raise InputError(
            f"{recording.name}: meta['{GROUP_KEY}'] = {g!r}; use real_walks() / simulated_walks() or one of {(*REAL_GROUPS, SIM_GROUP)}."
        )
    return g


def per_recording_table(recordings: Sequence[Recording]) -> pd.DataFrame:
    """Long table of :func:`window_dispersion`: ``group, recording, feature, sd_short, sd_long, ratio``."""
    frames = []
    for rec in recordings:
        d = window_dispersion(rec).rename_axis("feature").reset_index()
        d.insert(0, "recording", rec.name)
        d.insert(0, "group", _group(rec))
        frames.append(d)
    return pd.concat(frames, ignore_index=True)


def _real_vs_sim(values: pd.DataFrame, groups: pd.Series) -> pd.DataFrame:
    """Columns IFSM1, IFSM2, oxford_median, sim_median, sim_min, sim_max from a (row x recording) table."""
    cols = {g: [c for c in values.columns if groups[c] == g] for g in (*REAL_GROUPS, SIM_GROUP)}
    if not cols[SIM_GROUP]:
        raise InputError("no simulated recording (group 'sim') in the input; add simulated_walks().")
    if not any(cols[g] for g in REAL_GROUPS):
        raise InputError("no real recording in the input; add real_walks(DATA_DIR).")
    nan = pd.Series(np.nan, index=values.index)
    t = pd.DataFrame(index=values.index)
    for g in REAL_GROUPS[:2]:
        t[g] = values[cols[g]].median(axis=1) if cols[g] else nan
    t["oxford_median"] = values[cols["Oxford"]].median(axis=1) if cols["Oxford"] else nan
    sim = values[cols[SIM_GROUP]]
    t["sim_median"], t["sim_min"], t["sim_max"] = sim.median(axis=1), sim.min(axis=1), sim.max(axis=1)
    return t


def ratio_table(per_recording: pd.DataFrame, *, flag_pct: float = FLAG_PCT) -> pd.DataFrame:
    """Real against simulated ``sd(0.5 s) / sd(1.5 s)`` per feature (see the module docstring).

    Parameters
    ----------
    per_recording : DataFrame
        :func:`per_recording_table` (columns ``group, recording, feature, ratio``).
    flag_pct : float
        Flag threshold on ``|diff_pct|``.

    Returns
    -------
    DataFrame
        Index: feature (input order); columns ``IFSM1, IFSM2, oxford_median, sim_median,
        sim_min, sim_max, real_ref`` (median of the real columns present), ``diff_pct``
        (``100 * (real_ref / sim_median - 1)``) and ``flag`` (``REAL>SIM`` / ``REAL<SIM``
        when ``|diff_pct| > flag_pct`` and every real column present lies on that side of
        the simulated median, else empty). A group without recordings is NaN and left out.
    """
    features = pd.unique(per_recording["feature"])
    values = per_recording.pivot(index="feature", columns="recording", values="ratio").reindex(features)
    groups = per_recording.drop_duplicates("recording").set_index("recording")["group"]
    t = _real_vs_sim(values, groups)
    real = t[["IFSM1", "IFSM2", "oxford_median"]]
    t["real_ref"] = real.median(axis=1)
    t["diff_pct"] = 100.0 * (t["real_ref"] / t["sim_median"] - 1.0)
    side = np.sign(real.sub(t["sim_median"], axis=0))
    up = (side.eq(1) | real.isna()).all(axis=1)
    down = (side.eq(-1) | real.isna()).all(axis=1)
    big = t["diff_pct"].abs() > flag_pct
    t["flag"] = np.where(big & up & (t["diff_pct"] > 0), "REAL>SIM", np.where(big & down & (t["diff_pct"] < 0), "REAL<SIM", ""))
    return t


def ratio_summary(table: pd.DataFrame, *, flag_pct: float = FLAG_PCT) -> dict:
    """Counts of :func:`ratio_table`: ``n_features`` (with a difference), ``n_within``, ``n_real_gt_sim``, ``n_real_lt_sim``, ``median_diff_pct``."""
    d = table["diff_pct"].dropna()
    return {
        "n_features": len(d),
        "n_within": int((d.abs() <= flag_pct).sum()),
        "n_real_gt_sim": int((table["flag"] == "REAL>SIM").sum()),
        "n_real_lt_sim": int((table["flag"] == "REAL<SIM").sum()),
        "median_diff_pct": float(d.median()) if len(d) else float("nan"),
    }


def step_shape_table(recordings: Sequence[Recording]) -> pd.DataFrame:
    """Rows: :data:`STEP_STATS`; columns ``IFSM1, IFSM2, oxford_median, sim_median, sim_min, sim_max, real_over_sim``.

    ``real_over_sim`` is the median of the real columns present over the simulated median.
    """
    stats = {rec.name: step_shape_statistics(rec) for rec in recordings}
    values = pd.DataFrame(stats).loc[list(STEP_STATS)].astype(float)
    groups = pd.Series({rec.name: _group(rec) for rec in recordings})
    t = _real_vs_sim(values, groups)
    t["real_over_sim"] = t[["IFSM1", "IFSM2", "oxford_median"]].median(axis=1) / t["sim_median"]
    return t.rename_axis("statistic")


def _format_ratio(table: pd.DataFrame) -> str:
    from gaitml.features import feature_specs

    codes = {s.name: s.code for s in feature_specs("all52")}
    shown = pd.DataFrame(
        {
            "F": [codes.get(f, "") for f in table.index],
            "IFSM1": table["IFSM1"].map("{:.2f}".format),
            "IFSM2": table["IFSM2"].map("{:.2f}".format),
            "Oxford": table["oxford_median"].map("{:.2f}".format),
            "sim (min-max)": [f"{m:.2f} ({a:.2f}-{b:.2f})" for m, a, b in table[["sim_median", "sim_min", "sim_max"]].to_numpy()],
            "diff %": table["diff_pct"].map("{:+.0f}".format),
            "flag": table["flag"],
        },
        index=table.index.rename("feature"),
    )
    return shown.to_string()


def main(argv: list[str] | None = None) -> int:
    """Command line: ``python -m experiments.scripts.shortwin DATA_DIR [--out DIR] [--subjects N]``."""
    from gaitml.io import write_csv

    p = argparse.ArgumentParser(prog="python -m experiments.scripts.shortwin", description=__doc__.splitlines()[0])
    p.add_argument("data_dir", metavar="DATA_DIR", help="the shared data folder (e.g. ../shared/data)")
    p.add_argument("--out", help="write ratio.csv, step_shape.csv and per_recording.csv into this folder")
    p.add_argument("--subjects", type=int, default=SIM_SUBJECTS, help=f"simulated walkers (default {SIM_SUBJECTS}, seed {SIM_SEED})")
    a = p.parse_args(argv)
    try:
        real = real_walks(a.data_dir)
        recs = real + simulated_walks(a.subjects)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    per_rec = per_recording_table(recs)
    ratios = ratio_table(per_rec)
    summary = ratio_summary(ratios)
    shape = step_shape_table(recs)
    n_ox = sum(r.meta[GROUP_KEY] == "Oxford" for r in real)
    print(
        f"sd(0.5 s) / sd(1.5 s) across windows (overlap {OVERLAP:g}): IFSM 1, IFSM 2, Oxford hard/in-hand median "
        f"(n={n_ox}), simulated median (n={a.subjects}, route {SIM_ROUTE}, seed {SIM_SEED})"
    )
    print(_format_ratio(ratios))
    print(
        f"\nratio: {summary['n_within']}/{summary['n_features']} features within +/-{FLAG_PCT:g} %, "
        f"flags REAL>SIM {summary['n_real_gt_sim']} / REAL<SIM {summary['n_real_lt_sim']}, "
        f"median difference {summary['median_diff_pct']:+.0f} %"
    )
    print("\nper-step shape statistics (step = peak to peak of |acc|)")
    with pd.option_context("display.float_format", "{:.3f}".format, "display.width", 160):
        print(shape.to_string())
    if a.out:
        out = Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        write_csv(out / "ratio.csv", ratios, index=True, index_label="feature")
        write_csv(out / "step_shape.csv", shape, index=True)
        write_csv(out / "per_recording.csv", per_rec)
        print(f"tables: {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
