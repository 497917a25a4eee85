"""The orientation-dynamics part of the running flags, the gyroscope's range, and how vigorous each run is (diagnosis, no fitting).

``python -m experiments.scripts.run_dynamics --data ../shared/data --model-cache DIR [--person Jakob] [--csv out.csv]``
from the repository root. ``DIR`` holds the fold models of ``experiments.scripts.tyrex_modes --recipes a
--model-cache DIR`` (``DIR/models/<config>-a-<person>-<key>``) or of
:mod:`experiments.scripts.running_flags` (``DIR/a-<person>``): trained on the two other tyrex people.

Per left-out person's fold model, every moving running window (the speed rule of
:func:`experiments.scripts.tyrex_modes.moving_labels`) of **every** tyrex person is read through
``gaitml predict``'s own path (:func:`gaitml.models.predict_recording`): the left-out person's
windows are held out, the two others' are the fold's own training runs, the reference of what
"in the training domain" was. Per window:

- which part of the domain check flags it (feature distance, orientation dynamics, gravity,
  placement) and its ratios to the thresholds (the dynamics one is the span median the check decides on);
- its own (not span-median) dynamics distance, the nearest dynamics Gaussian (``mode|position``) and the
  per-descriptor z against it (``(q_j - m_j) / sqrt(Sigma_jj)``, Sigma the Gaussian's covariance, in the
  record's standardised units), for the 13 descriptors of
  :func:`gaitml.models.domain.orientation_dynamics` computed on the recording as the record reads it
  (:func:`gaitml.models._predict.domain_view`: clipped to its accelerometer range, if any);
- how vigorous the run is, from references the domain check does not read: the body speed from the motion
  capture (horizontal path of the rigid body averaged over ``SPEED_SMOOTH_S`` to take out the arm swing,
  per window its path length over its duration), the step cadence of the library's step detector
  (:func:`gaitml.models._predict.window_step_cadence`) and the RMS of ``|omega|`` (rad/s).

Per recording, from the raw sensor files (not resampled): the largest ``|gyro|`` on any axis, and how
many samples sit within ``PLATEAU_FRACTION`` of it on that axis: a gyroscope at its range repeats its
full-scale value over consecutive samples (a flat top), as the Nexus 5 and iPhone 4S accelerometers do at
2 g (:mod:`experiments.scripts.running_flags`); a few samples near the top (the largest swings' crests) are peaks, not a range.
"""

from __future__ import annotations

import argparse
import gzip
import sys
from pathlib import Path

import numpy as np
import pandas as pd

RUN_MOTIONS = ("RunningHand", "RunningPocket")
#: Moving average (s) of the motion capture's horizontal position before its speed is taken: one stride at 2.8
#: steps/s (the median step cadence of the tyrex runs), so the sway at the stride rate and its harmonics average
#: out and the body's pace remains; on the room's tight turns (2 m radius at 1.8 m/s) it shortens the path < 2 %.
SPEED_SMOOTH_S = 0.72
#: A gyroscope sample counts at the top of its axis when its absolute value is within this fraction of the
#: axis's largest absolute value over the recording: 2 %, the rule by which the accelerometers' 2 g range was
#: counted (experiments/reports/default-model.md, RF.2: a quarter of the Nexus 5's hand-run samples).
PLATEAU_FRACTION = 0.02


#: Bins (m/s) of the motion-capture speed and (rad/s) of the ``|omega|`` RMS in which the flag rate is tabulated.
SPEED_BINS = (0.0, 1.5, 1.75, 2.0, 2.25, 9.0)
GYR_BINS = (0.0, 3.0, 3.5, 4.0, 4.5, 5.0, 20.0)


