"""`gaitml pdr` on every tyrex walk and run, scored against the motion capture so that it can fail.

``python -m experiments.scripts.tyrex_pdr [--data ../shared/data] [--model models/demo] [--csv FILE] [--out FILE]``
from the repository root (about 3 minutes). For every tyrex recording with motion capture
(:func:`gaitml.pipeline.folder_source.tyrex_manifest`), read by the same reader as
``gaitml pdr DIR`` (:func:`gaitml.io.read_tyrex`; a recording with a sensor gap is scored
on its stretch that overlaps the capture most), it runs:

- ``gaitml``: :func:`gaitml.pdr.run_pdr` with the arguments ``gaitml pdr`` uses without
  options (its defaults: :data:`gaitml.consts.DEFAULT_STEP_DETECTOR`, the default heading
  source and gyroscope-bias removal, forward-only update, uncalibrated step length, start
  heading 0);
- ``paper003``: the paper-faithful settings, ``--detector single-peak --heading hde
  --gyro-bias off --hde-guard off`` (the defaults before issue 27; paper 003 has no structure guard);
- ``model``: the defaults with ``--model models/demo`` (model modes, multi-state update);
- ``still``: a trajectory that never moves;
- ``baseline``: a plain PDR written here for the comparison: peaks of the low-passed
  |acc| (:func:`baseline_steps`), one constant step length per gait (walk / run) fitted on
  the *other two people* (true body distance over steps found), and the heading integrated
  from the gyroscope about gravity (:func:`gyro_heading_about_gravity`);
- ``bound``: the true body speed carried along that same gyroscope heading (what a perfect
  distance with a plain gyroscope heading scores).

Scores (:func:`gaitml.evaluation.trajectory.walk_scores`, every trajectory aligned once on
its first 10 s of walking): walked-distance ratio against the truth low-passed at 0.5 Hz,
the median error of the displacement over 10 s of walking as a % of the distance walked
in it, and the walking-direction drift (deg/min, absolute). Tables: median over the
recordings of each motion, NoDist (9 per motion, as in issue 27) and all; per person.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = [
    "baseline_steps",
    "gyro_heading_about_gravity",
    "load_tyrex",
    "main",
    "md",
    "pdr_kwargs",
    "score_recording",
    "summarise",
]

MOTION_ORDER = ("Texting", "AR", "Phoning", "Swinging", "FrontPocket", "BackPocket", "RunningHand", "RunningPocket")
VARIANTS = ("gaitml", "paper003", "model", "baseline", "bound", "still")
#: ``gaitml pdr`` as paper 003 writes it (the CLI defaults before issue 27): single-peak steps,
#: HDE heading without the structure guard (``--hde-guard off``), the gyroscope as logged
PAPER003 = {"detector": "single-peak", "heading": "hde", "gyro_bias": "off", "hde_guard": "off"}

#: Baseline step detection: |acc| low-passed at this cutoff (Hz) ...
BASELINE_LOWPASS_HZ = 3.0
#: ... peaks at least this prominent (m/s^2) ...
BASELINE_PROMINENCE_MS2 = 0.6
#: ... and at least this far apart (s; 3.3 steps/s, above running cadence).
BASELINE_MIN_INTERVAL_S = 0.3


def gyro_heading_about_gravity(recording, *, cutoff_hz: float = 0.3) -> np.ndarray:
    """Compass heading change (rad, clockwise) from the gyroscope's rate about the low-passed gravity.

    ``psi(t) = -integral(omega . up) dt``: a turn to the left (counter-clockwise seen
    from above, positive about up) lowers the compass heading. Starts at 0.
    """
    from gaitml.signal import gravity_direction

    up = gravity_direction(recording.acc, recording.sampling_rate_hz, cutoff_hz=cutoff_hz)
    rate = np.sum(recording.gyr * up, axis=1)
    return -np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]))]) / recording.sampling_rate_hz


def baseline_steps(recording) -> np.ndarray:
    """Step sample indices: peaks of |acc| low-passed at 3 Hz, prominence 0.6 m/s^2, >= 0.3 s apart."""
    from scipy.signal import find_peaks

    from gaitml.signal import lowpass

    fs = recording.sampling_rate_hz
    mag = lowpass(np.linalg.norm(recording.acc, axis=1), BASELINE_LOWPASS_HZ, fs, order=2)
    peaks, _ = find_peaks(mag, prominence=BASELINE_PROMINENCE_MS2, distance=max(1, int(BASELINE_MIN_INTERVAL_S * fs)))
    return peaks


def load_tyrex(data: Path) -> list[dict]:
    """Every tyrex recording with motion capture: its manifest row, the recording and the truth track.

    A recording with a sensor gap is read in segments; the segment overlapping the
    capture longest is kept (``segment`` says which, ``n_segments`` of how many).
    """
    from gaitml.io import read_segments
    from gaitml.io.tyrex import read_tyrex_truth
    from gaitml.pipeline.folder_source import tyrex_manifest

    root = data / "tyrex-attitude"
    man = tyrex_manifest(root)
    out = []
    for row in man[man["truth"] != ""].to_dict("records"):
        d = root / row["file"]
        segs = read_segments(d)
        truth = read_tyrex_truth(d)

        def overlap(r, truth=truth):
            t0 = r.meta["t0_original_s"]
            return min(t0 + r.duration_s, truth.t_s[-1]) - max(t0, truth.t_s[0])

        k = int(np.argmax([overlap(r) for r in segs]))
        rec = segs[k]
        out.append({**row, "recording": rec, "truth": truth, "segment": k, "n_segments": len(segs)})
    return out


def _truth_on_recording(item) -> tuple[np.ndarray, np.ndarray]:
    rec, truth = item["recording"], item["truth"]
    return truth.t_s - rec.meta["t0_original_s"], truth.pos_m[:, :2]


def _trajectory_from_steps(t_step, length_m, heading_rad) -> tuple[np.ndarray, np.ndarray]:
    """Positions after each step (forward along the compass heading), preceded by the start at t = 0."""
    d = np.column_stack([np.sin(heading_rad), np.cos(heading_rad)]) * np.asarray(length_m, dtype=float)[:, None]
    xy = np.vstack([[0.0, 0.0], np.cumsum(d, axis=0)])
    return np.concatenate([[0.0], t_step]), xy


def baseline_counts(item) -> tuple[int, float]:
    """Baseline steps found inside the capture and the true body distance there (for the constant step length)."""
    from gaitml.evaluation.trajectory import walked_distance_ratio

    rec = item["recording"]
    tt, xy = _truth_on_recording(item)
    steps = baseline_steps(rec)
    t = steps / rec.sampling_rate_hz
    d = walked_distance_ratio([tt[0], tt[-1]], np.zeros((2, 2)), tt, xy)
    n = int(np.sum((t >= d["t0_s"]) & (t <= d["t1_s"])))
    return n, d["true_m"]


def bound_trajectory(item) -> tuple[np.ndarray, np.ndarray]:
    """The true body speed carried along the gyroscope's heading about gravity, at the capture's frames."""
    from gaitml.evaluation.trajectory import body_track

    rec = item["recording"]
    tt, xy = _truth_on_recording(item)
    inside = (tt >= 0) & (tt <= rec.t_s[-1])
    tt, xy = tt[inside], xy[inside]
    body = body_track(tt, xy)
    speed = np.linalg.norm(np.gradient(body, tt, axis=0), axis=1)
    psi = np.interp(tt, rec.t_s, gyro_heading_about_gravity(rec))
    dt = np.diff(tt)
    v = 0.5 * (speed[1:] + speed[:-1])
    h = 0.5 * (psi[1:] + psi[:-1])
    xy_est = np.vstack([[0.0, 0.0], np.cumsum(np.column_stack([np.sin(h), np.cos(h)]) * (v * dt)[:, None], axis=0)])
    return tt, xy_est


def pdr_kwargs(options: dict, initial_heading_rad: float = 0.0) -> dict:
    """:func:`gaitml.pdr.run_pdr` keywords of a ``gaitml pdr`` setting: ``hde_guard='off'`` becomes the HDE
    ``gaitml pdr --hde-guard off`` builds (its structure guard off, referenced to the start heading)."""
    kw = dict(options)
    if kw.pop("hde_guard", "on") == "off":
        from gaitml.pdr.hde import HeuristicDriftElimination

        kw["hde"] = HeuristicDriftElimination(reference_rad=initial_heading_rad, structure_alpha=None)
    return kw


def score_recording(item, *, model=None, step_length_by_mode: dict | None = None) -> list[dict]:
    """Every variant's trajectory of one recording, scored; one row per variant."""
    from gaitml.evaluation.trajectory import walk_scores
    from gaitml.pdr import run_pdr

    rec = item["recording"]
    tt, xy = _truth_on_recording(item)
    keys = {k: item[k] for k in ("file", "subject", "phone", "motion", "position", "mode", "disturbance", "segment", "n_segments")}
    rows = []

    def add(variant, t, exy, **extra):
        # a trajectory stays at its last position until the recording ends
        if t[-1] < rec.t_s[-1]:
            t, exy = np.append(t, rec.t_s[-1]), np.vstack([exy, exy[-1:]])
        rows.append({**keys, "variant": variant, **walk_scores(t, exy, tt, xy), **extra})

    runs = {"gaitml": ({}, None), "paper003": (PAPER003, None)}
    if model is not None:
        runs["model"] = ({}, model)
    trajs = {}
    for name, (kw, mdl) in runs.items():
        res = run_pdr(rec, model=mdl, modes="model" if mdl is not None else "forward", **pdr_kwargs(kw))
        tj = res.trajectory
        trajs[name] = tj
        extra = {"n_steps": res.n_steps}
        if mdl is not None:
            ood = res.info.get("out_of_domain_steps")
            extra["out_of_domain_share"] = (ood / res.n_steps) if (ood is not None and res.n_steps) else float("nan")
            extra["non_walk_steps"] = int(np.sum(res.steps["mode"].to_numpy().astype(str) != "walk")) if res.n_steps else 0
            fwd = trajs["gaitml"]
            extra["same_as_forward"] = bool(
                len(fwd) == len(tj) and np.allclose(fwd[["x_m", "y_m"]].to_numpy(), tj[["x_m", "y_m"]].to_numpy(), atol=1e-6)
            )
        add(name, tj["t_s"].to_numpy(), tj[["x_m", "y_m"]].to_numpy(), **extra)
    add("still", np.array([0.0, rec.t_s[-1]]), np.zeros((2, 2)))
    steps = baseline_steps(rec)
    length = (step_length_by_mode or {}).get(item["mode"], 0.7)
    psi = gyro_heading_about_gravity(rec)
    t_b, xy_b = _trajectory_from_steps(steps / rec.sampling_rate_hz, np.full(len(steps), length), psi[steps])
    add("baseline", t_b, xy_b, n_steps=len(steps), step_length_m=length)
    t_bd, xy_bd = bound_trajectory(item)
    add("bound", t_bd, xy_bd)
    return rows


