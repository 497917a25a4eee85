"""The still gate against detected steps: does a window in which the default step detector finds steps belong to a walker?

``python -m experiments.scripts.still_steps [--data ../shared/data] [--config experiments/demo.toml] [--cache DIR] [--out FILE]``
from the repository root.

The still gate (:func:`gaitml.models._predict.still_windows`, rule ``std_lp``) answers ``still`` for a window whose
low-passed |acc| varies little. A calm walker with the phone at the ear varies it little too: every silently wrong
Phoning window of the held-out tyrex people is the gate's ``still``. The step veto: a window in which the default step
detector (``adaptive``, gait check on, run once over the recording at the model's rate, as the run-cadence rule runs
it: :func:`gaitml.models._predict.recording_steps`) finds steps is not still. What the study does:

1. The three fold models and the gate-off predictions of the left-out people at 50 Hz and as a 20 Hz phone would
   record them are :mod:`experiments.scripts.still_rate`'s (the shipped recipe with its augmentation, cached under
   ``--cache``); every window's ``std_lp`` statistic as predict computes it; the detector's steps on every recording
   at the model's rate (cached).
2. Measure, no fitting (:func:`step_share_table`): how many of the moving windows the gate reads still hold >= 1 and
   >= 2 detected steps inside the window and within +-0.5 s of it, against the standing windows (read still or not)
   and the model-free recordings of :func:`experiments.scripts.still_gate.other_data_sets`, at 50 and 20 Hz.
3. Score the candidates (fixed with the adoption rule before they were measured; experiments/reports/still-gate.md):
   ``veto`` (>= 2 steps inside the window; the gate's threshold unchanged: each fold's own ``std_lp`` threshold held
   out, 0.38 in-sample) and ``veto+T`` (the same veto, the threshold chosen again on the two training people by the
   still-gate study's criterion applied to the vetoed gate, :func:`vetoed_standing_threshold`), held out and in-sample,
   at both rates, beside the gate without the veto; the model-free share read still under each.
4. The adoption rule (:func:`adoption_checks`).
"""

from __future__ import annotations

import argparse
import pickle
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = [
    "VARIANTS",
    "adoption_checks",
    "step_counts",
    "step_share_table",
    "vetoed_standing_threshold",
    "main",
]

PEOPLE = ("Guillaume", "Jakob", "Thibaud")
HAND = ("Texting", "AR", "Phoning")
#: the step-count variants measured in step 1: name -> (minimum steps, reach beyond the window in s)
VARIANTS = {">=1 in": (1, 0.0), ">=2 in": (2, 0.0), ">=1 +-0.5 s": (1, 0.5), ">=2 +-0.5 s": (2, 0.5)}
#: the candidate veto (fixed before the candidates were scored): >= 2 steps with their peak inside the window
CANDIDATE = ">=2 in"


def step_counts(peaks: np.ndarray, windows: pd.DataFrame, fs: float) -> dict[str, np.ndarray]:
    """Per window (``start``, ``end`` samples at ``fs``): the number of step peaks inside ``[start, end)`` (``in``) and
    within 0.5 s of it (``near``)."""
    p = np.sort(np.asarray(peaks, dtype=np.int64))
    s = windows["start"].to_numpy(np.int64)
    e = windows["end"].to_numpy(np.int64)
    reach = int(round(0.5 * fs))
    return {
        "in": np.searchsorted(p, e, side="left") - np.searchsorted(p, s, side="left"),
        "near": np.searchsorted(p, e + reach, side="left") - np.searchsorted(p, s - reach, side="left"),
    }


def vetoed(counts: dict[str, np.ndarray], variant: str) -> np.ndarray:
    """Which windows the ``variant`` (:data:`VARIANTS`) vetoes."""
    k, reach = VARIANTS[variant]
    return np.asarray(counts["near" if reach else "in"]) >= k


