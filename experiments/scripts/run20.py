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
domain record's feature scale, and as per-feature z against the nearest training class's Gaussian), and what moves
the linear SVM's run-vs-walk machine.

``--adopt BASE CAND``: the report's adoption rule for a post-hoc flag (:data:`CANDIDATES`, :func:`apply_candidate`,
``tyrex_modes --candidate``) read off two ``tyrex_modes --out STEM.md --csv STEM.csv`` runs. ``--cadence-check``:
where the ``walk-cadence`` flag fires on walking, the default detector's cadence against the motion capture's.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

RATE_HZ = 20.0


#: The lab candidates of the report's "Running in a pocket at 20 Hz" section (post-hoc flags on predict's table).
CANDIDATES = ("walk-cadence", "walk-run-nearest")
#: ``out_of_domain_reason`` of the windows a candidate flags.
CANDIDATE_REASON = {"walk-cadence": "walk at a running cadence", "walk-run-nearest": "walk / run disagree"}


def lowest_window_cadence(recording, windows: pd.DataFrame, steps: pd.DataFrame, reach_s: float) -> np.ndarray:
    """The lowest ``cadence_hz`` of the steps whose peak lies in each window or within ``reach_s`` of it (NaN: none).

    The mirror of :func:`gaitml.models._predict.window_step_cadence` (which takes the highest): a window counts as
    at a running cadence only when every step near it is.
    """
    from gaitml.models._predict import window_step_cadence

    return window_step_cadence(recording, windows, reach_s, steps, reduce=np.min)


def nearest_domain_class(model, rec) -> np.ndarray:
    """The domain record's nearest class (Mahalanobis, its per-class Gaussians) of every window predict reads of ``rec`` (at the model's rate)."""
    from experiments.scripts.running_flags import feature_z
    from gaitml.features import features_from_arrays
    from gaitml.models._predict import _windows_for, domain_view

    dom = model.domain
    w = _windows_for(rec, model.length_s, model.overlap)
    seen = domain_view(dom, rec)[0]
    L = int(round(model.length_s * model.sampling_rate_hz))
    gyr = seen.gyr if "gyro" in dom.feature_set else None
    X = features_from_arrays(seen.acc, gyr, rec.sampling_rate_hz, w["start"].to_numpy(np.int64), L, dom.feature_set, dom.frame)
    return np.asarray(dom.classes)[feature_z(dom, X)[0]]


def apply_candidate(p: pd.DataFrame, model, recording, name: str | None) -> pd.DataFrame:
    """``p`` (:func:`gaitml.models.predict_recording` of ``recording``) with candidate ``name``'s flags (None: ``p`` itself).

    ``walk-cadence``: an in-domain window answered ``walk`` whose :func:`lowest_window_cadence` is at least
    :data:`gaitml.models._predict.RUN_MIN_CADENCE_HZ` (140 steps/min, the walk-to-run transition) is flagged.
    ``walk-run-nearest``: an in-domain window answered ``walk`` whose :func:`nearest_domain_class` is ``run``, or
    answered ``run`` whose nearest class is ``walk``, is flagged.
    """
    if not name or len(p) == 0:
        return p
    from gaitml.models import resample_recording
    from gaitml.models._predict import RUN_CADENCE_REACH_S, RUN_MIN_CADENCE_HZ, recording_steps

    p = p.copy()
    rec = resample_recording(recording, model.sampling_rate_hz)
    inside = p["in_domain"].map(lambda v: v is True or v == True).to_numpy(bool)  # noqa: E712
    mode = p["mode"].astype(str).to_numpy()
    if name == "walk-cadence":
        hit = inside & (mode == "walk")
        if hit.any():
            cad = lowest_window_cadence(rec, p, recording_steps(rec), RUN_CADENCE_REACH_S)
            with np.errstate(invalid="ignore"):
                hit &= cad >= RUN_MIN_CADENCE_HZ
    elif name == "walk-run-nearest":
        hit = inside & np.isin(mode, ["walk", "run"])
        if hit.any():
            near = nearest_domain_class(model, rec)
            hit &= ((mode == "walk") & (near == "run")) | ((mode == "run") & (near == "walk"))
    else:
        raise ValueError(f"unknown candidate {name!r}; one of {CANDIDATES}")
    if hit.any():
        flags = p["in_domain"].to_numpy(dtype=object).copy()
        flags[hit] = False
        reason = p["out_of_domain_reason"].to_numpy(dtype=object).copy()
        reason[hit] = CANDIDATE_REASON[name]
        p["in_domain"], p["out_of_domain_reason"] = flags, reason
    p["candidate_flag"] = hit
    return p


