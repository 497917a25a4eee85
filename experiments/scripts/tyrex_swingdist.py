"""Why the calibrated walk line covers only ~0.78 of the distance in tyrex Swinging (issue 27): a diagnosis, then candidate inputs held out.

``python -m experiments.scripts.tyrex_swingdist [--data ../shared/data] [--steplen-cache FILE] [--cache FILE] [--csv FILE] [--plot DIR]``
from the repository root. ``--steplen-cache`` is the per-recording pickle of
:mod:`experiments.scripts.tyrex_steplen` (``--cache``; its steps, step-length samples and runs of
``gaitml pdr`` are reused, so both studies score the same steps); without it they are recomputed.
``--cache`` keeps this script's own per-recording extras (command-line counts, gyroscope per step).

**Diagnosis** (nothing fitted on the person scored; the walk line is the ``cal`` line of
``tyrex_steplen``: paper 003 eq. 12 fitted on the other two people's walking recordings, AR left out).
For every walking recording (Texting, Phoning, Swinging, FrontPocket, BackPocket; 90):

- the step counts of the three paths that could differ: ``gaitml steps DIR --json`` and ``gaitml pdr
  DIR --json`` (run in-process through :func:`gaitml.cli.main`, the whole recording as the command
  line reads it), the steps the PDR study scored (the default detector on the longest stretch between
  sensor gaps, inside the span the distance is scored on) and the motion-capture reference of
  :func:`experiments.scripts.tyrex_steps.mocap_steps` in the same span;
- the split of the distance ratio ``PDR distance / true distance`` into three factors:
  ``coverage`` = true length summed over the steps that have one (:func:`gaitml.pdr.calibrate.true_step_lengths`)
  / the true distance (what pauses, missed steps and truth gaps leave out), ``bias`` = the line's lengths
  / the true lengths on those same steps, and ``extra`` = all steps' lengths / those steps' lengths
  (steps with no true length still get one); ``ratio = coverage x bias x extra``;
- the true step length per step and per recording (body distance / motion-capture steps), the step
  inputs of eq. 12 (cadence, variance of |acc|), and the truth's own sensitivity to the body track's
  low-pass (path length at 0.3 and 0.2 Hz over that at the default 0.5 Hz).

**Candidate inputs** (measured after the diagnosis pointed at the step length, answer (c) of the
task). Each is a linear model fitted by least squares on the other two people's walking steps with a
true length, exactly as eq. 12 is (``cal``), and scored on the left-out person's recordings by the
same distance ratio (sum of the predicted lengths of every step in the scored span / true distance;
this sum is the ``gaitml pdr`` distance up to the partial step at the span's ends: checked against the
study's own ``fwd/cal`` ratio, printed). Inputs per step:

- ``eq12``: ``1, f, var(|acc|)`` (the library's line, the reference row);
- ``f``: ``1, f`` (variance dropped: it is the input that differs most between carrying positions);
- ``f+range4``: ``1, f, (a_max - a_min)^(1/4)`` (Weinberg's compressed |acc| range, eq. 13, in place
  of the variance);
- ``f+gyro``: ``1, f, RMS |w|`` (the gyroscope's band-passed 0.3-4 Hz angular-rate magnitude over the
  step, rad/s: the swing of the limb or trunk that carries the phone, which grows with the step).

**Adoption rule, fixed before the candidates were measured** (held out, each person left out once,
NoDist medians over the 9 recordings of a motion): a candidate is adopted only if (1) Swinging's
distance ratio is within 0.9-1.1, (2) in each of the other four walking motions its ratio is within
0.9-1.1 or no further from 1 than ``eq12``'s by more than 0.02, and (3) Swinging's median per
left-out person (all its recordings) moves toward 1 against ``eq12`` for at least two of the three
people. The library's default step length is not changed either way (task); an adopted input would
be a documented option.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_pdr import _truth_on_recording, load_tyrex, md
from experiments.scripts.tyrex_steplen import WALK_MOTIONS, fit_fold, prepare

__all__ = ["CANDIDATES", "adoption", "candidate_features", "decompose", "main"]

#: the candidate inputs (besides the intercept) of the linear step-length line (module docstring)
CANDIDATES = {
    "eq12": ("freq_hz", "var_ms2sq"),
    "f": ("freq_hz",),
    "f+range4": ("freq_hz", "range4"),
    "f+gyro": ("freq_hz", "gyro_rms_rads"),
}
#: band of the gyroscope statistic (Hz): adaptive's swing band (gaitml.steps.adaptive), the limb's swing
GYRO_BAND_HZ = (0.3, 4.0)
#: the body-track cutoffs whose path lengths are compared with the default 0.5 Hz (the truth's sensitivity)
CUTOFFS_HZ = (0.3, 0.2)
#: adoption rule (module docstring): the target band, and the slack a non-Swinging motion may lose
TARGET = (0.9, 1.1)
SLACK = 0.02


def _cli_counts(folder: Path) -> dict:
    """``gaitml steps DIR --json`` and ``gaitml pdr DIR --json`` run in-process: their step counts."""
    from gaitml.cli import main as cli

    out = {}
    for cmd in ("steps", "pdr"):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(io.StringIO()):
            rc = cli([cmd, str(folder), "--json"])
        out[f"n_cli_{cmd}"] = int(json.loads(buf.getvalue())["n_steps"]) if rc == 0 else -1
    return out


def candidate_features(rec, steps: pd.DataFrame) -> pd.DataFrame:
    """Per step: ``range4`` = (a_max - a_min)^(1/4) of the preprocessed |acc| and ``gyro_rms_rads`` (module docstring)."""
    from scipy.signal import butter, sosfiltfilt

    from gaitml.pdr.step_length import step_length_features

    feats = step_length_features(rec.acc, steps, rec.sampling_rate_hz).reset_index(drop=True)
    sos = butter(2, list(GYRO_BAND_HZ), btype="bandpass", fs=rec.sampling_rate_hz, output="sos")
    w = np.linalg.norm(sosfiltfilt(sos, rec.gyr, axis=0), axis=1)
    c2 = np.concatenate([[0.0], np.cumsum(w * w)])
    s, e = steps["start"].to_numpy(np.int64), steps["end"].to_numpy(np.int64)
    return pd.DataFrame(
        {
            "range4": np.maximum(feats["a_max_ms2"] - feats["a_min_ms2"], 0.0).to_numpy() ** 0.25,
            "gyro_rms_rads": np.sqrt((c2[e] - c2[s]) / np.maximum(e - s, 1)),
        }
    )


def extras(item) -> dict:
    """The per-recording inputs the study of ``tyrex_steplen`` does not keep."""
    from experiments.scripts.tyrex_steps import mocap_steps
    from gaitml.consts import DEFAULT_STEP_DETECTOR
    from gaitml.signal import body_track
    from gaitml.steps import get_detector

    rec = item["recording"]
    table = get_detector(DEFAULT_STEP_DETECTOR).detect(rec).steps_
    table = table.sort_values(table.attrs.get("event", "t_peak_s"), kind="stable").reset_index(drop=True)
    ref = mocap_steps(item["truth"], item["motion"])
    tt, xy = _truth_on_recording(item)
    return {
        **_cli_counts(Path(rec.meta["source"]) if Path(rec.meta["source"]).is_dir() else Path(rec.meta["source"]).parent),
        "cand": candidate_features(rec, table),
        "ref_t": ref["t_s"] - rec.meta["t0_original_s"],
        "ref_per_event": ref["steps_per_event"],
        "tracks": {c: body_track(tt, xy, cutoff_hz=c) for c in (0.5, *CUTOFFS_HZ)},
        "t_truth": tt,
    }


def _path(xy: np.ndarray) -> float:
    return float(np.sum(np.linalg.norm(np.diff(xy, axis=0), axis=1)))


def _fit(samples: pd.DataFrame, cols) -> np.ndarray:
    ok = np.isfinite(samples["true_length_m"]).to_numpy() & np.isfinite(samples[list(cols)].to_numpy()).all(axis=1)
    X = np.column_stack([np.ones(ok.sum()), *(samples.loc[ok, c] for c in cols)])
    coef, *_ = np.linalg.lstsq(X, samples.loc[ok, "true_length_m"].to_numpy(), rcond=None)
    return coef


def _predict(samples: pd.DataFrame, cols, coef) -> np.ndarray:
    X = np.column_stack([np.ones(len(samples)), *(samples[c] for c in cols)])
    return np.clip(X @ coef, 0.0, None)


def decompose(samples: pd.DataFrame, pred: np.ndarray, true_m: float) -> dict:
    """``ratio = coverage x bias x extra`` over the scored span's steps (module docstring)."""
    fin = np.isfinite(samples["true_length_m"].to_numpy())
    true_steps = float(samples["true_length_m"].to_numpy()[fin].sum())
    pred_fin = float(pred[fin].sum())
    return {
        "ratio": float(pred.sum()) / true_m,
        "coverage": true_steps / true_m,
        "bias": pred_fin / true_steps if true_steps > 0 else float("nan"),
        "extra": float(pred.sum()) / pred_fin if pred_fin > 0 else float("nan"),
    }