def vetoed_standing_threshold(std_standing, range_standing, veto, range_ms2: float) -> float:
    """The ``std_lp`` threshold at which the vetoed gate reads as many standing windows still as the range rule (2 decimals).

    The still-gate study's criterion (:func:`experiments.scripts.still_gate.equal_standing_threshold`) for the gate
    ``std_lp < T and not vetoed``: a vetoed standing window is never read still, whatever T. NaN when the veto leaves
    fewer windows below any threshold than the range rule reads still.
    """
    sd = np.asarray(std_standing, dtype=float)
    share = float(np.mean(np.asarray(range_standing) < float(range_ms2)))
    free = np.sort(sd[~np.asarray(veto, dtype=bool)])
    k = int(np.ceil(share * len(sd)))
    if k > len(free):
        return float("nan")
    if k == 0:
        return 0.0
    # the smallest 2-decimal threshold that reads at least k of the free windows still
    t = np.ceil(free[k - 1] * 100.0 + 1e-9) / 100.0
    return round(float(t), 2)


def _steps_of(rec) -> np.ndarray:
    """The default detector's step peaks on ``rec`` (``adaptive`` at its defaults: the still gate's veto as this study
    adopted it; the veto now reads the swing stage's steps, :func:`gaitml.models._predict.veto_steps`)."""
    from gaitml.models._predict import recording_steps

    return recording_steps(rec)["peak"].to_numpy(np.int64)


def add_steps(model, items, preds, cache: dict, key: str) -> None:
    """Add ``n_in``, ``n_near`` (step counts, :func:`step_counts`) to each of ``preds``; the peaks cached in ``cache[key]``."""
    from gaitml.models import resample_recording

    if key not in cache:
        cache[key] = [_steps_of(resample_recording(it["recording"], model.sampling_rate_hz)) for it in items]
    for peaks, p in zip(cache[key], preds, strict=True):
        c = step_counts(peaks, p, model.sampling_rate_hz)
        p["n_in"], p["n_near"] = c["in"], c["near"]


def _share_row(what: str, motion: str, counts: dict[str, np.ndarray]) -> dict:
    n = len(counts["in"])
    row = {"windows": what, "motion": motion, "n": n}
    for name in VARIANTS:
        row[name] = float(np.mean(vetoed(counts, name))) if n else float("nan")
    return row


def step_share_table(items, preds, thr) -> pd.DataFrame:
    """Per motion: the share of windows with >= 1 / >= 2 steps inside / within +-0.5 s, for the moving windows the gate
    reads still (``std_lp`` < ``thr``: a float, or a dict person -> float), all moving windows, the standing windows read
    still, and all standing windows."""
    from experiments.scripts.tyrex_modes import MOTION_ORDER

    parts = []
    for it, p in zip(items, preds, strict=True):
        t = thr[it["subject"]] if isinstance(thr, dict) else thr
        lab = p["label"].astype(str)
        ok = (p["label_fraction"] >= 0.5).to_numpy()
        parts.append(
            pd.DataFrame(
                {
                    "motion": it["motion"],
                    "moving": ((lab == it["mode"]).to_numpy() & ok),
                    "standing": ((lab == "still").to_numpy() & ok),
                    "gated": p["stat_std_lp"].to_numpy() < t,
                    "in": p["n_in"].to_numpy(),
                    "near": p["n_near"].to_numpy(),
                }
            )
        )
    d = pd.concat(parts, ignore_index=True)
    rows = []
    for what, sel in (
        ("moving, read still", d["moving"] & d["gated"]),
        ("moving, all", d["moving"]),
        ("standing, read still", d["standing"] & d["gated"]),
        ("standing, all", d["standing"]),
    ):
        for motion in [*MOTION_ORDER, "all"]:
            g = d[sel] if motion == "all" else d[sel & (d["motion"] == motion)]
            if len(g) == 0:
                continue
            rows.append(_share_row(what, motion, {"in": g["in"].to_numpy(), "near": g["near"].to_numpy()}))
    return pd.DataFrame(rows)