def fold_model_dir(cache: Path, recipe: str, person: str) -> Path:
    """The cached fold model of ``recipe`` with ``person`` left out (one per person in ``cache/models``)."""
    found = sorted((cache / "models").glob(f"*-{recipe}-{person}-*"))
    if len(found) != 1:
        raise SystemExit(
            f"expected one fold model for {person} under {cache / 'models'}, found {len(found)}; pass --model-cache of tyrex_modes"
        )
    return found[0]


def window_rows(model, rec, mode: str) -> pd.DataFrame:
    """The prediction table of ``rec`` with the model's features (``f:<name>``) and the domain ratios, moving windows only.

    ``window_steps`` is replaced by the count of the default detector's steps (:func:`gaitml.models._predict.recording_steps`
    at the model's rate, whose cadence ``step_cadence_hz`` reads) in every window: predict's column holds the still
    gate's veto counts only where the gate reads a window still, NaN in a moving window.
    """
    from gaitml.models import predict_recording, resample_recording
    from gaitml.models._predict import model_inputs, model_view, recording_steps, window_step_counts

    p = predict_recording(model, rec)
    r50 = resample_recording(rec, model.sampling_rate_hz)
    p["window_steps"] = window_step_counts(p, recording_steps(r50)).astype(float)
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


def tyrex_shares(csv: Path, rate: float | None) -> pd.DataFrame:
    """Per motion (and ``all``): right / flagged / silently wrong shares pooled over the left-out people, and per person,
    from a ``tyrex_modes --csv`` file (``rate`` None: as recorded; else the rows scored at that rate)."""
    t = pd.read_csv(csv)
    if "left_out" not in t or t["left_out"].isna().all():  # a shipped model scored in sample: per person instead
        t = t.assign(left_out=t["subject"])
    t = t[t["left_out"].notna()]
    if "score_rate_hz" in t:
        rr = t["score_rate_hz"]
        native = rr.isna() if rr.isna().any() else rr == rr.max()  # a shipped model's rows carry their rate, a recipe's native rows none
        t = t[native] if rate is None else t[t["score_rate_hz"] == rate]
    rows = []
    for motion in [*sorted(t["motion"].unique()), "all"]:
        g = t if motion == "all" else t[t["motion"] == motion]
        n = g["n"].sum()
        per = g.groupby("left_out")[["right", "flagged", "wrong", "n"]].sum()
        rows.append(
            {
                "motion": motion,
                "n": int(n),
                **{k: g[k].sum() / n for k in ("right", "flagged", "wrong")},
                "right per left-out": "/".join(f"{v:.2f}" for v in per["right"] / per["n"]),
                "wrong per left-out": "/".join(f"{v:.2f}" for v in per["wrong"] / per["n"]),
            }
        )
    return pd.DataFrame(rows).set_index("motion")