def flagged_stretches(held: pd.DataFrame, train: pd.DataFrame, min_len: int = 5, max_gap: int = 3) -> pd.DataFrame:
    """Per recording, the stretches of flagged windows (gaps of at most ``max_gap`` windows joined, at least ``min_len`` long),
    with their median vigour beside the rest of the recording and the training people's windows."""
    out = []
    for (subject, phone), g in held.groupby(["subject", "phone"]):
        idx = np.sort(g.loc[g["flagged"], "window"].to_numpy())
        if not len(idx):
            continue
        cuts = np.flatnonzero(np.diff(idx) > max_gap + 1)
        for a, b in zip(np.r_[0, cuts + 1], np.r_[cuts, len(idx) - 1], strict=True):
            lo, hi = int(idx[a]), int(idx[b])
            if hi - lo + 1 < min_len:
                continue
            inside = g["window"].between(lo, hi)
            st, rest = g[inside], g[~inside]
            both = int(((train["speed_ms"] >= st["speed_ms"].median()) & (train["gyr_rms"] >= st["gyr_rms"].median())).sum())
            out.append(
                {
                    "subject": subject,
                    "phone": phone,
                    "windows": f"{lo}-{hi}",
                    "flagged": f"{int(st['flagged'].sum())} of {len(st)}",
                    "speed_ms": st["speed_ms"].median(),
                    "speed rest": rest["speed_ms"].median(),
                    "speed training": train["speed_ms"].median(),
                    "gyr_rms": st["gyr_rms"].median(),
                    "gyr rest": rest["gyr_rms"].median(),
                    "gyr training": train["gyr_rms"].median(),
                    "cadence": st["cadence_hz"].median(),
                    "cadence rest": rest["cadence_hz"].median(),
                    "training windows as fast and as rotating": f"{both} of {len(train)}",
                }
            )
    return pd.DataFrame(out)


def resolve_fold(cache: Path, recipe: str, person: str) -> Path:
    """The fold model directory for ``person`` left out: ``cache/<recipe>-<person>`` or tyrex_modes' ``cache/models/*-<recipe>-<person>-<key>``."""
    own = cache / f"{recipe}-{person}"
    if (own / "model.json").exists():
        return own
    hits = sorted(p for p in (cache / "models").glob(f"*-{recipe}-{person}-*") if (p / "model.json").exists())
    if len(hits) != 1:
        raise SystemExit(
            f"run_dynamics: expected one fold model for {person} left out under {cache} (a-{person}/ or models/*-{recipe}-{person}-*/), "
            f"found {len(hits)}; pass the --model-cache of tyrex_modes --recipes {recipe}."
        )
    return hits[0]


def gyro_top(path: Path) -> dict:
    """Largest ``|gyro|`` (rad/s) on any axis of a raw tyrex gyroscope file, and samples at that axis's top."""
    with gzip.open(path, "rt") as fh:
        g = np.loadtxt(fh)[:, 1:4]
    a = np.abs(g)
    top = a.max(axis=0)
    ax = int(top.argmax())
    at_top = int((a[:, ax] >= (1.0 - PLATEAU_FRACTION) * top[ax]).sum())
    return {
        "gyr_max_rad_s": float(top[ax]),
        "gyr_max_dps": float(np.degrees(top[ax])),
        "samples_at_top": at_top,
        "share_at_top": at_top / len(a),
    }


def all_gyro_tops(data: Path) -> pd.DataFrame:
    """Per phone, over every tyrex recording folder (walks and runs; not the calibration ones): the largest ``|gyro|``
    on any axis, where, and the most samples any recording holds at its own top (:func:`gyro_top`)."""
    rows = []
    for sub, fname in (("android", "gyroscope-calibrated.txt.gz"), ("ios", "gyroscope.txt.gz")):
        for f in sorted((data / "tyrex-attitude" / sub).glob(f"*/{fname}")):
            name = f.parent.name
            if name.startswith("calib"):
                continue
            rows.append({"phone": name.split("_")[1], "recording": name, **gyro_top(f)})
    t = pd.DataFrame(rows)
    best = t.loc[t.groupby("phone")["gyr_max_rad_s"].idxmax()].set_index("phone")
    return pd.DataFrame(
        {
            "recordings": t.groupby("phone").size(),
            "largest abs gyro (rad/s)": best["gyr_max_rad_s"],
            "(dps)": best["gyr_max_dps"],
            "in": best["recording"],
            "most samples at a recording's top": t.groupby("phone")["samples_at_top"].max(),
            "largest % at a recording's top": 100.0 * t.groupby("phone")["share_at_top"].max(),
        }
    ).reset_index()