def other_data_steps(data: Path, rate: float, cache: dict) -> list[tuple[str, list[pd.DataFrame]]]:
    """Per model-free set (:func:`experiments.scripts.still_gate.other_data_sets`) made at ``rate`` and read at 50 Hz as
    predict reads it: per recording, its 1.5 s windows with ``stat_std_lp`` (as recorded), ``n_in`` and ``n_near``."""
    from experiments.scripts.still_gate import other_data_sets
    from gaitml.features import make_windows
    from gaitml.models import resample_recording
    from gaitml.models._predict import still_statistic

    key = f"other-{rate:g}"
    if key in cache:
        return cache[key]
    out = []
    for name, recs in other_data_sets(data):
        tabs = []
        for r in recs:
            made = resample_recording(r, rate)
            at50 = resample_recording(made, 50.0)
            if at50.n_samples < 75:
                continue
            w = make_windows(at50, 1.5, 0.5, min_label_fraction=0.0)[["start", "end"]].reset_index(drop=True)
            w["stat_std_lp"] = still_statistic(at50, w, "std_lp", recorded=made)
            c = step_counts(_steps_of(at50), w, 50.0)
            w["n_in"], w["n_near"] = c["in"], c["near"]
            tabs.append(w)
        out.append((name, tabs))
    cache[key] = out
    return out


def other_share_table(sets, rate: float, thr: float) -> pd.DataFrame:
    """Model-free: per set, the windows read still (``std_lp`` < ``thr``) and the share of them with steps per variant."""
    rows = []
    for name, tabs in sets:
        d = pd.concat(tabs, ignore_index=True)
        g = d[d["stat_std_lp"] < thr]
        row = {"data": name, "recorded at": f"{rate:g} Hz", "windows": len(d), "read still": len(g) / len(d)}
        for v in VARIANTS:
            row[f"of them {v}"] = float(np.mean(vetoed({"in": g["n_in"].to_numpy(), "near": g["n_near"].to_numpy()}, v))) if len(g) else 0.0
        rows.append(row)
    return pd.DataFrame(rows)


def other_still_table(sets, rate: float, gates: dict) -> pd.DataFrame:
    """Model-free: per set, the share of windows read still under each gate (name -> (threshold, variant or None))."""
    rows = []
    for name, tabs in sets:
        d = pd.concat(tabs, ignore_index=True)
        row = {"data": name, "recorded at": f"{rate:g} Hz", "windows": len(d)}
        for g, (thr, var) in gates.items():
            still = d["stat_std_lp"].to_numpy() < thr
            if var is not None:
                still &= ~vetoed({"in": d["n_in"].to_numpy(), "near": d["n_near"].to_numpy()}, var)
            row[g] = float(np.mean(still))
        rows.append(row)
    return pd.DataFrame(rows)


def with_gate(preds, name: str, variant: str | None) -> None:
    """Add ``stat_<name>``: ``stat_std_lp``, +inf where ``variant`` vetoes (so that a threshold on it is the vetoed gate)."""
    for p in preds:
        s = p["stat_std_lp"].to_numpy(float).copy()
        if variant is not None:
            s[vetoed({"in": p["n_in"].to_numpy(), "near": p["n_near"].to_numpy()}, variant)] = np.inf
        p[f"stat_{name}"] = s


