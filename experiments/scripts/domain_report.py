"""Out-of-domain check of motion-mode models on real recordings unlike their training data (issue 12).

Run from the repository root::

    python -m experiments.scripts.domain_report [--data ../shared/data] [--out experiments/reports/model-domain.md]

Models (all trained on the simulator, hand-held phone flat or tilted, five modes, the
settings of ``experiments/demo.toml``):

- ``demo``: ``models/demo`` as committed (``all52+gyro``, phone frame);
- ``acc-phone``: the same config with ``features.set = "all52"`` (no gyroscope, for the
  accelerometer-only Oxford and IFSM recordings), phone frame;
- ``acc-gravity``: the same with ``features.frame = "gravity"``.

The last two are trained here into a temporary folder (``gaitml train`` with the
overrides, no cross-validation), about a minute each.

Tables: every real walking recording in the shared data (Oxford optimisation set per
carrying position, the IFSM flat-held phone, the gaitmap foot-mounted IMU) with the
fraction of windows flagged out of domain, the fraction read as ``walk`` among the
in-domain windows and among all, and the fraction *silently wrong* (in domain and not
``walk``: every real recording here is walking). Then held-out simulated subjects of
the training positions (new seeds), the same subjects with the phone held another way
(rotated copies), and the cost of the check.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_DATA = ROOT.parent / "shared" / "data"
OXFORD_POSITIONS = {
    "inhand": "InHand",
    "frontpocket": "FrontPocket",
    "backpocket": "BackPocket",
    "purse": "Purse",
    "swingingarm": "SwingingArm",
    "neckpouch": "NeckPouch",
    "armband": "Armband",
}


def train_variant(out: Path, fset: str, frame: str):
    """``experiments/demo.toml`` with another feature set / frame, trained without CV."""
    from gaitml.experiments.config import load_config
    from gaitml.experiments.runner import train_config

    cfg = load_config(ROOT / "experiments" / "demo.toml").with_values(
        {"features.set": fset, "features.frame": frame, "train.cross_validate": False, "name": f"demo-{fset}-{frame}"}
    )
    return train_config(cfg, out_dir=out, progress=False)


def score(model, rec) -> dict:
    """Windows, out-of-domain fraction, walk fractions of one recording."""
    from gaitml.models import predict_recording

    t = predict_recording(model, rec)
    ind = t["in_domain"].to_numpy(dtype=object)
    known = np.array([v is not None for v in ind])
    ok = np.array([bool(v) if v is not None else True for v in ind])
    walk = (t["mode"] == "walk").to_numpy()
    return {
        "windows": len(t),
        "ood": int((known & ~ok).sum()),
        "walk_in": int((walk & ok).sum()),
        "in": int(ok.sum()),
        "walk_all": int(walk.sum()),
        "silent": int((ok & ~walk).sum()),
    }


def _row(label: str, model: str, s: dict) -> dict:
    n = max(s["windows"], 1)
    return {
        "data": label,
        "model": model,
        "windows": s["windows"],
        "flagged out of domain": s["ood"] / n,
        "walk among in-domain": s["walk_in"] / s["in"] if s["in"] else float("nan"),
        "walk among all": s["walk_all"] / n,
        "silently wrong": s["silent"] / n,
    }


def _add(a: dict, b: dict) -> dict:
    return {k: a.get(k, 0) + b[k] for k in b}


def real_table(data: Path, models: dict) -> pd.DataFrame:
    from gaitml.io import read_dataset, read_recording

    rows = []
    ox = data / "oxford-step-counter" / "optimisation"
    if ox.exists():
        recs = read_dataset(ox)
        by_pos: dict[str, list] = {}
        for r in recs:
            pos = OXFORD_POSITIONS.get(str(r.meta.get("position", "")).lower(), str(r.meta.get("position")))
            by_pos.setdefault(pos, []).append(r)
        for pos in OXFORD_POSITIONS.values():
            for name in ("acc-phone", "acc-gravity"):
                tot: dict = {}
                for r in by_pos.get(pos, []):
                    tot = _add(tot, score(models[name], r))
                if tot:
                    rows.append(_row(f"Oxford {pos} ({len(by_pos[pos])} walks)", name, tot))
    ifsm = data / "ifsm-flat-phone"
    if ifsm.exists():
        files = sorted(ifsm.glob("*.xlsx"))
        for name in ("acc-phone", "acc-gravity"):
            tot = {}
            for f in files:
                tot = _add(tot, score(models[name], read_recording(f)))
            rows.append(_row(f"IFSM flat-held phone ({len(files)} walks)", name, tot))
    gm = data / "gaitmap-example" / "imu_sample.csv.gz"
    if gm.exists():
        for name in ("demo", "acc-phone", "acc-gravity"):
            tot = {}
            for sensor in ("left", "right"):
                tot = _add(tot, score(models[name], read_recording(gm, sensor=sensor)))
            rows.append(_row("gaitmap foot-mounted IMU (both feet)", name, tot))
    return pd.DataFrame(rows)


def simulated_table(models: dict, seed: int = 2024, subjects: int = 8) -> pd.DataFrame:
    """Held-out simulated subjects (another seed than the models' 1000) and rotated copies."""
    from scipy.spatial.transform import Rotation

    from gaitml.models import predict_recording
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(n_subjects=subjects, duration_s=120.0, pose="mixed", seed=seed)
    cases = {
        "held-out subjects, phone in the hand (flat/tilted)": None,
        "same, phone turned upright (90 deg about x)": Rotation.from_euler("x", 90, degrees=True).as_matrix(),
        "same, phone upside down (180 deg about y)": Rotation.from_euler("y", 180, degrees=True).as_matrix(),
        "same, random constant rotation per subject": "random",
    }
    rows = []
    for label, q in cases.items():
        for name, model in models.items():
            tot, correct, n_lab = {}, 0, 0
            for i, r in enumerate(recs):
                if q is None:
                    rr = r
                else:
                    m = Rotation.random(random_state=seed + i).as_matrix() if isinstance(q, str) else q
                    rr = r.replace(acc=r.acc @ m.T, gyr=r.gyr @ m.T, check_units=False)
                t = predict_recording(model, rr)
                ind = t["in_domain"].to_numpy(dtype=object)
                ok = np.array([bool(v) for v in ind])
                tot = _add(tot, {"windows": len(t), "ood": int((~ok).sum())})
                lab = t["label"].to_numpy() if "label" in t else None
                if lab is not None:
                    sel = t["label_fraction"].to_numpy() >= 0.5
                    correct += int((t["mode"].to_numpy()[sel] == lab[sel]).sum())
                    n_lab += int(sel.sum())
            rows.append(
                {
                    "data": label,
                    "model": name,
                    "windows": tot["windows"],
                    "flagged out of domain": tot["ood"] / tot["windows"],
                    "mode accuracy (all windows)": correct / n_lab if n_lab else float("nan"),
                }
            )
    return pd.DataFrame(rows)


def frame_cv_table(seed: int = 5, subjects: int = 8) -> pd.DataFrame:
    """Leave-one-subject-out accuracy, phone vs gravity frame (simulated hand-held phones, five modes)."""
    from gaitml.evaluation.cv import cross_validate
    from gaitml.models import build_window_dataset
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(n_subjects=subjects, duration_s=150.0, pose="mixed", seed=seed)
    groups = [r.meta["subject"] for r in recs]
    rows = []
    for fset in ("all52", "all52+gyro"):
        for frame in ("phone", "gravity"):
            ds = build_window_dataset(recs, groups=groups, length_s=1.5, overlap=0.5, feature_set=fset, frame=frame)
            res = cross_validate(ds, "linear-ovo-svm", {"C": 1.0}, progress=False, seed=seed)
            pc = res.before["per_class"]
            rows.append(
                {
                    "data": f"{subjects} simulated subjects x 150 s, LOSO, SVM",
                    "model": f"{fset}, {frame} frame",
                    "mode accuracy (all windows)": res.before["accuracy"],
                    **{f"F1 {m}": pc[m]["f1"] for m in ("walk", "backward", "run", "side_left", "side_right")},
                }
            )
    return pd.DataFrame(rows)


def cost_table(model, repeats: int = 3) -> pd.DataFrame:
    """predict_recording time of a 10-minute recording with and without the domain check."""
    from gaitml.models import predict_recording
    from gaitml.simulate import simulate_dataset

    rec = simulate_dataset(n_subjects=1, duration_s=600.0, pose="mixed", seed=77)[0]
    dom = model.domain
    n = len(predict_recording(model, rec))
    out = []
    for label, d in (("without the domain check", None), ("with the domain check", dom)):
        model.domain = d
        best = min(_timed(lambda: predict_recording(model, rec)) for _ in range(repeats))
        out.append({"predict (10 min at 50 Hz)": label, "best of 3 (s)": best, "windows/s": n / best})
    model.domain = dom
    return pd.DataFrame(out)


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


_PCT = (
    "flagged out of domain",
    "walk among in-domain",
    "walk among all",
    "silently wrong",
    "mode accuracy (all windows)",
    "F1 walk",
    "F1 backward",
    "F1 run",
    "F1 side_left",
    "F1 side_right",
)


def _md(df: pd.DataFrame) -> str:
    """Markdown table; fractions as percentages, other floats with 3 significant digits."""
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" if c in ("data", "model") else "---:" for c in cols) + "|"]
    for _, r in df.iterrows():
        cells = []
        for c in cols:
            v = r[c]
            if isinstance(v, float):
                cells.append("-" if not np.isfinite(v) else (f"{100 * v:.1f} %" if c in _PCT else f"{v:.3g}"))
            else:
                cells.append(str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the shared data folder (default ../shared/data)")
    ap.add_argument("--out", type=Path, help="write the tables as markdown to this file")
    args = ap.parse_args(argv)
    from gaitml.models import load_model

    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        models = {"demo": load_model(ROOT / "models" / "demo")}
        for name, fset, frame in (("acc-phone", "all52", "phone"), ("acc-gravity", "all52", "gravity")):
            print(f"training {name} ...", file=sys.stderr, flush=True)
            train_variant(Path(tmp) / name, fset, frame)
            models[name] = load_model(Path(tmp) / name)
        thresholds = pd.DataFrame(
            [
                {
                    "model": k,
                    "frame": m.frame,
                    "feature set": m.feature_set,
                    "distance threshold held out": m.domain.distance_threshold,
                    "in sample": m.domain.distance_threshold_in_sample,
                    "gravity threshold held out (deg)": np.degrees(m.domain.gravity_threshold_rad) if m.domain.gravity_check else np.nan,
                }
                for k, m in models.items()
            ]
        )
        print("real recordings ...", file=sys.stderr, flush=True)
        real = real_table(args.data, models)
        print("simulated ...", file=sys.stderr, flush=True)
        sim = simulated_table(models)
        cost = cost_table(models["demo"])
        print("phone vs gravity frame (cross-validation) ...", file=sys.stderr, flush=True)
        frames = frame_cv_table()
    text = "\n\n".join(
        [
            "### Domain thresholds of the models\n\n" + _md(thresholds),
            "### Real walking recordings\n\n" + _md(real),
            "### Simulated held-out subjects (seed 2024, 8 subjects x 120 s, all five modes)\n\n" + _md(sim),
            "### Cost of the check\n\n" + _md(cost),
            "### Phone vs gravity frame on the simulator (seed 5, before the adjacent-window correction)\n\n" + _md(frames),
            f"(run time {time.perf_counter() - t0:.0f} s)",
        ]
    )
    print(text)
    if args.out:
        args.out.write_text(text + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