def raw_gyro_file(data: Path, name: str) -> Path:
    """The raw gyroscope file of a tyrex recording folder ``name`` (Android's calibrated one, or iOS's)."""
    root = data / "tyrex-attitude"
    for sub, fname in (("android", "gyroscope-calibrated.txt.gz"), ("ios", "gyroscope.txt.gz")):
        p = root / sub / name / fname
        if p.exists():
            return p
    raise FileNotFoundError(f"no gyroscope file for {name} under {root}")


def window_speed(rec, truth, starts: np.ndarray, length: int) -> np.ndarray:
    """Body speed (m/s) of each window from the motion capture: smoothed horizontal path length over the window's duration."""
    tt = truth.t_s - rec.meta["t0_original_s"]
    xy = np.asarray(truth.pos_m[:, :2], dtype=float)
    ok = np.isfinite(xy).all(axis=1)
    tt, xy = tt[ok], xy[ok]
    dt = float(np.median(np.diff(tt)))
    k = max(1, int(round(SPEED_SMOOTH_S / dt)))
    ker = np.ones(k) / k
    sm = np.column_stack([np.convolve(xy[:, c], ker, mode="same") for c in range(2)])
    sm, tt = sm[k : len(sm) - k], tt[k : len(tt) - k]  # drop the edges the average pads with zeros
    step = np.r_[0.0, np.cumsum(np.hypot(*np.diff(sm, axis=0).T))]
    t0 = rec.t_s[0] + starts / rec.sampling_rate_hz
    t1 = t0 + length / rec.sampling_rate_hz
    out = np.full(len(starts), np.nan)
    inside = (t0 >= tt[0]) & (t1 <= tt[-1])
    out[inside] = (np.interp(t1[inside], tt, step) - np.interp(t0[inside], tt, step)) / (t1[inside] - t0[inside])
    return out