def adoption_checks(before: dict, after: dict, other_before: dict, other_after: dict) -> tuple[bool, pd.DataFrame]:
    """The adoption rule (fixed before the candidates were scored), per rate: ``before`` / ``after`` map a rate to the
    held-out :func:`experiments.scripts.tyrex_modes.summarise` table (indexed by motion) and to its raw per-recording
    table (``(summary, table)``); ``other_*`` map a rate to the model-free still shares (set name -> share).

    R1 no motion's silently wrong count rises; R2 Phoning's falls; R3 standing read as a mode (all motions) rises by at
    most 0.02; R4 the phone on a table and the simulated desk: the share read still falls by at most 0.02.
    """
    from experiments.scripts.tyrex_modes import MOTION_ORDER

    rows, ok = [], True
    for r in before:
        (_sb, tb), (_sa, ta) = before[r], after[r]
        for motion in MOTION_ORDER:
            wb = int(tb.loc[tb["motion"] == motion, "wrong"].sum())
            wa = int(ta.loc[ta["motion"] == motion, "wrong"].sum())
            n = int(tb.loc[tb["motion"] == motion, "n"].sum())
            passed = wa < wb if motion == "Phoning" else wa <= wb
            rows.append(
                {
                    "rate": r,
                    "check": f"{'R2' if motion == 'Phoning' else 'R1'} {motion}: silently wrong",
                    "before": f"{wb / n:.3f} ({wb})",
                    "after": f"{wa / n:.3f} ({wa})",
                    "allowed": "must fall" if motion == "Phoning" else "no rise",
                    "pass": passed,
                }
            )
            ok &= passed
        mb, ma, ns = int(tb["still_moded"].sum()), int(ta["still_moded"].sum()), int(tb["n_still"].sum())
        passed = (ma - mb) / ns <= 0.02 + 1e-12
        rows.append(
            {
                "rate": r,
                "check": "R3 standing read as a mode",
                "before": f"{mb / ns:.4f} ({mb} of {ns})",
                "after": f"{ma / ns:.4f} ({ma})",
                "allowed": "rise <= 0.02",
                "pass": passed,
            }
        )
        ok &= passed
        for name, share in other_before[r].items():
            if not (name.startswith("phone lying") or "desk" in name):
                continue
            passed = other_after[r][name] >= share - 0.02 - 1e-9
            rows.append(
                {
                    "rate": r,
                    "check": f"R4 {name}: read still",
                    "before": f"{share:.3f}",
                    "after": f"{other_after[r][name]:.3f}",
                    "allowed": "fall <= 0.02",
                    "pass": passed,
                }
            )
            ok &= passed
    return bool(ok), pd.DataFrame(rows)


def emit_verdicts(emit, held_tabs: dict, other: dict, rates, base: str, candidates, heading: str, checks=None) -> None:
    """Each candidate gate against ``base`` by the adoption rule (``checks``, default :func:`adoption_checks`), held out
    at every rate of ``rates``: ``held_tabs[(rate, gate)]`` the held-out tables, ``other[rate]`` the model-free still
    shares (a ``data`` column and one per gate); ``heading`` a section title with ``{cand}``. Emits each rule's table
    and verdict."""
    from experiments.scripts import tyrex_modes as tm

    checks = adoption_checks if checks is None else checks
    for cand in candidates:
        ok, table = checks(
            {r: held_tabs[(r, base)] for r in rates},
            {r: held_tabs[(r, cand)] for r in rates},
            {r: dict(zip(other[r]["data"], other[r][base], strict=True)) for r in rates},
            {r: dict(zip(other[r]["data"], other[r][cand], strict=True)) for r in rates},
        )
        emit(f"\n### {heading.format(cand=cand)}\n")
        emit(tm.md(table))
        emit(f"\nVerdict: {'passes' if ok else 'fails'} ({cand}).")


