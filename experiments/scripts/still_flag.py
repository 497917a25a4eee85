"""Mark a window unsure where the still gate reads it still but the gyroscope's stride rhythm says the body walks.

``python -m experiments.scripts.still_flag [--data ../shared/data] [--model-cache DIR] [--vs-cache DIR] [--out FILE]``
from the repository root.

The still gate (:func:`gaitml.models._predict.still_windows`, with its step veto) reports ``still`` for the calm
phone-at-ear walker whose |acc| varies as little as a standing hand and whose steps the veto's detector misses
(experiments/reports/still-gate.md, vetoswing). The gyroscope's stride rhythm reaches about half of those windows but,
as a veto, reads standing windows as a mode. Here it does not decide: a window reported ``still`` that holds the rhythm
is *marked unsure* (kept ``still``, counted flagged by the scorer). Candidates, fixed before they were scored (same
report, stillflag section):

- ``rhythm``: :func:`experiments.scripts.veto_swing.stride_rhythm` around the window;
- ``rhythm+step``: ``rhythm`` and at least one of the veto's steps inside the window (``window_steps`` >= 1).

Held out: each tyrex person left out, the shipped recipe's fold models (``--model-cache``: a copy of tyrex_modes'
``--model-cache`` for experiments/demo-fwdface.toml, recipe a), through :func:`gaitml.models.predict_recording` at its
defaults, scored at the native rate and as a 20 Hz phone records it; in-sample: ``models/demo``. Model-free: the sets
of :func:`experiments.scripts.still_gate.other_data_sets` from veto_swing's cache (``--vs-cache``: ``steps.pkl`` and
``veto-swing.pkl``; computed when missing).
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["CANDIDATES", "candidate_marks", "score_table", "adoption", "main"]

PEOPLE = ("Guillaume", "Jakob", "Thibaud")
#: the baseline (the shipped defaults: nothing marked) and the two candidates fixed before scoring
CANDIDATES = ("baseline", "rhythm", "rhythm+step")
RATES = (50.0, 20.0)
#: scored beside the candidates: predict's own ``still_unsure`` column (the library's :func:`gaitml.models._predict.stride_rhythm`,
#: which band-passes each window's 15 s rather than the whole recording)
LIBRARY = "library still_unsure"
#: the rule's bounds (fixed before scoring)
PHONING_WRONG_MAX = 0.05
RIGHT_FALL_MAX = 0.01
STANDING_MARKED_MAX = 0.15


def candidate_marks(still, rhythm, window_steps) -> dict[str, np.ndarray]:
    """Which windows each candidate marks unsure: reported ``still`` and holding the stride rhythm (``rhythm+step``: and
    at least one of the veto's steps inside, ``window_steps`` >= 1; NaN counts as none)."""
    still = np.asarray(still, dtype=bool)
    r = np.asarray(rhythm, dtype=bool)
    one = np.nan_to_num(np.asarray(window_steps, dtype=float), nan=0.0) >= 1
    return {"baseline": np.zeros(len(still), dtype=bool), "rhythm": still & r, "rhythm+step": still & r & one}


def window_rows(model, rec, who: str, motion: str, true_mode: str) -> pd.DataFrame:
    """Per window of ``rec``: the columns the scorer reads, predict's ``still`` / ``window_steps`` and the rhythm."""
    from experiments.scripts.tyrex_modes import out_of_domain_windows
    from experiments.scripts.veto_swing import stride_rhythm
    from gaitml.models import predict_recording, resample_recording

    p = predict_recording(model, rec)
    r = resample_recording(rec, model.sampling_rate_hz)
    flagged = out_of_domain_windows(p)
    return pd.DataFrame(
        {
            "who": who,
            "motion": motion,
            "true_mode": true_mode,
            "label": p["label"].astype(str).to_numpy(),
            "label_fraction": p["label_fraction"].to_numpy(float),
            "mode": p["mode"].astype(str).to_numpy(),
            "flagged": flagged,
            "still": p["still"].to_numpy(bool),
            "window_steps": p["window_steps"].to_numpy(float),
            "rhythm": stride_rhythm(r, p),
            "still_unsure": p["still_unsure"].to_numpy(bool) if "still_unsure" in p else np.zeros(len(p), dtype=bool),
        }
    )


def score_table(rows: pd.DataFrame, cand: str) -> pd.DataFrame:
    """Per motion and per person (and ``all``): moving windows, right, flagged (domain or marked), silently wrong; standing
    windows, marked unsure, read as a mode."""
    if cand == LIBRARY:
        m = rows["still_unsure"].to_numpy(bool)
    else:
        m = candidate_marks(rows["still"], rows["rhythm"], rows["window_steps"])[cand]
    flagged = rows["flagged"].to_numpy(bool) | m
    ok = rows["label_fraction"].to_numpy() >= 0.5
    moving = ok & (rows["label"].to_numpy() == rows["true_mode"].to_numpy())
    standing = ok & (rows["label"].to_numpy() == "still")
    right = ~flagged & (rows["mode"].to_numpy() == rows["true_mode"].to_numpy())
    moded = ~flagged & (rows["mode"].to_numpy() != "still")
    d = pd.DataFrame(
        {
            "motion": rows["motion"].to_numpy(),
            "who": rows["who"].to_numpy(),
            "n": moving,
            "right": moving & right,
            "flagged": moving & flagged,
            "wrong": moving & ~flagged & ~right,
            "n_standing": standing,
            "standing marked": standing & m,
            "standing as a mode": standing & moded,
        }
    ).astype({c: int for c in ("n", "right", "flagged", "wrong", "n_standing", "standing marked", "standing as a mode")})
    out = []
    for motion, g in [*d.groupby("motion", sort=False), ("all", d)]:
        for who, h in [*g.groupby("who", sort=True), ("all", g)]:
            s = h.drop(columns=["motion", "who"]).sum()
            out.append({"motion": motion, "who": who, **{k: int(v) for k, v in s.items()}})
    return pd.DataFrame(out)


def shares(t: pd.DataFrame) -> pd.DataFrame:
    """:func:`score_table` as shares (of the moving windows; the standing columns of the standing windows)."""
    s = t.copy()
    for c in ("right", "flagged", "wrong"):
        s[c] = t[c] / t["n"].where(t["n"] > 0)
    for c in ("standing marked", "standing as a mode"):
        s[c] = t[c] / t["n_standing"].where(t["n_standing"] > 0)
    return s


def adoption(base: pd.DataFrame, cand: pd.DataFrame, rate: float) -> tuple[bool, pd.DataFrame]:
    """The rule fixed before scoring (pooled rows, ``who == 'all'``), for one rate: R1-R4."""
    b = base[base["who"] == "all"].set_index("motion")
    c = cand[cand["who"] == "all"].set_index("motion")
    rows = []

    def add(check, before, after, allowed, passed):
        rows.append({"rate": f"{rate:g} Hz", "check": check, "before": before, "after": after, "allowed": allowed, "pass": bool(passed)})

    w = c.loc["Phoning", "wrong"] / c.loc["Phoning", "n"]
    add(
        "R1 Phoning silently wrong",
        f"{b.loc['Phoning', 'wrong'] / b.loc['Phoning', 'n']:.4f}",
        f"{w:.4f}",
        f"<= {PHONING_WRONG_MAX}",
        w <= PHONING_WRONG_MAX,
    )
    for motion in [m for m in b.index if m != "all"]:
        add(
            f"R2 {motion} silently wrong (count)",
            int(b.loc[motion, "wrong"]),
            int(c.loc[motion, "wrong"]),
            "no rise",
            c.loc[motion, "wrong"] <= b.loc[motion, "wrong"],
        )
        rb, rc = b.loc[motion, "right"] / b.loc[motion, "n"], c.loc[motion, "right"] / c.loc[motion, "n"]
        add(f"R3 {motion} right", f"{rb:.4f}", f"{rc:.4f}", f"fall <= {RIGHT_FALL_MAX}", rc >= rb - RIGHT_FALL_MAX - 1e-12)
    ns = c.loc["all", "n_standing"]
    sm = c.loc["all", "standing marked"] / ns
    add(
        "R4 standing windows marked unsure",
        f"{b.loc['all', 'standing marked'] / ns:.4f}",
        f"{sm:.4f}",
        f"<= {STANDING_MARKED_MAX}",
        sm <= STANDING_MARKED_MAX,
    )
    add(
        "R4 standing windows read as a mode (count)",
        int(b.loc["all", "standing as a mode"]),
        int(c.loc["all", "standing as a mode"]),
        "no rise",
        c.loc["all", "standing as a mode"] <= b.loc["all", "standing as a mode"],
    )
    t = pd.DataFrame(rows)
    return bool(t["pass"].all()), t


def model_free(data: Path, cache_dir: Path, thr: float) -> pd.DataFrame:
    """The sets of :func:`experiments.scripts.still_gate.other_data_sets` made at 50 and 20 Hz: windows reported still
    (``std_lp`` < ``thr`` and fewer than 2 swing-stage steps inside: the shipped veto) and the share of all windows each
    candidate marks unsure."""
    from experiments.scripts.veto_swing import other_sets
    from gaitml.models._predict import STILL_STEP_VETO_MIN_STEPS

    f_steps, f_ev = cache_dir / "steps.pkl", cache_dir / "veto-swing.pkl"
    steps_cache = pickle.loads(f_steps.read_bytes()) if f_steps.exists() else {}
    ev_cache = pickle.loads(f_ev.read_bytes()) if f_ev.exists() else {}
    rows = []
    for rate in RATES:
        for name, d in other_sets(data, rate, steps_cache, ev_cache):
            still = (d["stat_std_lp"].to_numpy() < thr) & (d["n_swing"].to_numpy() < STILL_STEP_VETO_MIN_STEPS)
            marks = candidate_marks(still, d["rhythm"].to_numpy(), d["n_swing"].to_numpy())
            row = {"data": name, "recorded at": f"{rate:g} Hz", "windows": len(d), "reported still": float(still.mean())}
            for cnd in CANDIDATES[1:]:
                row[f"marked unsure: {cnd}"] = float(marks[cnd].mean())
            rows.append(row)
    cache_dir.mkdir(parents=True, exist_ok=True)
    f_steps.write_bytes(pickle.dumps(steps_cache))
    f_ev.write_bytes(pickle.dumps(ev_cache))
    return pd.DataFrame(rows)


def _fmt(t: pd.DataFrame) -> pd.DataFrame:
    s = shares(t)
    out = s[["motion", "who", "n", "right", "flagged", "wrong", "n_standing", "standing marked", "standing as a mode"]].copy()
    for c in ("right", "flagged", "wrong", "standing marked", "standing as a mode"):
        out[c] = out[c].map(lambda v: "-" if pd.isna(v) else f"{v:.4f}")
    return out.rename(columns={"n": "moving windows", "wrong": "silently wrong", "n_standing": "standing windows"})


def main(argv=None) -> int:
    from experiments.scripts import tyrex_modes as tm
    from experiments.scripts.run20 import fold_model_dir
    from gaitml.models import load_model
    from gaitml.models._predict import STILL_STD_LP_MS2

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument(
        "--model-cache", type=Path, required=True, help="tyrex_modes' --model-cache of experiments/demo-fwdface.toml (recipe a)"
    )
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--shipped", default="models/demo", help="the in-sample model ('' = skip)")
    ap.add_argument("--vs-cache", type=Path, default=None, help="veto_swing's cache for the model-free sets (None: skip them)")
    ap.add_argument("--rows", type=Path, default=None, help="keep the per-window rows here (pickle) and reuse them")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    rows: dict = pickle.loads(a.rows.read_bytes()) if a.rows is not None and a.rows.exists() else {}
    if not rows:
        items = tm.load_tyrex_labelled(a.data, 50.0)
        by_rate = {50.0: items, 20.0: tm.at_rate(items, 20.0)}
        for rate, its in by_rate.items():
            parts = []
            for person in PEOPLE:
                model = load_model(fold_model_dir(a.model_cache, a.recipe, person))
                parts += [window_rows(model, it["recording"], person, it["motion"], it["mode"]) for it in its if it["subject"] == person]
            rows[("held", rate)] = pd.concat(parts, ignore_index=True)
            if a.shipped:
                model = load_model(a.shipped)
                rows[("in", rate)] = pd.concat(
                    [window_rows(model, it["recording"], it["subject"], it["motion"], it["mode"]) for it in its], ignore_index=True
                )
            print(f"[still_flag] {rate:g} Hz predicted ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        if a.rows is not None:
            a.rows.write_bytes(pickle.dumps(rows))
    text: list[str] = []

    def emit(s=""):
        print(s)
        text.append(s)

    verdict = {}
    summary = []
    for (kind, rate), r in rows.items():
        names = [*CANDIDATES, LIBRARY] if r["still_unsure"].any() else list(CANDIDATES)
        tabs = {c: score_table(r, c) for c in names}
        what = "held out (each tyrex person left out, fold models)" if kind == "held" else f"in-sample ({a.shipped})"
        for c in names:
            emit(f"\n#### {what}, recorded at {rate:g} Hz: {c}\n")
            emit(tm.md(_fmt(tabs[c])))
            s = shares(tabs[c]).set_index(["motion", "who"])
            summary.append(
                {
                    "scored": kind,
                    "rate": f"{rate:g} Hz",
                    "candidate": c,
                    "Phoning right / flagged / silently wrong": "{:.3f} / {:.3f} / {:.3f}".format(
                        *s.loc[("Phoning", "all"), ["right", "flagged", "wrong"]]
                    ),
                    "Phoning right per person (G / J / T)": " / ".join(f"{s.loc[('Phoning', p), 'right']:.3f}" for p in PEOPLE),
                    "Phoning wrong per person": " / ".join(f"{s.loc[('Phoning', p), 'wrong']:.3f}" for p in PEOPLE),
                    "all wrong": f"{s.loc[('all', 'all'), 'wrong']:.4f}",
                    "standing marked (per person)": f"{s.loc[('all', 'all'), 'standing marked']:.3f} ("
                    + " / ".join(f"{s.loc[('all', p), 'standing marked']:.3f}" for p in PEOPLE)
                    + ")",
                    "standing as a mode": f"{s.loc[('all', 'all'), 'standing as a mode']:.3f}",
                }
            )
            if kind == "held" and c != "baseline":
                ok, checks = adoption(tabs["baseline"], tabs[c], rate)
                verdict.setdefault(c, []).append((ok, checks))
    emit("\n#### Summary\n")
    emit(tm.md(pd.DataFrame(summary)))
    for c, res in verdict.items():
        ok = all(v for v, _ in res)
        emit(f"\n#### The adoption rule (fixed before scoring): {c} against the baseline, held out: {'PASSES' if ok else 'FAILS'}\n")
        emit(tm.md(pd.concat([t for _, t in res], ignore_index=True)))
    if a.vs_cache is not None:
        emit(f"\n#### Model-free: windows reported still (std_lp < {STILL_STD_LP_MS2:g}, the swing veto) and marked unsure\n")
        emit(tm.md(model_free(a.data, a.vs_cache, STILL_STD_LP_MS2)))
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    print(f"[still_flag] done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