def md(df: pd.DataFrame, floats: str = "{:.2f}") -> str:
    """A DataFrame (index kept) as a markdown table; NaN as '-'."""
    d = df.reset_index()
    cols = [str(c) for c in d.columns]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for row in d.itertuples(index=False):
        cells = []
        for v in row:
            if isinstance(v, (float, np.floating)):
                cells.append("-" if not np.isfinite(v) else floats.format(v))
            else:
                cells.append(str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def summarise(table: pd.DataFrame, *, by: str = "motion") -> dict[str, pd.DataFrame]:
    """Median per ``by`` and variant of the distance ratio, 10 s error and |drift|."""
    t = table.assign(abs_drift=table["drift_deg_per_min"].abs())
    out = {}
    for col, name in (("distance_ratio", "distance ratio"), ("error_10s_pct", "10 s error %"), ("abs_drift", "|drift| deg/min")):
        piv = t.pivot_table(index="variant", columns=by, values=col, aggfunc="median")
        cols = [c for c in MOTION_ORDER if c in piv.columns] if by == "motion" else list(piv.columns)
        out[name] = piv.reindex(index=[v for v in VARIANTS if v in piv.index], columns=cols)
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_pdr", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--model", default="models/demo", help="model for the model-mode rows ('' to skip them)")
    p.add_argument("--csv", metavar="FILE", help="write the long table (one row per recording and variant)")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    items = load_tyrex(Path(args.data))
    print(f"{len(items)} recordings with motion capture read ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    model = None
    if args.model:
        from gaitml.models import load_model

        model = load_model(args.model)
    # the baseline's constant step length per gait, fitted on the other two people
    counts = pd.DataFrame(
        [{"subject": it["subject"], "mode": it["mode"], **dict(zip(("n", "m"), baseline_counts(it), strict=True))} for it in items]
    )
    lengths = {}
    for s in sorted(counts["subject"].unique()):
        other = counts[counts["subject"] != s].groupby("mode")[["n", "m"]].sum()
        lengths[s] = (other["m"] / other["n"]).to_dict()
    rows = []
    for i, it in enumerate(items):
        rows += score_recording(it, model=model, step_length_by_mode=lengths[it["subject"]])
        if (i + 1) % 20 == 0:
            print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    table = pd.DataFrame(rows)
    if args.csv:
        table.to_csv(args.csv, index=False)
    lines = [f"baseline step length fitted on the other two people (m): {lengths}", ""]
    for subset, sel in (
        ("NoDist (9 per motion)", table["disturbance"] == "NoDist"),
        ("all (18 per walking motion, 9 running)", table.index >= 0),
    ):
        for name, tab in summarise(table[sel]).items():
            lines.append(f"### {name}, median, {subset}")
            lines.append(md(tab))
            lines.append("")
    walks = table[table["variant"] == "gaitml"]
    lines.append(f"steps found at the defaults, median per motion: {walks.groupby('motion')['n_steps'].median().to_dict()}")
    if model is not None:
        m = table[table["variant"].isin(["model"])]
        lines.append("")
        lines.append("### model modes against forward-only")
        lines.append(
            m.groupby("variant")
            .agg(
                recordings=("file", "size"),
                same_as_forward=("same_as_forward", "sum"),
                out_of_domain_share=("out_of_domain_share", "median"),
                non_walk_steps=("non_walk_steps", "sum"),
            )
            .pipe(md)
        )
    lines.append("")
    lines.append("### per person (all recordings): median 10 s error % per motion")
    for v in ("gaitml", "paper003", "baseline", "bound", "still"):
        sub = table[table["variant"] == v]
        piv = sub.pivot_table(index="subject", columns="motion", values="error_10s_pct", aggfunc="median")
        lines.append(f"{v}:")
        lines.append(md(piv.reindex(columns=[c for c in MOTION_ORDER if c in piv.columns]), "{:.1f}"))
        lines.append("")
    lines.append("### per person (all recordings): median distance ratio per motion")
    for v in ("gaitml", "paper003", "baseline"):
        sub = table[table["variant"] == v]
        piv = sub.pivot_table(index="subject", columns="motion", values="distance_ratio", aggfunc="median")
        lines.append(f"{v}:")
        lines.append(md(piv.reindex(columns=[c for c in MOTION_ORDER if c in piv.columns])))
        lines.append("")
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
