"""Why running in a pocket recorded at 20 Hz is silently wrong (diagnosis, no fitting; issue 27).

``python -m experiments.scripts.run20 --data ../shared/data --model-cache /tmp/run20/tm [--motions RunningPocket] [--csv FILE]``
from the repository root; the fold models are those of ``experiments.scripts.tyrex_modes --config
experiments/demo.toml --recipes a --model-cache DIR`` (``models/demo-a-<person>-<hash>``: trained on the two
other people, the shipped recipe, with the 20 Hz copies).

Every moving window of the left-out person (the speed rule of
:func:`experiments.scripts.tyrex_modes.moving_labels`) is read twice through ``gaitml predict``'s own path
(:func:`gaitml.models.predict_recording`, its defaults): as recorded (the recording at 50 Hz) and taken down
to 20 Hz (:func:`experiments.scripts.tyrex_modes.at_rate`, :func:`gaitml.models.resample_recording`), the
same windows matched by their start time. Per window: the answer (``mode``, ``mode_raw``), the run-cadence
rule (``run_at_walking_cadence``, ``step_cadence_hz``), the domain check (feature distance, gravity angle,
orientation dynamics, each over its threshold) and the model's features. Printed: where the windows wrong at
20 Hz come from (person, phone), what they are read as, whether the rule moved them and their cadence at both
rates, their domain ratios at both rates, and the features that move most between the rates (in units of the
domain record's feature scale, and as per-feature z against the nearest training class's Gaussian).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

RATE_HZ = 20.0


def fold_model_dir(cache: Path, recipe: str, person: str) -> Path:
    """The cached fold model of ``recipe`` with ``person`` left out (one per person in ``cache/models``)."""
    found = sorted((cache / "models").glob(f"*-{recipe}-{person}-*"))
    if len(found) != 1:
        raise SystemExit(
            f"expected one fold model for {person} under {cache / 'models'}, found {len(found)}; pass --model-cache of tyrex_modes"
        )
    return found[0]


def window_rows(model, rec, mode: str) -> pd.DataFrame:
    """The prediction table of ``rec`` with the model's features (``f:<name>``) and the domain ratios, moving windows only."""
    from gaitml.models import predict_recording, resample_recording
    from gaitml.models._predict import model_inputs, model_view

    p = predict_recording(model, rec)
    r50 = resample_recording(rec, model.sampling_rate_hz)
    X = model_inputs(model, model_view(model, r50)[0], p[["start", "end"]])
    dom = model.domain
    p["dist_ratio"] = p["domain_distance"] / dom.distance_threshold
    p["grav_ratio"] = np.radians(p["gravity_angle_deg"]) / dom.gravity_threshold_rad
    p["dyn_ratio"] = p.get("dynamics_distance", np.nan) / dom.dynamics["threshold"] if dom.dynamics else np.nan
    feats = pd.DataFrame(X, columns=[f"f:{n}" for n in model.feature_names], index=p.index)
    p = pd.concat([p, feats], axis=1)
    moving = (p["label"].astype(str) == mode) & (p["label_fraction"] >= 0.5)
    p = p[moving].copy()
    p["key"] = np.rint(p["t_start_s"].to_numpy() * 1000).astype(np.int64)
    return p