def dynamics_z(dom, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per row of descriptors ``Q``: nearest dynamics Gaussian, its distance, per-descriptor z (diagonal of its covariance)."""
    a = dom.arrays
    Z = (Q - a["dyn_center"]) / a["dyn_scale"]
    means, precs = a["dyn_means"], a["dyn_precisions"]
    d2 = np.stack([np.einsum("ij,jk,ik->i", Z - m, P, Z - m) for m, P in zip(means, precs, strict=True)], axis=1)
    k = np.nanargmin(np.where(np.isfinite(d2), d2, np.inf), axis=1)
    sd = np.sqrt(np.stack([np.diag(np.linalg.inv(P)) for P in precs]))
    return k, np.sqrt(d2[np.arange(len(k)), k]), (Z - means[k]) / sd[k]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--model-cache", type=Path, required=True)
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--person", default="Jakob", help="left-out people whose fold models to read (comma-separated)")
    ap.add_argument("--motions", default=",".join(RUN_MOTIONS))
    ap.add_argument("--csv", type=Path, default=None, help="per-window table")
    ap.add_argument(
        "--all-gyro", action="store_true", help="also the gyroscope tops of every tyrex recording, walks included (about 1 min)"
    )
    a = ap.parse_args(argv)
    from experiments.scripts.tyrex_modes import load_tyrex_labelled, md
    from gaitml.models import load_model, predict_recording
    from gaitml.models._predict import domain_view, window_step_cadence
    from gaitml.models.domain import DYNAMICS_NAMES, orientation_dynamics

    if not (a.data / "tyrex-attitude").is_dir():
        raise SystemExit(f"run_dynamics: no tyrex-attitude under {a.data}; pass --data the shared data folder.")
    motions = a.motions.split(",")
    people = [p for p in a.person.split(",") if p]
    folds = {p: resolve_fold(a.model_cache, a.recipe, p) for p in people}
    items = [it for it in load_tyrex_labelled(a.data) if it["motion"] in motions]
    tops = {}
    for it in items:
        name = Path(str(it["file"])).name
        if name not in tops:
            tops[name] = gyro_top(raw_gyro_file(a.data, name))
    rows = []
    for person, mdir in folds.items():
        model = load_model(mdir)
        dom = model.domain
        thr_d, thr_y = dom.distance_threshold, dom.dynamics["threshold"]
        thr_g = np.degrees(dom.gravity_threshold_rad) if dom.gravity_check else np.inf
        labels = list(dom.dynamics["labels"])
        print(f"[run_dynamics] {person} left out ({mdir.name}): distance threshold {thr_d:.2f}, dynamics {thr_y:.2f}", file=sys.stderr)
        L = int(round(model.length_s * model.sampling_rate_hz))
        for it in items:
            rec = it["recording"]
            p = predict_recording(model, rec)
            starts = p["start"].to_numpy(np.int64)
            seen = domain_view(dom, rec)[0]
            Q = orientation_dynamics(seen.acc, seen.gyr, starts, starts + L, rec.sampling_rate_hz)
            k, dk, zq = dynamics_z(dom, Q)
            cad = window_step_cadence(rec, p)
            speed = window_speed(rec, it["truth"], starts, L)
            wmag = np.linalg.norm(rec.gyr, axis=1)
            moving = (p["label"].astype(str) == it["mode"]).to_numpy() & (p["label_fraction"] >= 0.5).to_numpy()
            flagged = p["in_domain"].map(lambda v: v is False).to_numpy(bool)
            reason = p["out_of_domain_reason"].astype(str).to_numpy()
            name = Path(str(it["file"])).name
            for j in np.flatnonzero(moving):
                s = starts[j]
                rows.append(
                    {
                        "fold": person,
                        "role": "held out" if it["subject"] == person else "training",
                        "subject": it["subject"],
                        "phone": it["phone"],
                        "motion": it["motion"],
                        "recording": name,
                        "window": int(j),
                        "flagged": bool(flagged[j]),
                        "mode": str(p["mode"].iloc[j]),
                        "placement": "placement" in reason[j],
                        "dist_ratio": float(p["domain_distance"].iloc[j]) / thr_d,
                        "dyn_ratio": float(p["dynamics_distance"].iloc[j]) / thr_y,
                        "dyn_own_ratio": float(dk[j]) / thr_y,
                        "gravity_flag": bool(float(p["gravity_angle_deg"].iloc[j]) > thr_g),
                        "nearest_dyn": labels[k[j]],
                        "speed_ms": float(speed[j]),
                        "cadence_hz": float(cad[j]),
                        "gyr_rms": float(np.sqrt(np.mean(wmag[s : s + L] ** 2))),
                        **tops[name],
                        **{f"q:{n}": float(Q[j, c]) for c, n in enumerate(DYNAMICS_NAMES)},
                        **{f"zq:{n}": float(zq[j, c]) for c, n in enumerate(DYNAMICS_NAMES)},
                    }
                )
    w = pd.DataFrame(rows)
    if a.csv:
        w.to_csv(a.csv, index=False)
    pd.set_option("display.width", 250)
    w["by_feature"] = w["flagged"] & (w["dist_ratio"] > 1)
    w["by_dynamics"] = w["flagged"] & (w["dyn_ratio"] > 1)
    w["flagged_run"] = w["flagged"] & (w["mode"] == "run")  # the classifier's answer under the flag: the right one
    w["by_gravity"] = w["flagged"] & w["gravity_flag"]
    w["by_placement"] = w["flagged"] & w["placement"]
    w["dynamics_only"] = w["by_dynamics"] & ~(w["dist_ratio"] > 1) & ~w["gravity_flag"] & ~w["placement"]
    print("\n## per recording: moving windows flagged, by which part; vigour (median over moving windows); raw gyroscope top\n")
    g = (
        w.groupby(["fold", "role", "motion", "subject", "phone"])
        .agg(
            windows=("flagged", "size"),
            flagged=("flagged", "sum"),
            by_feature=("by_feature", "sum"),
            by_dynamics=("by_dynamics", "sum"),
            by_gravity=("by_gravity", "sum"),
            by_placement=("by_placement", "sum"),
            dynamics_only=("dynamics_only", "sum"),
            flagged_read_run=("flagged_run", "sum"),
            dyn_ratio_med=("dyn_ratio", "median"),
            dyn_ratio_max=("dyn_ratio", "max"),
            speed_ms=("speed_ms", "median"),
            cadence_hz=("cadence_hz", "median"),
            gyr_rms=("gyr_rms", "median"),
            gyr_max_dps=("gyr_max_dps", "first"),
            samples_at_top=("samples_at_top", "first"),
            pct_at_top=("share_at_top", lambda v: 100.0 * v.iloc[0]),
        )
        .reset_index()
    )
    print(md(g))
    zc = [c for c in w.columns if c.startswith("zq:")]
    for (person, motion), grp in w.groupby(["fold", "motion"]):
        held = grp[grp["role"] == "held out"]
        dflag = held[held["by_dynamics"]]
        if len(dflag) < 5:
            continue
        train = grp[grp["role"] == "training"]
        held_ok = held[~held["flagged"]]
        med = dflag[zc].median()
        top = med.abs().sort_values(ascending=False).index
        print(
            f"\n## {person} left out, {motion}: dynamics descriptors, median z against the nearest dynamics Gaussian "
            f"({len(dflag)} held-out windows the dynamics flags; {len(held_ok)} held-out in domain; {len(train)} training-people windows)\n"
        )
        print(
            md(
                pd.DataFrame(
                    {
                        "descriptor": [c[3:] for c in top],
                        "z flagged by dynamics": med[top].values,
                        "z held out in domain": held_ok[top].median().values if len(held_ok) else np.nan,
                        "z training people": train[top].median().values,
                        "value flagged (median)": dflag[["q:" + c[3:] for c in top]].median().values,
                        "value training (median)": train[["q:" + c[3:] for c in top]].median().values,
                        "value training (max)": train[["q:" + c[3:] for c in top]].max().values,
                    }
                )
            )
        )
        print("nearest dynamics Gaussians of the flagged:", dflag["nearest_dyn"].value_counts().to_dict())
        print("\nvigour of the flagged against the training people's runs of this motion (quantiles over windows):\n")
        qs = [0.05, 0.5, 0.95]
        vig = []
        for lab, part in (("held out, flagged by dynamics", dflag), ("held out, in domain", held_ok), ("training people", train)):
            for col in ("speed_ms", "cadence_hz", "gyr_rms", "q:log_gyr_mean", "q:log_gyr_std"):
                v = part[col].dropna()
                vig.append(
                    {"windows": lab, "quantity": col, **{f"q{int(q * 100)}": float(v.quantile(q)) if len(v) else np.nan for q in qs}}
                )
        print(md(pd.DataFrame(vig)))
        beyond = {
            col: float((dflag[col] > train[col].max()).mean())
            for col in ("speed_ms", "cadence_hz", "gyr_rms", "q:log_gyr_mean", "q:log_gyr_std")
        }
        print("\nshare of the flagged above every training-people window:", {k: round(v, 2) for k, v in beyond.items()})
        r = dflag["dyn_ratio"]
        print(
            f"dynamics ratio (span median / threshold) of the {len(r)}: median {r.median():.3f}, q90 {r.quantile(0.9):.3f}, "
            f"max {r.max():.3f}; within 5 % of the threshold {int((r <= 1.05).sum())}, within 10 % {int((r <= 1.10).sum())}"
        )
        print("\nflag rate of the held-out windows by vigour (training-people windows in the same bin beside):\n")
        bins = []
        for col, edges in (("speed_ms", SPEED_BINS), ("gyr_rms", GYR_BINS)):
            for lo, hi in zip(edges[:-1], edges[1:], strict=True):
                m, mt = held[col].between(lo, hi, inclusive="left"), train[col].between(lo, hi, inclusive="left")
                bins.append(
                    {
                        "quantity": col,
                        "bin": f"{lo:g}-{hi:g}",
                        "held-out windows": int(m.sum()),
                        "flagged": float(held.loc[m, "flagged"].mean()) if m.any() else np.nan,
                        "training windows": int(mt.sum()),
                    }
                )
        print(md(pd.DataFrame(bins)))
        print(
            "\nstretches of consecutive flagged held-out windows (>= 5 windows, gaps of <= 3 allowed) against the rest of the recording:\n"
        )
        st = flagged_stretches(held, train)
        print(md(st) if len(st) else "none")
    if a.all_gyro:
        print("\n## every tyrex recording's raw gyroscope: the largest |axis| value per phone, and the most samples at a recording's top\n")
        print(md(all_gyro_tops(a.data)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
