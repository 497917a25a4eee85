"""A phone in a bag and the gait-evidence test: which bouts the rotation test rejects, and the long-bout exemption.

``adaptive``'s gait-evidence test (``gaitml.steps._gait_evidence``) rejects a bout whose rotation at the step
frequency exceeds 0.7 rad/s and its rotation at the stride frequency. A bag swinging on its strap rotates once per
step. The test now keeps every bout of at least ``LONG_BOUT_STEPS`` regular steps whatever its rotation. This study
compares three rules on the same steps (``adaptive`` run once with the test off, then the test applied):

- ``off``: no test;
- ``before``: the rotation test alone on every bout (``long_bout_steps`` = infinity, the rule before the exemption;
  the short-bout context rule off);
- ``now``: the shipped default (bouts of >= ``LONG_BOUT_STEPS`` steps exempt; since the gait-check branch also the
  vertical-symmetry and short-bout context rules).

Tables:

1. Simulated 60 s walks per carrying position (``gaitml.simulate``, ``Placement.random``), selection seeds 0-39 and
   held-out seeds 100-129: count accuracy (min(n, true) / max(n, true)) per rule, bouts rejected before, and the
   rotation of those bouts (rad/s at the step and stride frequency; the step rotation as a pitch angle, degrees).
   ``single-peak`` with the test as ``gaitml steps`` runs it (``gait_check_recording``) too.
2. Non-gait (``gaitml.simulate.nongait``, gestures and desk, 120 s): the sizes of the bouts the rotation test
   rejects on the selection seeds 0-39 (the exemption's length was chosen against their longest), and steps per
   minute per rule, selection seeds 0-39 and held-out seeds 100-129.
3. tyrex (every recording, over the motion-capture span): steps left out per rule, per person and motion.

    python -m experiments.scripts.bag_gait_check [--data ../shared/data] [--skip-tyrex] [--cache /tmp/bag]
"""

from __future__ import annotations

import argparse
import pickle
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.nongait import md_table
from gaitml.simulate import Placement, Subject, simulate_recording
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import get_detector
from gaitml.steps._gait_evidence import LONG_BOUT_STEPS, gait_check, gait_check_recording, gait_evidence

SELECTION_SEEDS = tuple(range(40))
HELDOUT_SEEDS = tuple(range(100, 130))
POSITIONS = ("bag", "belt", "hand-flat", "front-pocket", "back-pocket", "swinging-hand")
NEVER = 10**9  # long_bout_steps that exempts no bout: the rule before the exemption


def walk_recording(position: str, seed: int, duration_s: float = 60.0):
    """The review's simulated walk: a random walker, ``position`` drawn with ``Placement.random`` (hand-flat: None)."""
    rng = np.random.default_rng(seed)
    placement = None if position == "hand-flat" else Placement.random(position, rng)
    return simulate_recording(Subject.random(rng, subject="W"), modes=["walk"], duration_s=duration_s, seed=seed, placement=placement)


def rules(rec) -> dict:
    """Step counts of adaptive per rule on ``rec``, and the evidence table of the bouts (rule ``before``)."""
    fs = rec.sampling_rate_hz
    raw = get_detector("adaptive", gait_check=False).detect(rec).steps_
    out = {
        "off": len(raw),
        "before": len(gait_check(raw, rec.gyr, fs, long_bout_steps=NEVER, confirm_bout_steps=0)),
        "now": len(gait_check(raw, rec.gyr, fs, acc=rec.acc)),
        "ev": gait_evidence(rec.gyr, fs, raw, long_bout_steps=NEVER),
        "raw": raw,
    }
    return out


def _acc(n: int, t: int) -> float:
    return min(n, t) / max(n, t) if max(n, t) else 1.0


