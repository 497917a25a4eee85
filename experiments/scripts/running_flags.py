"""Why running windows of a left-out tyrex person are flagged out of domain (diagnosis, no fitting).

``python -m experiments.scripts.running_flags --data ../shared/data --model-cache /tmp/runflag/folds [--config experiments/demo.toml]``
from the repository root; the fold models are those of ``experiments.scripts.tyrex_modes --recipes a
--model-cache DIR`` (``a-<person>``: trained on the two other people, the shipped recipe).

For every moving RunningHand / RunningPocket window of the left-out person (the speed rule of
:func:`experiments.scripts.tyrex_modes.moving_labels`), read through ``gaitml predict``'s own path
(:func:`gaitml.models.predict_recording`): which part of the domain check flags it (feature distance,
gravity direction, orientation dynamics, foot-placement rule), by how much over its threshold (ratio), the
nearest class, and which standardised features lie furthest from that class's Gaussian (per-feature z =
(z_j - m_j) / sqrt(Sigma_jj), the class covariance's diagonal). Beside it, per recording, the share of raw
accelerometer samples at the phone's range (any axis within 2 % of its largest |value|, when that is
within 10 % of 2 g: the Nexus 5 and iPhone 4S clip at 2 g), over the recording and within the flagged windows.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

RUN_MOTIONS = ("RunningHand", "RunningPocket")
G = 9.80665


def clip_share(acc: np.ndarray) -> tuple[float, float, np.ndarray]:
    """(range in g, share of samples at it, per-sample mask): a sample is at the range when an axis reaches 98 % of it."""
    a = np.abs(np.asarray(acc, dtype=float))
    top = float(np.nanmax(a))
    if not (0.9 * 2 * G <= top <= 1.1 * 2 * G):  # not a 2 g phone (or it never reached its range)
        return top / G, 0.0, np.zeros(len(a), bool)
    m = (a >= 0.98 * top).any(axis=1)
    return top / G, float(m.mean()), m


def feature_z(dom, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per window: nearest class, its distance, and per-feature z against that class's Gaussian (diagonal of its covariance)."""
    Z = (X - dom.arrays["center"]) / dom.arrays["scale"]
    means, precs = dom.arrays["class_means"], dom.arrays["class_precisions"]
    d2 = np.stack([np.einsum("ij,jk,ik->i", Z - m, P, Z - m) for m, P in zip(means, precs, strict=True)], axis=1)
    k = d2.argmin(axis=1)
    sd = np.sqrt(np.stack([np.diag(np.linalg.inv(P)) for P in precs]))
    zf = (Z - means[k]) / sd[k]
    return k, np.sqrt(d2[np.arange(len(k)), k]), zf


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--model-cache", type=Path, required=True)
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--motions", default=",".join(RUN_MOTIONS))
    ap.add_argument("--csv", type=Path, default=None, help="per-window table")
    a = ap.parse_args(argv)
    from experiments.scripts.tyrex_modes import load_tyrex_labelled, md
    from gaitml.features import features_from_arrays
    from gaitml.models import load_model, predict_recording
    from gaitml.models._predict import domain_view

    motions = a.motions.split(",")
    items = [it for it in load_tyrex_labelled(a.data) if it["motion"] in motions]
    raw = {}
    from experiments.scripts.tyrex_pdr import load_tyrex

    for it in load_tyrex(a.data):
        if it["motion"] in motions:
            raw[(it["subject"], it["phone"], it["motion"])] = it["recording"]
    rows, rec_rows = [], []
    for person in sorted({it["subject"] for it in items}):
        model = load_model(a.model_cache / f"{a.recipe}-{person}")
        dom = model.domain
        thr_d, thr_g, thr_y = dom.distance_threshold, np.degrees(dom.gravity_threshold_rad), dom.dynamics["threshold"]
        print(
            f"[running_flags] {person} left out: thresholds distance {thr_d:.2f}, gravity {thr_g:.1f} deg, dynamics {thr_y:.2f}",
            file=sys.stderr,
        )
        for it in [i for i in items if i["subject"] == person]:
            rec = it["recording"]
            p = predict_recording(model, rec)
            L = int(round(model.length_s * model.sampling_rate_hz))
            starts = p["start"].to_numpy(np.int64)
            seen = domain_view(dom, rec)[0]  # the accelerometer as the record reads it (its own range, if any)
            X = features_from_arrays(seen.acc, seen.gyr, rec.sampling_rate_hz, starts, L, dom.feature_set, dom.frame)
            k, dk, zf = feature_z(dom, X)
            rng, share, _ = clip_share(raw[(it["subject"], it["phone"], it["motion"])].acc)
            # clipping on the resampled recording, per window (a window holds a clipped sample)
            a50 = np.abs(rec.acc)
            clipped = (a50 >= 0.95 * 2 * G).any(axis=1) if rng <= 2.2 else np.zeros(len(a50), bool)
            moving = (p["label"].astype(str) == it["mode"]).to_numpy() & (p["label_fraction"] >= 0.5).to_numpy()
            flagged = p["in_domain"].map(lambda v: v is False).to_numpy(bool)
            reason = p["out_of_domain_reason"].astype(str).to_numpy()
            for j in np.flatnonzero(moving):
                s = starts[j]
                top = np.argsort(-np.abs(zf[j]))[:3]
                rows.append(
                    {
                        "left_out": person,
                        "phone": it["phone"],
                        "motion": it["motion"],
                        "window": int(j),
                        "flagged": bool(flagged[j]),
                        "mode": str(p["mode"].iloc[j]),
                        "placement": "placement" in reason[j],
                        "dist_ratio": float(p["domain_distance"].iloc[j]) / thr_d,
                        "grav_deg": float(p["gravity_angle_deg"].iloc[j]),
                        "grav_ratio": float(p["gravity_angle_deg"].iloc[j]) / thr_g,
                        "dyn_ratio": float(p["dynamics_distance"].iloc[j]) / thr_y,
                        "nearest": dom.classes[k[j]],
                        "clip_frac": float(clipped[s : s + L].mean()),
                        "top_features": ";".join(f"{dom.feature_names[t]}={zf[j, t]:+.1f}" for t in top),
                        **{f"z:{n}": float(zf[j, q]) for q, n in enumerate(dom.feature_names)},
                    }
                )
            rec_rows.append(
                {
                    "left_out": person,
                    "phone": it["phone"],
                    "motion": it["motion"],
                    "acc range (g)": rng,
                    "samples at range": share,
                    "moving windows": int(moving.sum()),
                    "flagged": int((moving & flagged).sum()),
                }
            )
    w = pd.DataFrame(rows)
    r = pd.DataFrame(rec_rows)
    if a.csv:
        w.to_csv(a.csv, index=False)
    pd.set_option("display.width", 250)
    pd.set_option("display.max_columns", 30)
    print("\n## per recording: accelerometer range, samples at it, moving windows flagged\n")
    print(md(r))
    f = w[w["flagged"]].copy()
    f["feature"] = f["dist_ratio"] > 1
    f["gravity"] = f["grav_ratio"] > 1
    f["dynamics"] = f["dyn_ratio"] > 1
    print("\n## flagged moving running windows: which part flags them (a window may fail several)\n")
    g = f.groupby(["left_out", "motion"]).agg(
        flagged=("flagged", "size"),
        feature=("feature", "sum"),
        gravity=("gravity", "sum"),
        dynamics=("dynamics", "sum"),
        placement=("placement", "sum"),
        feature_only=(
            "feature",
            lambda v: int((v & ~f.loc[v.index, "gravity"] & ~f.loc[v.index, "dynamics"] & ~f.loc[v.index, "placement"]).sum()),
        ),
        dist_ratio_median=("dist_ratio", "median"),
        dist_ratio_max=("dist_ratio", "max"),
        grav_deg_median=("grav_deg", "median"),
        dyn_ratio_median=("dyn_ratio", "median"),
        with_clipped_sample=("clip_frac", lambda v: float((v > 0).mean())),
    )
    print(md(g.reset_index()))
    print("\n## in-domain vs flagged moving running windows: distance ratio, clipped-sample share of the window\n")
    h = w.groupby(["left_out", "motion", "flagged"]).agg(
        n=("flagged", "size"),
        dist_ratio=("dist_ratio", "median"),
        clip_frac=("clip_frac", "mean"),
        any_clip=("clip_frac", lambda v: float((v > 0).mean())),
    )
    print(md(h.reset_index()))
    zc = [c for c in w.columns if c.startswith("z:")]
    for (person, motion), grp in f.groupby(["left_out", "motion"]):
        if len(grp) < 5:
            continue
        ok = w[(w["left_out"] == person) & (w["motion"] == motion) & ~w["flagged"]]
        med = grp[zc].median()
        top = med.abs().sort_values(ascending=False).index[:8]
        print(
            f"\n## {person} left out, {motion}: features furthest from the nearest class (median z over {len(grp)} flagged windows; in-domain windows of the same person: {len(ok)})\n"
        )
        print(
            md(
                pd.DataFrame(
                    {
                        "feature": [c[2:] for c in top],
                        "median z flagged": med[top].values,
                        "median z in domain": ok[top].median().values if len(ok) else np.nan,
                    }
                )
            )
        )
        print("nearest classes of the flagged:", grp["nearest"].value_counts().to_dict())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