def outcome(df: pd.DataFrame, mode: str, sfx: str) -> np.ndarray:
    flagged = df[f"in_domain{sfx}"].map(lambda v: v is False or v == False).to_numpy(bool)  # noqa: E712
    right = ~flagged & (df[f"mode{sfx}"].astype(str).to_numpy() == mode)
    return np.where(flagged, "flagged", np.where(right, "right", "wrong"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--model-cache", type=Path, required=True)
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--motions", default="RunningPocket")
    ap.add_argument("--rate", type=float, default=RATE_HZ)
    ap.add_argument("--csv", type=Path, default=None, help="per-window table (both rates side by side)")
    a = ap.parse_args(argv)
    from experiments.scripts.running_flags import feature_z
    from experiments.scripts.tyrex_modes import at_rate, load_tyrex_labelled, md
    from gaitml.models import load_model

    motions = a.motions.split(",")
    items = [it for it in load_tyrex_labelled(a.data) if it["motion"] in motions]
    low = at_rate(items, a.rate)
    parts = []
    models = {}
    for person in sorted({it["subject"] for it in items}):
        model = models[person] = load_model(fold_model_dir(a.model_cache, a.recipe, person))
        for it, it20 in zip(items, low, strict=True):
            if it["subject"] != person:
                continue
            n = window_rows(model, it["recording"], it["mode"])
            w = window_rows(model, it20["recording"], it["mode"])
            m = n.merge(w, on="key", suffixes=("_nat", "_20"))
            m["left_out"], m["phone"], m["motion"], m["true"] = person, it["phone"], it["motion"], it["mode"]
            m["out_nat"], m["out_20"] = outcome(m, it["mode"], "_nat"), outcome(m, it["mode"], "_20")
            dom = model.domain
            names = list(dom.feature_names)
            for sfx in ("_nat", "_20"):
                X = m[[f"f:{q}{sfx}" for q in names]].to_numpy(float)
                k, _, zf = feature_z(dom, X)
                m[f"nearest{sfx}"] = np.asarray(dom.classes)[k]
                for j, q in enumerate(names):
                    m[f"z:{q}{sfx}"] = zf[:, j]
            scale = dom.arrays["scale"]
            for j, q in enumerate(names):
                m[f"shift:{q}"] = (m[f"f:{q}_20"] - m[f"f:{q}_nat"]) / scale[j]
            parts.append(m)
            print(f"[run20] {person} {it['phone']} {it['motion']}: {len(n)} / {len(w)} moving windows, {len(m)} matched", file=sys.stderr)
    t = pd.concat(parts, ignore_index=True)
    if a.csv:
        keep = [c for c in t.columns if not c.startswith(("f:",))]
        t[keep].to_csv(a.csv, index=False)
    pd.set_option("display.width", 250)
    print(f"\n## outcome as recorded x at {a.rate:g} Hz (moving windows matched by start time)\n")
    print(md(pd.crosstab([t["motion"], t["out_nat"]], t["out_20"]).reset_index()))
    print("\n## per left-out person and phone: right / flagged / wrong, as recorded -> 20 Hz\n")
    g = t.groupby(["motion", "left_out", "phone"])
    rows = []
    for key, d in g:
        rows.append(
            {
                "motion": key[0],
                "left out": key[1],
                "phone": key[2],
                "windows": len(d),
                "as recorded r/f/w": "/".join(str(int((d["out_nat"] == o).sum())) for o in ("right", "flagged", "wrong")),
                "20 Hz r/f/w": "/".join(str(int((d["out_20"] == o).sum())) for o in ("right", "flagged", "wrong")),
                "wrong at 20 Hz read as": ", ".join(f"{k} {v}" for k, v in d.loc[d["out_20"] == "wrong", "mode_20"].value_counts().items()),
                "raw answer of those": ", ".join(
                    f"{k} {v}" for k, v in d.loc[d["out_20"] == "wrong", "mode_raw_20"].value_counts().items()
                ),
                "moved by run-cadence rule": int(d.loc[d["out_20"] == "wrong", "run_at_walking_cadence_20"].sum()),
            }
        )
    print(md(pd.DataFrame(rows)))
    wr = t[t["out_20"] == "wrong"]
    ok = t[(t["out_20"] == "right") & (t["out_nat"] == "right")]
    print(f"\n## the {len(wr)} windows wrong at {a.rate:g} Hz against the windows right at both rates (medians)\n")
    cols = {
        "step cadence (steps/s)": "step_cadence_hz",
        "steps in window": "window_steps",
        "feature distance / threshold": "dist_ratio",
        "gravity angle / threshold": "grav_ratio",
        "dynamics / threshold": "dyn_ratio",
    }
    rows = []
    for name, c in cols.items():
        rows.append(
            {
                "what": name,
                "wrong@20: as recorded": wr[f"{c}_nat"].median(),
                "wrong@20: at 20 Hz": wr[f"{c}_20"].median(),
                "right both: as recorded": ok[f"{c}_nat"].median(),
                "right both: at 20 Hz": ok[f"{c}_20"].median(),
            }
        )
    print(md(pd.DataFrame(rows)))
    print(
        "\nnearest domain class of the wrong-at-20 windows, as recorded:",
        wr["nearest_nat"].value_counts().to_dict(),
        "at 20 Hz:",
        wr["nearest_20"].value_counts().to_dict(),
    )
    for person, d in wr.groupby("left_out"):
        print(
            f"  {person}: cadence as recorded {d['step_cadence_hz_nat'].median():.2f}, at 20 Hz {d['step_cadence_hz_20'].median():.2f}; dist ratio {d['dist_ratio_nat'].median():.2f} -> {d['dist_ratio_20'].median():.2f}; n={len(d)}"
        )
    sc = [c for c in t.columns if c.startswith("shift:")]
    med_w = wr[sc].median()
    med_ok = ok[sc].median()
    top = med_w.abs().sort_values(ascending=False).index[:12]
    zc = lambda c, s: f"z:{c[6:]}{s}"  # noqa: E731
    print(
        f"\n## features that move most between the rates in the wrong-at-{a.rate:g} windows (median shift in units of the record's scale)\n"
    )
    print(
        md(
            pd.DataFrame(
                {
                    "feature": [c[6:] for c in top],
                    "shift, wrong@20": med_w[top].values,
                    "shift, right both": med_ok[top].values,
                    "z vs nearest class, as recorded": [wr[zc(c, "_nat")].median() for c in top],
                    "z vs nearest class, 20 Hz": [wr[zc(c, "_20")].median() for c in top],
                }
            )
        )
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