def build(items, preps, ext, *, max_fit_hz: float | None = None) -> tuple[pd.DataFrame, pd.DataFrame, dict]:
    """Per-recording rows (held out and in sample) and the per-step table with the person's held-out prediction.

    ``max_fit_hz``: fit the candidate lines (not the library's) only on training steps below this cadence.
    """
    from gaitml.evaluation.trajectory import walked_distance_ratio

    people = sorted({it["subject"] for it in items})
    samples_all = []
    for it, pr, ex in zip(items, preps, ext, strict=True):
        if it["motion"] in WALK_MOTIONS:
            s = pr["samples"].reset_index(drop=True)
            samples_all.append(pd.concat([s, ex["cand"]], axis=1).assign(subject=it["subject"], motion=it["motion"]))
    train = pd.concat(samples_all, ignore_index=True)
    if max_fit_hz is not None:
        train = train[train["freq_hz"] < max_fit_hz]
    fits = {
        fold: {name: _fit(train[train["subject"].isin([p for p in people if p != fold])], cols) for name, cols in CANDIDATES.items()}
        for fold in [*people, "all"]
    }
    fits_lib = {fold: fit_fold(preps, items, [p for p in people if p != fold])["cal"] for fold in [*people, "all"]}
    rows, steps = [], []
    k = 0
    for it, pr, ex in zip(items, preps, ext, strict=True):
        if it["motion"] not in WALK_MOTIONS:
            continue
        s = samples_all[k]
        k += 1
        run = pr["runs"]["fwd"]
        tt, xy = _truth_on_recording(it)
        span = walked_distance_ratio(np.r_[0.0, run["t_step"]], np.zeros((len(run["t_step"]) + 1, 2)), tt, xy)
        t0, t1, true_m = span["t0_s"], span["t1_s"], span["true_m"]
        ins = ((s["t_s"] >= t0) & (s["t_s"] <= t1)).to_numpy()
        si = s[ins].reset_index(drop=True)
        fin = np.isfinite(si["true_length_m"].to_numpy())
        n_ref = int(ex["ref_per_event"] * np.sum((ex["ref_t"] >= t0) & (ex["ref_t"] <= t1)))
        inside_truth = (ex["t_truth"] >= t0) & (ex["t_truth"] <= t1)
        base = {
            "file": it["file"],
            "subject": it["subject"],
            "phone": it["phone"],
            "motion": it["motion"],
            "disturbance": it["disturbance"],
            "span_s": t1 - t0,
            "true_m": true_m,
            "n_cli_steps": ex["n_cli_steps"],
            "n_cli_pdr": ex["n_cli_pdr"],
            "n_pdr_stretch": len(s),
            "n_pdr": int(ins.sum()),
            "n_mocap": n_ref,
            "cadence_det_hz": ins.sum() / (t1 - t0),
            "cadence_mocap_hz": n_ref / (t1 - t0),
            "f_med_hz": float(si["freq_hz"].median()),
            "var_med": float(si["var_ms2sq"].median()),
            "gyro_med": float(si["gyro_rms_rads"].median()),
            "true_step_med_m": float(si["true_length_m"][fin].median()),
            "true_m_per_mocap_step": true_m / max(n_ref, 1),
            "speed_ms": true_m / (t1 - t0),
            **{f"truth_{c:g}hz_over_0.5": _path(ex["tracks"][c][inside_truth]) / true_m for c in CUTOFFS_HZ},
        }
        for fold in (it["subject"], "all"):
            row = {**base, "fold": fold, "held_out": fold != "all"}
            lib = fits_lib[fold].predict(si[["freq_hz", "var_ms2sq", "a_max_ms2", "a_min_ms2"]], np.full(len(si), "walk"))
            row.update({f"lib_{k_}": v for k_, v in decompose(si, lib, true_m).items()})
            for name, cols in CANDIDATES.items():
                pred = _predict(si, cols, fits[fold][name])
                row.update({f"{name}_{k_}": v for k_, v in decompose(si, pred, true_m).items()})
                if fold != "all" and name == "eq12":
                    steps.append(si.assign(pred_eq12=pred, disturbance=it["disturbance"]))
            rows.append(row)
    return pd.DataFrame(rows), pd.concat(steps, ignore_index=True), fits