def setup(argv, name: str, description: str):
    """The shared start of the step-veto studies (this script and ``veto_swing``): their options, the tyrex recordings
    at 50 and 20 Hz, and the shipped and fold models' predictions (``still_rate``'s cache). Returns ``(args, items,
    items20, shipped_model, ship, held)``."""
    from experiments.scripts import tyrex_modes as tm
    from experiments.scripts.still_rate import _train_and_predict

    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--model", default="models/demo", help="the shipped model scored in-sample")
    ap.add_argument("--cache", type=Path, default=Path(tempfile.gettempdir()) / "gaitml-still-steps")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    a.cache.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    items = tm.load_tyrex_labelled(a.data, 50.0)
    items20 = tm.at_rate(items, 20.0)
    print(f"[{name}] {len(items)} tyrex recordings read ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    shipped_model, ship, held = _train_and_predict(a, items, items20)
    return a, items, items20, shipped_model, ship, held


def main(argv=None) -> int:
    from experiments.scripts import tyrex_modes as tm
    from experiments.scripts.still_gate import _standing_stats, equal_standing_threshold, gated_table, per_person
    from experiments.scripts.still_rate import add_statistics
    from gaitml.models._predict import STILL_RANGE_MS2, STILL_STD_LP_MS2

    t0 = time.perf_counter()
    a, items, items20, shipped_model, ship, held = setup(argv, "still_steps", __doc__.splitlines()[0])
    f = a.cache / "steps.pkl"
    steps_cache = pickle.loads(f.read_bytes()) if f.exists() else {}
    n_cached = len(steps_cache)
    by_rate = {"50": items, "20": items20}
    for r, its in by_rate.items():
        add_statistics(shipped_model, its, ship[r])
        add_steps(shipped_model, its, ship[r], steps_cache, f"tyrex-{r}")
    h_items = {r: [] for r in by_rate}
    h_preds = {r: [] for r in by_rate}
    for person in PEOPLE:
        model, d = held[person]
        for r, its in by_rate.items():
            sel = [its[i] for i in d["idx"]]
            add_statistics(model, sel, d[r])
            allp = {i: p for i, p in zip(d["idx"], d[r], strict=True)}
            # the steps are the model-free detector's on the recording at the model's rate: the same for every fold
            peaks = steps_cache[f"tyrex-{r}"]
            for i in d["idx"]:
                c = step_counts(peaks[i], allp[i], model.sampling_rate_hz)
                allp[i]["n_in"], allp[i]["n_near"] = c["in"], c["near"]
            h_items[r] += sel
            h_preds[r] += d[r]
    others = {r: other_data_steps(a.data, float(r), steps_cache) for r in by_rate}
    if len(steps_cache) != n_cached:
        f.write_bytes(pickle.dumps(steps_cache))
    print(f"[still_steps] statistics and steps ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    text: list[str] = []

    def emit(s=""):
        print(s)
        text.append(s)

    # ---- the fold thresholds of the gate without the veto (still_rate's), and of the vetoed gate
    chosen, chosen_v = {}, {}
    emit("### The std_lp threshold chosen on the two training people of each fold (native rate): without and with the veto\n")
    emit(
        "| left out | training standing windows | read still: range < 2 | threshold, no veto | threshold, veto (>= 2 steps inside) | standing vetoed | read still: vetoed gate |"
    )
    emit("|---|---|---|---|---|---|---|")

    def standing(sel):
        sd = np.concatenate(
            [p.loc[(p["label"].astype(str) == "still") & (p["label_fraction"] >= 0.5), "stat_std_lp"].to_numpy() for _, p in sel]
        )
        ve = np.concatenate(
            [
                vetoed({"in": p["n_in"].to_numpy(), "near": p["n_near"].to_numpy()}, CANDIDATE)[
                    ((p["label"].astype(str) == "still") & (p["label_fraction"] >= 0.5)).to_numpy()
                ]
                for _, p in sel
            ]
        )
        _, rg = _standing_stats([x[0] for x in sel], [x[1] for x in sel])
        return sd, ve, rg

    for person in PEOPLE:
        tr = [(it, p) for it, p in zip(h_items["50"], h_preds["50"], strict=True) if it["subject"] != person]
        sd, ve, rg = standing(tr)
        chosen[person] = equal_standing_threshold(sd, rg, STILL_RANGE_MS2)
        chosen_v[person] = vetoed_standing_threshold(sd, rg, ve, STILL_RANGE_MS2)
        emit(
            f"| {person} | {len(sd)} | {np.mean(rg < STILL_RANGE_MS2):.2f} | {chosen[person]:.2f} | {chosen_v[person]:.2f} | {np.mean(ve):.3f} | "
            f"{np.mean((sd < chosen_v[person]) & ~ve):.2f} |"
        )
    sd, ve, rg = standing(list(zip(h_items["50"], h_preds["50"], strict=True)))
    all_v = vetoed_standing_threshold(sd, rg, ve, STILL_RANGE_MS2)
    emit(
        f"\nAll three people: no veto {equal_standing_threshold(sd, rg, STILL_RANGE_MS2):.2f} m/s^2 (gaitml's STILL_STD_LP_MS2 = "
        f"{STILL_STD_LP_MS2:g}); with the veto {all_v:.2f} m/s^2."
    )
    # ---- step 1: measure (no fitting)
    for r in by_rate:
        emit(
            f"\n### Step 1 (measured, nothing fitted): windows with detected steps, held out, recorded at {r} Hz (gate: std_lp < the fold's threshold)\n"
        )
        emit(tm.md(step_share_table(h_items[r], h_preds[r], chosen)))
    for r in by_rate:
        emit(
            f"\n### Step 1, model-free: windows read still (std_lp < {STILL_STD_LP_MS2:g}) and the share of them with steps, recorded at {r} Hz\n"
        )
        emit(tm.md(other_share_table(others[r], float(r), STILL_STD_LP_MS2)))
    # ---- step 2: the candidates, held out and in-sample
    gates = {"no veto": (None, chosen), "veto": (CANDIDATE, chosen), "veto+T": (CANDIDATE, chosen_v)}
    for name, (var, _thr) in gates.items():
        with_gate(h_preds["50"] + h_preds["20"] + ship["50"] + ship["20"], name.replace(" ", "_").replace("+", "_"), var)
    held_tabs: dict = {}
    for r in by_rate:
        for name, (_var, thr) in gates.items():
            t = gated_table(h_items[r], h_preds[r], name.replace(" ", "_").replace("+", "_"), thr)
            s = tm.summarise(t, by="left_out")
            held_tabs[(r, name)] = (s.set_index("motion"), t)
            emit(f"\n### Held out, recorded at {r} Hz, {name} (thresholds {', '.join(f'{p} {thr[p]:.2f}' for p in PEOPLE)})\n")
            emit(tm.md(s))
            emit("\nPer left-out person: right / flagged / silently wrong over the moving windows; standing windows read as a mode\n")
            emit(tm.md(per_person(t)))
    in_gates = {"no veto": (None, STILL_STD_LP_MS2), "veto": (CANDIDATE, STILL_STD_LP_MS2), "veto+T": (CANDIDATE, all_v)}
    for r in by_rate:
        for name, (_var, thr) in in_gates.items():
            t = gated_table(by_rate[r], ship[r], name.replace(" ", "_").replace("+", "_"), thr)
            emit(f"\n### In-sample: {a.model} (trained on all three people), recorded at {r} Hz, {name} (threshold {thr:.2f})\n")
            emit(tm.md(tm.summarise(t)))
    # ---- the other step-count variants (measured, not candidates)
    emit("\n### Held out, the other step-count variants at each fold's threshold (measured beside; not candidates)\n")
    rows = []
    for r in by_rate:
        for var in VARIANTS:
            key = "v_" + var.replace(">=", "ge").replace(" ", "_").replace("+-", "pm").replace(".", "")
            with_gate(h_preds[r], key, var)
            s = tm.summarise(gated_table(h_items[r], h_preds[r], key, chosen), by="left_out").set_index("motion")
            rows.append(
                {
                    "rate": f"{r} Hz",
                    "veto": var,
                    **{f"wrong {m}": s.loc[m, "silently wrong"] for m in ("Texting", "AR", "Phoning", "all")},
                    "right Phoning per left-out": s.loc["Phoning", "right per left-out"],
                    "standing read as a mode": s.loc["all", "standing read as a mode"],
                }
            )
    emit(tm.md(pd.DataFrame(rows)))
    # ---- model-free still shares under each gate
    emit("\n### Model-free: the share of 1.5 s windows read still under each gate\n")
    og = {"no veto": (STILL_STD_LP_MS2, None), "veto": (STILL_STD_LP_MS2, CANDIDATE), "veto+T": (all_v, CANDIDATE)}
    ot = {r: other_still_table(others[r], float(r), og) for r in by_rate}
    emit(tm.md(pd.concat(list(ot.values()), ignore_index=True)))
    # ---- the adoption rule, per candidate
    emit_verdicts(
        emit,
        held_tabs,
        ot,
        by_rate,
        "no veto",
        ("veto", "veto+T"),
        "The adoption rule (fixed before the candidates were scored): {cand} against no veto, held out",
    )
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    print(f"[still_steps] done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
