"""The shipped default models on real recordings they were not trained on, and on untrained positions.

``python -m experiments.scripts.default_model [--data ../shared/data] [--models models/demo,models/demo-acc]
[--run-cadence on|off|HZ] [--rates native,20] [--out FILE]`` from the repository root.

Every window goes through :func:`gaitml.models.predict_recording`, the path of ``gaitml predict``
(adjacent-window correction, the still gate, the domain check). Per model and data set:

- real walking the models never saw: the Oxford step-counter walks per carrying position (no
  gyroscope: only accelerometer-only models read them) and the two IFSM flat-held walks; every
  window of a walk is scored *walk* (in domain and read ``walk``), *still* (the still gate: no
  step in the window), *flagged* (out of domain), *silently wrong* (in domain, another of the five
  modes). Which Oxford positions a model was trained on is in its card; the others should be flagged.
- untrained carrying positions and sensors, the share of windows flagged out of domain: the
  simulator's bag and belt (held-out seed 2024, 2 subjects x 120 s, five modes) and the gaitmap
  foot-mounted IMU (both feet).
- side steps and backward walking (and walk, run) on held-out simulator seeds (seed 2024, 2
  subjects x 120 s) in the positions each model was trained on (its domain record's simulator
  positions): right / flagged / silently wrong per position and mode.

``--rates``: every table again with each recording as a phone recording at that rate would give it
(:func:`gaitml.models.resample_recording` down to the rate; ``native``: as recorded).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["score_walk", "main"]

OXFORD_POSITIONS = ("InHand", "FrontPocket", "BackPocket", "SwingingArm", "Purse", "NeckPouch", "Armband")
HELDOUT_SEED = 2024


def at(recs, rate: float | None) -> list:
    """``recs`` recorded at ``rate`` Hz (:func:`gaitml.models.resample_recording`; None: as they are)."""
    from gaitml.models import resample_recording

    return list(recs) if rate is None else [resample_recording(r, rate) for r in recs]


def score_walk(model, recs, run_min_cadence_hz: float | None = None) -> dict:
    """Counts over every window of ``recs`` (all walking): walk, still, flagged, silently wrong.

    ``run_min_cadence_hz``: predict's run-cadence rule (None: the library default, 0: off)."""
    from gaitml.models import predict_recording

    n = walk = still = flagged = 0
    per = []
    for r in recs:
        p = predict_recording(model, r, run_min_cadence_hz=run_min_cadence_hz)
        out = np.array([v is False for v in p["in_domain"]], dtype=bool)
        mode = p["mode"].astype(str).to_numpy()
        n += len(p)
        flagged += int(out.sum())
        walk += int(np.sum(~out & (mode == "walk")))
        still += int(np.sum(~out & (mode == "still")))
        if len(p):
            per.append(float(np.mean(~out & (mode == "walk"))))
    return {
        "windows": n,
        "walk": walk,
        "still": still,
        "flagged": flagged,
        "silently wrong": n - walk - still - flagged,
        "walk per recording": f"{min(per):.2f}-{max(per):.2f}" if per else "-",
    }


def _share_row(what: str, model: str, c: dict) -> dict:
    n = max(c["windows"], 1)
    return {
        "data": what,
        "model": model,
        "windows": c["windows"],
        **{k: c[k] / n for k in ("walk", "still", "flagged", "silently wrong")},
        "walk per recording": c["walk per recording"],
    }


def flagged_share(model, recs) -> tuple[float, int]:
    from gaitml.models import predict_recording

    n = k = 0
    for r in recs:
        p = predict_recording(model, r)
        n += len(p)
        k += int(sum(v is False for v in p["in_domain"]))
    return (k / n if n else float("nan")), n


def md(df: pd.DataFrame) -> str:
    cols = list(df.columns)
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in df.to_dict("records"):
        out.append("| " + " | ".join(f"{v:.2f}" if isinstance(v, float) else str(v) for v in r.values()) + " |")
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--models", default="models/demo,models/demo-acc", help="model folders, comma-separated")
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--run-cadence", default=None, metavar="on|off|HZ", help="predict's run-cadence rule (default: the library's)")
    ap.add_argument("--rates", default="native", help="comma-separated: 'native' (as recorded) and/or rates in Hz to record at")
    ap.add_argument(
        "--no-rate-check",
        action="store_true",
        help="lab: drop the models' training rate (domain min_rate_hz) so that only the features decide (what a model answers below its rates)",
    )
    a = ap.parse_args(argv)
    from gaitml.commands.predict import run_cadence_arg

    run_cad = run_cadence_arg(a.run_cadence)
    rates = [None if r == "native" else float(r) for r in a.rates.split(",") if r]
    if a.out and a.out.exists():
        a.out.unlink()
    for rate in rates:
        print(f"\n## Recorded {'as they are' if rate is None else f'at {rate:g} Hz'}" + (" (rate check off)" if a.no_rate_check else ""))
        _tables(a, rate, run_cad)
    return 0