def adoption(table: pd.DataFrame) -> pd.DataFrame:
    """The rule of the module docstring, per candidate (held out)."""
    held = table[table["held_out"]]
    nd = held[held["disturbance"] == "NoDist"].groupby("motion")
    per = held[held["motion"] == "Swinging"].groupby("subject")
    out = {}
    for name in CANDIDATES:
        r, r0 = nd[f"{name}_ratio"].median(), nd["eq12_ratio"].median()
        c1 = TARGET[0] <= r["Swinging"] <= TARGET[1]
        others = [m for m in WALK_MOTIONS if m != "Swinging"]
        bad = [m for m in others if not (TARGET[0] <= r[m] <= TARGET[1]) and abs(r[m] - 1) > abs(r0[m] - 1) + SLACK]
        p, p0 = per[f"{name}_ratio"].median(), per["eq12_ratio"].median()
        toward = int(np.sum(np.abs(p - 1) < np.abs(p0 - 1)))
        out[name] = {
            **{f"{m} (NoDist median)": f"{r[m]:.3f}" for m in WALK_MOTIONS},
            "Swinging per left-out person": ", ".join(f"{s} {p[s]:.2f}" for s in p.index),
            "(1) Swinging 0.9-1.1": "yes" if c1 else "no",
            "(2) others in band or within 0.02 of eq12": "yes" if not bad else "no (" + ", ".join(bad) + ")",
            "(3) Swinging nearer 1 for >= 2 people": f"{'yes' if toward >= 2 else 'no'} ({toward})",
            "adopted": "yes" if c1 and not bad and toward >= 2 else "no",
        }
    return pd.DataFrame(out)