def adoption(base: Path, cand: Path, rate: float = RATE_HZ) -> tuple[list[str], list[str]]:
    """The report's adoption rule for a candidate: (failed criteria, table lines). ``base``, ``cand``: the stems of two
    ``tyrex_modes --out STEM.md --csv STEM.csv`` runs (before, with ``--candidate``)."""
    from experiments.scripts.rates_adoption import _find, _spread, read_tables

    fails, lines = [], []
    for r in (None, rate):
        b, c = tyrex_shares(base.with_suffix(".csv"), r), tyrex_shares(cand.with_suffix(".csv"), r)
        at = "as recorded" if r is None else f"{r:g} Hz"
        for m in b.index:
            dw = c.loc[m, "wrong"] - b.loc[m, "wrong"]
            moved = max(abs(c.loc[m, k] - b.loc[m, k]) for k in ("right", "flagged", "wrong"))
            bad = []
            if dw > 1e-12:
                bad.append("1: silently wrong rises")
            if r is None and moved > 0.01 + 1e-12:
                bad.append("3: native figure moves > 0.01")
            if r == rate and m == "RunningPocket" and not dw < 0:
                bad.append("2: RunningPocket's silently wrong does not fall")
            fails += [f"tyrex {m} {at}: {x}" for x in bad]
            lines.append(
                f"| {m} | {at} | {b.loc[m, 'right']:.3f} / {b.loc[m, 'flagged']:.3f} / {b.loc[m, 'wrong']:.3f} | "
                f"{c.loc[m, 'right']:.3f} / {c.loc[m, 'flagged']:.3f} / {c.loc[m, 'wrong']:.3f} | {c.loc[m, 'right per left-out']} | "
                f"{c.loc[m, 'wrong per left-out']} | {'; '.join(bad) or 'ok'} |"
            )
    tb, tc = read_tables(base.with_suffix(".md")), read_tables(cand.with_suffix(".md"))
    for title, avoid in (("held-out simulator (seed", None), (f"held-out simulator recorded at {rate:g} Hz", "without the rate check")):
        sb, sc = _find(tb, title, avoid=avoid), _find(tc, title, avoid=avoid)
        for rb, rc in zip(sb, sc, strict=True):
            sp = _spread(rb["right over folds"])
            if float(rc["right"]) < float(rb["right"]) - sp - 1e-9:
                fails.append(f"simulator {title} {rb['position']} {rb['mode']}: {rb['right']} -> {rc['right']} (spread {sp:.2f})")
            elif rc["right"] != rb["right"]:
                lines.append(
                    f"| sim {rb['position']} {rb['mode']} | {title} | right {rb['right']} | {rc['right']} | spread {sp:.2f} | | ok |"
                )
    for title in ("not trained on, flagged", f"not trained on, recorded at {rate:g} Hz, flagged"):
        for rb, rc in zip(_find(tb, title), _find(tc, title), strict=True):
            fb = [float(v) for v in rb["flagged"].split("/")]
            fc = [float(v) for v in rc["flagged"].split("/")]
            ok = all(y >= x for x, y in zip(fb, fc, strict=True))
            fails += [] if ok else [f"untrained {rb['what']} ({title}): {rb['flagged']} -> {rc['flagged']}"]
            lines.append(f"| {rb['what']} | {title} | {rb['flagged']} | {rc['flagged']} | | | {'ok' if ok else 'FALLS'} |")
    return fails, lines