def _tables(a, rate, run_cad):
    from gaitml.io import read_dataset, read_recording
    from gaitml.models import load_model
    from gaitml.simulate import simulate_dataset

    models = {m: load_model(m) for m in a.models.split(",") if m}
    if a.no_rate_check:
        for m in models.values():
            if m.domain is not None:
                m.domain.min_rate_hz = None
    text: list[str] = []

    def emit(s=""):
        print(s)
        text.append(s)

    rows = []
    ox = a.data / "oxford-step-counter" / "optimisation"
    if ox.exists():
        recs = read_dataset(ox)
        by_pos: dict[str, list] = {}
        for r in recs:
            by_pos.setdefault(str(r.meta.get("position", "")).lower(), []).append(r)
        for pos in OXFORD_POSITIONS:
            its = by_pos.get(pos.lower(), [])
            for name, m in models.items():
                if "gyro" in m.feature_set or not its:
                    continue
                rows.append(_share_row(f"Oxford {pos} ({len(its)} walks)", name, score_walk(m, at(its, rate), run_cad)))
                print(f"[default_model] Oxford {pos}, {name}", file=sys.stderr)
    ifsm = a.data / "ifsm-flat-phone"
    if ifsm.exists():
        recs = [read_recording(f) for f in sorted(ifsm.glob("*.xlsx"))]
        for name, m in models.items():
            if "gyro" not in m.feature_set:
                rows.append(_share_row(f"IFSM flat-held phone ({len(recs)} walks)", name, score_walk(m, at(recs, rate), run_cad)))
    if rows:
        emit("### Real walking the models never saw (every window; no gyroscope: accelerometer-only models)\n")
        emit(md(pd.DataFrame(rows)))
    sim = list(simulate_dataset(n_subjects=2, duration_s=120.0, pose="mixed", seed=HELDOUT_SEED, positions=("bag", "belt")))
    urows = []
    for name, m in models.items():
        for pos in ("bag", "belt"):
            share, n = flagged_share(m, at([r for r in sim if r.meta["position"] == pos], rate))
            urows.append(
                {"what": f"simulator {pos} (seed {HELDOUT_SEED}, 2 subjects, five modes)", "model": name, "windows": n, "flagged": share}
            )
        gm = a.data / "gaitmap-example" / "imu_sample.csv.gz"
        if gm.exists():
            share, n = flagged_share(m, at([read_recording(gm, sensor=s) for s in ("left", "right")], rate))
            urows.append({"what": "gaitmap foot-mounted IMU (both feet)", "model": name, "windows": n, "flagged": share})
    emit("\n### Untrained positions and sensors: share of windows flagged out of domain\n")
    emit(md(pd.DataFrame(urows)))
    from experiments.scripts.tyrex_modes import side_summary, sim_side_table
    from gaitml.simulate.positions import POSITIONS

    for name, m in models.items():
        trained = [p for p in POSITIONS if p in (m.domain.positions if m.domain is not None else {})]
        if not trained:
            continue
        held = list(simulate_dataset(n_subjects=4, duration_s=120.0, pose="mixed", seed=HELDOUT_SEED, positions=tuple(trained)))
        tabs = []
        for subj in sorted({r.meta["subject"] for r in held}):
            t = sim_side_table(m, at([r for r in held if r.meta["subject"] == subj], rate))
            t["left_out"] = subj
            tabs.append(t)
        emit(f"\n### {name}: held-out simulator (seed {HELDOUT_SEED}, 4 subjects x 120 s) in its simulated positions\n")
        emit(md(side_summary(tabs).rename(columns={"right over folds": "right over subjects"})))
    if a.out:
        with open(a.out, "a") as fh:
            off = " (rate check off)" if a.no_rate_check else ""
            fh.write(f"\n## Recorded {'as they are' if rate is None else f'at {rate:g} Hz'}{off}\n\n" + "\n".join(text) + "\n")


if __name__ == "__main__":
    raise SystemExit(main())