def walks_table(seeds, cache: Path | None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per position: count accuracy per rule (mean, worst), bouts rejected before and their rotations."""
    rows, bouts = [], []
    for position in POSITIONS:
        for seed in seeds:
            f = cache / f"walk_{position}_{seed}.pkl" if cache else None
            if f is not None and f.exists():
                r = pickle.loads(f.read_bytes())
            else:
                rec = walk_recording(position, seed)
                res = rules(rec)
                sp = get_detector("single-peak").detect(rec).steps_
                r = {
                    "true": int(rec.reference["n_steps_true"]),
                    **{k: res[k] for k in ("off", "before", "now", "ev")},
                    "sp_off": len(sp),
                    "sp_before": len(_check_recording_never(sp, rec)),
                    "sp_now": len(gait_check_recording(sp, rec)),
                }
                if f is not None:
                    f.write_bytes(pickle.dumps(r))
            rows.append({"position": position, "seed": seed, **{k: v for k, v in r.items() if k != "ev"}})
            ev = r["ev"]
            for b in ev.itertuples(index=False):
                bouts.append(
                    {
                        "position": position,
                        "seed": seed,
                        "n_steps": b.n_steps,
                        "step_hz": b.step_hz,
                        "rot_step": b.rotation_step_rad_s,
                        "rot_stride": b.rotation_stride_rad_s,
                        "rejected_before": not b.gait,
                    }
                )
        print(f"walks {position} {seeds[0]}-{seeds[-1]}", file=sys.stderr, flush=True)
    df, bt = pd.DataFrame(rows), pd.DataFrame(bouts)
    out = []
    for position, g in df.groupby("position", sort=False):
        row = {"position": position, "n": len(g), "true_steps": int(g["true"].sum())}
        for k in ("off", "before", "now", "sp_off", "sp_before", "sp_now"):
            a = np.array([_acc(n, t) for n, t in zip(g[k], g["true"], strict=True)])
            row[f"{k}_mean"], row[f"{k}_worst"] = a.mean(), a.min()
        b = bt[bt.position == position]
        rej = b[b.rejected_before]
        row["bouts"] = len(b)
        row["rejected_before"] = len(rej)
        row["min_rejected_bout_steps"] = int(rej.n_steps.min()) if len(rej) else 0
        row["rot_step_median"] = float(b.rot_step.median())
        row["rot_step_max"] = float(b.rot_step.max())
        row["rot_stride_median"] = float(b.rot_stride.median())
        pitch = np.rad2deg(b.rot_step / (2 * np.pi * b.step_hz))
        row["step_pitch_deg_median"], row["step_pitch_deg_max"] = float(pitch.median()), float(pitch.max())
        out.append(row)
    return pd.DataFrame(out), bt


def _check_recording_never(steps: pd.DataFrame, rec) -> pd.DataFrame:
    """``gait_check_recording`` with the rule before the exemption (adaptive's cadence, no long bout exempt)."""
    cad = get_detector("adaptive", gait_check=False).detect(rec).cadence_
    cadence = (cad["t_s"].to_numpy(), cad["cadence_hz"].to_numpy())
    return gait_check(steps, rec.gyr, rec.sampling_rate_hz, cadence=cadence, long_bout_steps=NEVER, confirm_bout_steps=0)


def nongait_tables(seeds, cache: Path | None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Steps per minute per rule (adaptive; single-peak as ``gaitml steps`` checks it) and every bout's size."""
    rows, bouts = [], []
    for kind in ("gestures", "desk"):
        for seed in seeds:
            f = cache / f"nongait_{kind}_{seed}.pkl" if cache else None
            if f is not None and f.exists():
                r = pickle.loads(f.read_bytes())
            else:
                rec = simulate_nongait(kind, duration_s=120, seed=seed)
                res = rules(rec)
                sp = get_detector("single-peak").detect(rec).steps_
                r = {
                    "minutes": rec.duration_s / 60.0,
                    **{k: res[k] for k in ("off", "before", "now", "ev")},
                    "sp_off": len(sp),
                    "sp_before": len(_check_recording_never(sp, rec)),
                    "sp_now": len(gait_check_recording(sp, rec)),
                }
                if f is not None:
                    f.write_bytes(pickle.dumps(r))
            rows.append({"kind": kind, "seed": seed, **{k: v for k, v in r.items() if k != "ev"}})
            for b in r["ev"].itertuples(index=False):
                bouts.append({"kind": kind, "seed": seed, "n_steps": b.n_steps, "rejected_before": not b.gait})
        print(f"nongait {kind} {seeds[0]}-{seeds[-1]}", file=sys.stderr, flush=True)
    df = pd.DataFrame(rows)
    out = []
    for kind, g in df.groupby("kind", sort=False):
        for det, pre in (("adaptive", ""), ("single-peak (gaitml steps)", "sp_")):
            row = {"kind": kind, "detector": det}
            for k in ("off", "before", "now"):
                per_min = g[pre + k] / g["minutes"]
                row[f"{k}_mean"], row[f"{k}_max"] = float(per_min.mean()), float(per_min.max())
            out.append(row)
    return pd.DataFrame(out), pd.DataFrame(bouts)


def tyrex_table(data: Path, cache: Path | None) -> pd.DataFrame:
    """Steps of adaptive within the motion-capture span per rule, summed per person and motion."""
    from experiments.scripts.tyrex_steps import in_reference_span, tyrex_walks

    f = cache / "tyrex.pkl" if cache else None
    if f is not None and f.exists():
        return pickle.loads(f.read_bytes())
    rows = []
    for walk in tyrex_walks(data):
        ref = walk["ref"]
        row = {"person": walk["person"], "motion": walk["motion"], "mocap": ref["n_steps"], "off": 0, "before": 0, "now": 0}
        row["long_bouts_rotating"] = 0
        for r in walk["recs"]:
            fs = r.sampling_rate_hz
            raw = get_detector("adaptive", gait_check=False).detect(r).steps_
            t0 = float(r.meta.get("t0_original_s", 0.0))
            for k, st in (
                ("off", raw),
                ("before", gait_check(raw, r.gyr, fs, long_bout_steps=NEVER, confirm_bout_steps=0)),
                ("now", gait_check(raw, r.gyr, fs, acc=r.acc)),
            ):
                row[k] += int(np.sum(in_reference_span(t0 + st["t_peak_s"].to_numpy(), ref)))
            ev = gait_evidence(r.gyr, fs, raw, long_bout_steps=NEVER)
            row["long_bouts_rotating"] += int(((~ev["gait"].astype(bool)) & (ev["n_steps"] >= LONG_BOUT_STEPS)).sum())
        rows.append(row)
    df = pd.DataFrame(rows)
    out = df.groupby(["person", "motion"], as_index=False)[["mocap", "off", "before", "now", "long_bouts_rotating"]].sum()
    if f is not None:
        f.write_bytes(pickle.dumps(out))
    return out


def main(argv: list[str] | None = None) -> int:
    """Print the tables as markdown."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.bag_gait_check", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--skip-tyrex", action="store_true")
    ap.add_argument("--cache", default=None, help="folder for per-recording results (a rerun is cheap)")
    args = ap.parse_args(argv)
    cache = Path(args.cache) if args.cache else None
    if cache is not None:
        cache.mkdir(parents=True, exist_ok=True)
    print(f"long_bout_steps = {LONG_BOUT_STEPS}\n")
    for name, seeds in (("selection seeds 0-39", SELECTION_SEEDS), ("held-out seeds 100-129", HELDOUT_SEEDS)):
        tab, _ = walks_table(seeds, cache)
        print(f"## Simulated walks, 60 s, {name}\n")
        print(md_table(tab) + "\n")
    for name, seeds in (("selection seeds 0-39", SELECTION_SEEDS), ("held-out seeds 100-129", HELDOUT_SEEDS)):
        tab, bouts = nongait_tables(seeds, cache)
        print(f"## Non-gait, steps per minute, {name}\n")
        print(md_table(tab) + "\n")
        for kind, g in bouts.groupby("kind", sort=False):
            rej = g[g.rejected_before]
            print(
                f"{kind}: {len(g)} bouts, longest {int(g.n_steps.max()) if len(g) else 0} steps; rejected by the rotation "
                f"test {len(rej)}, longest {int(rej.n_steps.max()) if len(rej) else 0} steps, "
                f"{int((rej.n_steps >= LONG_BOUT_STEPS).sum())} of >= {LONG_BOUT_STEPS} steps\n"
            )
    if not args.skip_tyrex:
        tab = tyrex_table(Path(args.data), cache)
        print("## tyrex, adaptive's steps within the motion-capture span per rule\n")
        print(md_table(tab) + "\n")
        per = tab.groupby("person")[["mocap", "off", "before", "now", "long_bouts_rotating"]].sum().reset_index()
        print(md_table(per) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