#: walking-speed bands (m/s, the recording's true distance over its scored span) of the bias-by-speed table
SPEED_BANDS_MS = (0.0, 0.6, 0.75, 0.9, 1.2)


def speed_bands(held: pd.DataFrame, column: str) -> pd.DataFrame:
    """Median of ``column`` per motion and walking-speed band, with the number of recordings: 'median (n)'."""
    band = pd.cut(held["speed_ms"], list(SPEED_BANDS_MS))
    g = held.assign(band=band).groupby(["band", "motion"], observed=True)[column]
    med, n = g.median().unstack(), g.count().unstack()
    out = pd.DataFrame(index=med.index, columns=[m for m in WALK_MOTIONS if m in med.columns], dtype=object)
    for b in out.index:
        for m in out.columns:
            out.loc[b, m] = f"{med.loc[b, m]:.2f} ({int(n.loc[b, m])})" if np.isfinite(med.loc[b, m]) else "-"
    out.index = [f"{iv.left:g}-{iv.right:g} m/s" for iv in out.index]
    return out


def _plot(steps: pd.DataFrame, fits: dict, held: pd.DataFrame, out: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(1, 3, figsize=(17, 4.5))
    colours = dict(zip(WALK_MOTIONS, ("C0", "C1", "C3", "C2", "C4"), strict=True))
    st = steps[np.isfinite(steps["true_length_m"])]
    for m in WALK_MOTIONS:
        g = st[st["motion"] == m]
        axes[0].scatter(g["freq_hz"], g["true_length_m"], s=2, alpha=0.15, color=colours[m])
        med = g.groupby(pd.cut(g["freq_hz"], np.arange(0.8, 2.6, 0.1)), observed=True)["true_length_m"].median()
        axes[0].plot([iv.mid for iv in med.index], med.to_numpy(), color=colours[m], lw=2, label=f"{m} (median per 0.1 Hz)")
        axes[1].hist(g["pred_eq12"] / g["true_length_m"], bins=np.linspace(0, 2.5, 60), histtype="step", color=colours[m], label=m)
    f = np.linspace(0.8, 2.5, 20)
    a, b, _ = fits["all"]["eq12"]
    axes[0].plot(f, a + b * f, "k--", label="eq. 12 in sample at var = 0")
    axes[0].set(xlabel="step frequency f (Hz, the detector's)", ylabel="true step length (m, body track)", ylim=(0, 1.3))
    axes[0].legend(fontsize=7)
    axes[1].set(xlabel="held-out eq. 12 length / true length, per step", ylabel="steps")
    axes[1].legend(fontsize=7)
    for m in WALK_MOTIONS:
        g = held[held["motion"] == m]
        for dist, marker in (("NoDist", "o"), ("Dist", "x")):
            gd = g[g["disturbance"] == dist]
            axes[2].scatter(gd["speed_ms"], gd["lib_bias"], color=colours[m], marker=marker, label=f"{m} {dist}")
    axes[2].axhline(1.0, color="k", lw=0.5)
    axes[2].set(xlabel="walking speed of the recording (m/s)", ylabel="held-out eq. 12 lengths / true lengths (recording)")
    axes[2].legend(fontsize=6, ncol=2)
    fig.tight_layout()
    path = out / "tyrex-swingdist.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_swingdist", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--steplen-cache", metavar="FILE", help="tyrex_steplen's --cache pickle (its steps and runs are reused)")
    p.add_argument("--cache", metavar="FILE", help="pickle of this script's per-recording extras: read if present, else written")
    p.add_argument("--csv", metavar="FILE", help="write the per-recording table")
    p.add_argument(
        "--max-fit-hz",
        type=float,
        metavar="HZ",
        help="post hoc (chosen after the plot): fit the candidate lines only on steps below this cadence (e.g. 2.0: the octave errors)",
    )
    p.add_argument("--plot", metavar="DIR", help="write tyrex-swingdist.png (true length against cadence; prediction / truth)")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    items = load_tyrex(Path(args.data))
    if args.steplen_cache and Path(args.steplen_cache).exists():
        with open(args.steplen_cache, "rb") as fh:
            preps = pickle.load(fh)
        if [q["file"] for q in preps] != [it["file"] for it in items]:
            raise SystemExit(f"error: {args.steplen_cache} holds other recordings; rerun tyrex_steplen with --cache.")
    else:
        from gaitml.models import load_model

        model = load_model("models/demo")
        preps = [prepare(it, model) for it in items]
    if args.cache and Path(args.cache).exists():
        with open(args.cache, "rb") as fh:
            ext = pickle.load(fh)
    else:
        ext = []
        for i, it in enumerate(items):
            ext.append(extras(it) if it["motion"] in WALK_MOTIONS else None)
            if (i + 1) % 20 == 0:
                print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        if args.cache:
            with open(args.cache, "wb") as fh:
                pickle.dump(ext, fh)
    table, steps, fits = build(items, preps, ext, max_fit_hz=args.max_fit_hz)
    if args.csv:
        table.to_csv(args.csv, index=False)
    held = table[table["held_out"]]
    nd = held[held["disturbance"] == "NoDist"]
    ins = table[~table["held_out"] & (table["disturbance"] == "NoDist")]
    order = [m for m in WALK_MOTIONS]

    def med(df, cols, by="motion"):
        return df.groupby(by)[cols].median().reindex(order if by == "motion" else None)

    lines = ["### step counts per recording: the command line, the PDR study and the motion capture (NoDist medians; sums over all 18)"]
    cnt = ["n_cli_steps", "n_cli_pdr", "n_pdr_stretch", "n_pdr", "n_mocap", "cadence_det_hz", "cadence_mocap_hz"]
    sums = held.groupby("motion")[["n_cli_steps", "n_cli_pdr", "n_pdr", "n_mocap"]].sum().reindex(order)
    read = held[held["n_cli_steps"] >= 0]
    same = read.groupby("motion").apply(lambda g: int((g["n_cli_steps"] == g["n_cli_pdr"]).sum()), include_groups=False).reindex(order)
    same2 = read.groupby("motion").apply(lambda g: int((g["n_cli_steps"] == g["n_pdr_stretch"]).sum()), include_groups=False).reindex(order)
    lines += [
        md(med(nd, cnt), "{:.2f}"),
        "",
        "sums (all 18 recordings; a command line refusing a recording counts -1): ",
        md(
            sums.assign(readable=read.groupby("motion").size().reindex(order), cli_steps_eq_cli_pdr=same, cli_steps_eq_study_stretch=same2),
            "{:.0f}",
        ),
        "",
        "refused by the command line: " + (", ".join(held.loc[held["n_cli_steps"] < 0, "file"]) or "none"),
        "",
    ]
    lines += [
        "### distance ratio = coverage x bias x extra, the library's eq. 12 line, NoDist medians: held out / in sample",
    ]
    dec = pd.DataFrame(
        {
            f: [f"{a:.3f} / {b:.3f}" for a, b in zip(med(nd, [f"lib_{f}"])[f"lib_{f}"], med(ins, [f"lib_{f}"])[f"lib_{f}"], strict=True)]
            for f in ("ratio", "coverage", "bias", "extra")
        },
        index=order,
    )
    lines += [md(dec), ""]
    lines += ["### per left-out person (median over all their recordings of the motion): library line, held out"]
    pp = held.groupby(["motion", "subject"])[
        [
            "n_pdr",
            "n_mocap",
            "f_med_hz",
            "var_med",
            "gyro_med",
            "speed_ms",
            "true_step_med_m",
            "true_m_per_mocap_step",
            "lib_coverage",
            "lib_bias",
            "lib_ratio",
        ]
    ].median()
    lines += [md(pp.reset_index().set_index(["motion", "subject"]), "{:.3f}"), ""]
    lines += ["### the walker and the truth, NoDist medians"]
    lines += [
        md(
            med(
                nd,
                [
                    "speed_ms",
                    "f_med_hz",
                    "var_med",
                    "gyro_med",
                    "true_step_med_m",
                    "true_m_per_mocap_step",
                    *(f"truth_{c:g}hz_over_0.5" for c in CUTOFFS_HZ),
                ],
            ),
            "{:.3f}",
        ),
        "",
    ]
    lines += [
        "### the line's bias (its lengths / true lengths, steps with a true length) by the recording's walking speed, held out, "
        "all recordings: median (recordings)"
    ]
    lines += [md(speed_bands(held, "lib_bias")), ""]
    lines += ["correlation over the recordings of speed with the line's bias / with the true m per motion-capture step / with the cadence:"]
    lines += [
        "; ".join(
            f"{m} {np.corrcoef(g['speed_ms'], g['lib_bias'])[0, 1]:.2f} / {np.corrcoef(g['speed_ms'], g['true_m_per_mocap_step'])[0, 1]:.2f}"
            f" / {np.corrcoef(g['speed_ms'], g['f_med_hz'])[0, 1]:.2f}"
            for m, g in ((m, held[held["motion"] == m]) for m in order)
        ),
        "",
    ]
    lines += ["### by disturbance (held out, medians over 9 recordings)"]
    lines += [
        md(
            held.groupby(["motion", "disturbance"])[["speed_ms", "true_m_per_mocap_step", "f_med_hz", "lib_bias", "lib_ratio"]].median(),
            "{:.3f}",
        ),
        "",
    ]
    chk = held.groupby("motion")["eq12_ratio"].median().reindex(order) - held.groupby("motion")["lib_ratio"].median().reindex(order)
    lines += [f"check: this script's eq12 refit equals the library's line (largest median difference {np.nanmax(np.abs(chk)):.1e})", ""]
    coef = pd.DataFrame(
        {f"{fold} / {name}": pd.Series(c, index=["1", *CANDIDATES[name]]) for fold, fs in fits.items() for name, c in fs.items()}
    ).T
    lines += ["### candidate lines (fitted on all but the fold's person; 'all' = in sample)", md(coef, "{:.3f}"), ""]
    rat = pd.DataFrame(
        {
            name: [
                f"{a:.2f} / {b:.2f}"
                for a, b in zip(med(nd, [f"{name}_ratio"])[f"{name}_ratio"], med(ins, [f"{name}_ratio"])[f"{name}_ratio"], strict=True)
            ]
            for name in CANDIDATES
        },
        index=order,
    ).T
    lines += ["### candidates: distance ratio, NoDist median, held out / in sample", md(rat), ""]
    rng = pd.DataFrame(
        {
            name: [
                f"{g.min():.2f}-{g.max():.2f}"
                for g in (held[held["motion"] == m].groupby("subject")[f"{name}_ratio"].median() for m in order)
            ]
            for name in CANDIDATES
        },
        index=order,
    ).T
    lines += ["### candidates: range over the left-out people of their median (all recordings)", md(rng), ""]
    lines += ["### adoption rule (fixed before measuring; module docstring)", md(adoption(table)), ""]
    if args.plot:
        lines += [f"plot: {_plot(steps, fits, held, Path(args.plot))}"]
    print("\n".join(lines))
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