def cadence_check(data: Path, cache: Path, recipe: str = "a", motions=("Phoning", "Texting", "BackPocket")) -> pd.DataFrame:
    """Per recording of ``motions``: the moving windows candidate ``walk-cadence`` flags (each person's fold model) and the
    step cadence there by the default detector (:func:`lowest_window_cadence`) and by the motion capture
    (:func:`experiments.scripts.tyrex_steps.mocap_steps`: steps per second from the median interval of the capture's steps
    within 1 s of the window; a stride motion's events count two steps), beside the same for the other moving windows."""
    from experiments.scripts.tyrex_modes import load_tyrex_labelled
    from experiments.scripts.tyrex_steps import mocap_steps
    from gaitml.models import load_model, predict_recording
    from gaitml.models._predict import RUN_CADENCE_REACH_S, recording_steps

    rows, models = [], {}
    for it in [i for i in load_tyrex_labelled(data) if i["motion"] in motions]:
        person = it["subject"]
        if person not in models:
            models[person] = load_model(fold_model_dir(cache, recipe, person))
        model, rec = models[person], it["recording"]
        p = predict_recording(model, rec)
        f = apply_candidate(p, model, rec, "walk-cadence")["candidate_flag"].to_numpy(bool)
        mv = ((p["label"].astype(str) == "walk") & (p["label_fraction"] >= 0.5)).to_numpy()
        det = lowest_window_cadence(rec, p, recording_steps(rec), RUN_CADENCE_REACH_S)
        cap = mocap_steps(it["truth"], it["motion"])
        ts = np.sort(np.asarray(cap["t_s"]) - rec.meta["t0_original_s"])

        def mocap_rate(a, b, ts=ts, per=cap["steps_per_event"]):
            s = ts[(ts >= a - 1.0) & (ts <= b + 1.0)]
            return per / float(np.median(np.diff(s))) if len(s) > 2 else np.nan

        cad = np.array([mocap_rate(a, b) for a, b in zip(p["t_start_s"], p["t_end_s"], strict=True)])
        if not (f & mv).any():
            continue
        rows.append(
            {
                "left out": person,
                "phone": it["phone"],
                "motion": it["motion"],
                "moving windows": int(mv.sum()),
                "flagged": int((f & mv).sum()),
                "detector, flagged": float(np.nanmedian(det[f & mv])),
                "motion capture, flagged": float(np.nanmedian(cad[f & mv])),
                "detector, other moving": float(np.nanmedian(det[mv & ~f])),
                "motion capture, other moving": float(np.nanmedian(cad[mv & ~f])),
            }
        )
    return pd.DataFrame(rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--model-cache", type=Path, default=None, help="the fold models (required for the diagnosis)")
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--motions", default="RunningPocket")
    ap.add_argument("--rate", type=float, default=RATE_HZ)
    ap.add_argument("--csv", type=Path, default=None, help="per-window table (both rates side by side)")
    ap.add_argument(
        "--adopt",
        nargs=2,
        type=Path,
        metavar=("BASE", "CAND"),
        default=None,
        help="apply the adoption rule to two tyrex_modes runs (stems of --out STEM.md --csv STEM.csv) instead of the diagnosis",
    )
    ap.add_argument(
        "--cadence-check",
        action="store_true",
        help="the walking windows candidate walk-cadence flags: the detector's cadence against the motion capture's (needs --model-cache)",
    )
    a = ap.parse_args(argv)
    if a.cadence_check:
        if a.model_cache is None:
            ap.error("--cadence-check needs --model-cache")
        from experiments.scripts.tyrex_modes import md

        print(md(cadence_check(a.data, a.model_cache, a.recipe)))
        return 0
    if a.adopt:
        fails, lines = adoption(*a.adopt, rate=a.rate)
        print("| what | rate / table | before (right / flagged / wrong) | after | right per left-out | wrong per left-out | verdict |")
        print("|---|---|---|---|---|---|---|")
        print("\n".join(lines))
        print("\nadoption rule:", "MET" if not fails else "NOT MET: " + "; ".join(fails))
        return 0
    if a.model_cache is None:
        ap.error("--model-cache is required for the diagnosis (the fold models of tyrex_modes --model-cache)")
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
            est = model.estimator
            cls = [str(c) for c in getattr(est, "classes_", [])]
            if hasattr(est, "pairs_") and {"run", "walk"} <= set(cls):
                i, j = sorted((cls.index("run"), cls.index("walk")))
                k = int(np.flatnonzero((est.pairs_[:, 0] == i) & (est.pairs_[:, 1] == j))[0])
                sign = 1.0 if cls[i] == "run" else -1.0  # positive: run
                fn = list(model.feature_names)
                for sfx in ("_nat", "_20"):
                    Xm = m[[f"f:{q}{sfx}" for q in fn]].to_numpy(float)
                    m[f"run_vs_walk{sfx}"] = sign * (Xm @ est.coef_[k] + est.intercept_[k])
                dX = m[[f"f:{q}_20" for q in fn]].to_numpy(float) - m[[f"f:{q}_nat" for q in fn]].to_numpy(float)
                contrib = pd.DataFrame(sign * dX * est.coef_[k], columns=[f"dmargin:{q}" for q in fn], index=m.index)
                m = pd.concat([m, contrib], axis=1)
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
    if "run_vs_walk_nat" in t:
        print(
            f"\nthe run-vs-walk machine of the linear OVO SVM (positive: run), median: wrong-at-{a.rate:g} windows "
            f"{wr['run_vs_walk_nat'].median():+.2f} as recorded -> {wr['run_vs_walk_20'].median():+.2f} at {a.rate:g} Hz; "
            f"windows right at both rates {ok['run_vs_walk_nat'].median():+.2f} -> {ok['run_vs_walk_20'].median():+.2f}"
        )
        dc = [c for c in t.columns if c.startswith("dmargin:")]
        mw = wr[dc].median()
        top = mw.abs().sort_values(ascending=False).index[:10]
        print(f"\n## what moves that margin most in the wrong-at-{a.rate:g} windows (median of coefficient x feature change)\n")
        print(
            md(
                pd.DataFrame(
                    {"feature": [c[8:] for c in top], "margin change, wrong@20": mw[top].values, "right both": ok[top].median().values}
                )
            )
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
