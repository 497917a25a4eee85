"""More step evidence for the still gate's veto in calm phone-at-ear walking: the swing stage's steps, the gyroscope's stride rhythm.

``python -m experiments.scripts.veto_swing [--data ../shared/data] [--config experiments/demo.toml] [--cache DIR] [--out FILE]``
from the repository root.

The still gate's step veto (:data:`gaitml.models._predict.STILL_STEP_VETO_MIN_STEPS`) keeps a window's mode when the
default ``adaptive`` detector finds >= 2 steps with their peak inside it. It misses the calm phone-at-ear walker whose
steps ``adaptive`` misses (experiments/reports/still-gate.md, "The step veto"). This study scores, against that veto
(the current default) and by the adoption rule committed before they were scored (same report, top section):

- ``swing``: the veto with its steps from ``adaptive`` with the opt-in swing stage 2c on
  (``gyro_swing_min_periodicity=0.3``, :data:`SWING_PERIODICITY`), run once per recording at the model's rate;
- ``rhythm``: the veto, or the gyroscope's stride rhythm in the 5 s centred on the window (:func:`stride_rhythm`);
- ``swing|rhythm``: either of the two.

The fold models, the gate-off predictions and the default detector's steps are :mod:`experiments.scripts.still_steps`'
(its cache layout; ``--cache`` may be a copy of its cache). Held out: each tyrex person left out, at the native rate
and as a 20 Hz phone records it, with each fold's own ``std_lp`` threshold; in-sample: ``models/demo`` at 0.38; the
model-free sets of :func:`experiments.scripts.still_gate.other_data_sets`.
"""

from __future__ import annotations

import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["CANDIDATES", "SWING_PERIODICITY", "adoption_checks", "candidate_vetoes", "stride_rhythm", "main"]

PEOPLE = ("Guillaume", "Jakob", "Thibaud")
#: the opt-in swing stage's documented value (``adaptive``'s ``gyro_swing_min_periodicity``; tyrex-steps.md, fifth helper)
SWING_PERIODICITY = 0.3
#: the gates scored: the baseline (the current default) and the three candidates fixed before scoring
CANDIDATES = ("veto", "swing", "rhythm", "swing|rhythm")
#: the model-free sets the rule's R4 reads (name prefixes of :func:`experiments.scripts.still_gate.other_data_sets`)
R4_SETS = ("phone lying", "simulate_nongait desk", "simulate_nongait gestures")


def stride_rhythm(rec, windows: pd.DataFrame) -> np.ndarray:
    """Per window (``start``, ``end`` samples of ``rec``): does the phone turn with a stride rhythm around it?

    The body that carries the phone (trunk, head, the arm that holds it) rotates once per stride and reverses between
    the left and the right step (Perry & Burnfield, Gait Analysis, 2nd ed. 2010, ch. 10; the physics of ``adaptive``'s
    stages 2b and 2c); a standing body's sway has no stride period. Over the ``adaptive.WINDOW_S`` (5 s) centred on
    the window (moved inside the recording at its ends), the angular rate band-passed to ``adaptive.GYRO_BAND_HZ``
    (at the rate ``adaptive`` decimates to) and projected on its principal axis must have an RMS of at least
    ``GYRO_MIN_RMS_RADS``, a stride period P (:func:`gaitml.steps.adaptive.swing_stride`) whose autocorrelation
    reaches ``MIN_PERIODICITY``, at which P / 2 is a step of the human range, and anti-phase at P / 2 (at most
    ``-GYRO_SWING_HALF_CORRELATION``). All False without a gyroscope or when the recording is shorter than 5 s.
    """
    from gaitml.signal import bandpass
    from gaitml.steps import adaptive as ad

    n = len(windows)
    out = np.zeros(n, dtype=bool)
    if rec.gyr is None or n == 0:
        return out
    fs = float(rec.sampling_rate_hz)
    q = ad.cadence_decimation(fs)
    g = np.asarray(rec.gyr, dtype=float)
    g = bandpass(g - g.mean(axis=0), ad.GYRO_BAND_HZ[0], min(ad.GYRO_BAND_HZ[1], 0.45 * fs), fs, order=2)[::q]
    L = int(round(ad.WINDOW_S * fs / q))
    if len(g) < L:
        return out
    centre = (windows["start"].to_numpy(float) + windows["end"].to_numpy(float)) / 2.0 / q
    s0 = np.clip(np.round(centre - L / 2.0).astype(np.int64), 0, len(g) - L)
    seg = g[s0[:, None] + np.arange(L)[None, :]]  # (n, L, 3)
    seg = seg - seg.mean(axis=1, keepdims=True)
    cov = np.einsum("nlc,nld->ncd", seg, seg)
    axis = np.linalg.eigh(cov)[1][:, :, -1]
    proj = np.einsum("nlc,nc->nl", seg, axis)
    rms = np.sqrt(np.mean(proj**2, axis=1))
    P, corr, half = ad.swing_stride(proj, fs / q)
    ok = (rms >= ad.GYRO_MIN_RMS_RADS) & np.isfinite(P)
    ok &= np.nan_to_num(corr, nan=-1.0) >= ad.MIN_PERIODICITY
    ok &= np.nan_to_num(half, nan=1.0) <= -ad.GYRO_SWING_HALF_CORRELATION
    step = P / 2.0
    with np.errstate(invalid="ignore"):
        ok &= (step >= (fs / q) / ad.MAX_STEP_HZ) & (step <= (fs / q) / ad.MIN_STEP_HZ)
    return ok


def swing_peaks(rec) -> np.ndarray:
    """``adaptive``'s step peaks on ``rec`` with the swing stage on (:data:`SWING_PERIODICITY`), gait check on."""
    from gaitml.errors import InputError
    from gaitml.steps import get_detector

    kw = {"gyro_swing_min_periodicity": SWING_PERIODICITY} if rec.has_gyr else {}  # without a gyroscope the stage cannot run
    try:
        return get_detector("adaptive", **kw).detect(rec).steps_["peak"].to_numpy(np.int64)
    except InputError:  # shorter than the detector's cadence window
        return np.zeros(0, dtype=np.int64)


def _count_in(peaks, windows) -> np.ndarray:
    p = np.sort(np.asarray(peaks, dtype=np.int64))
    return np.searchsorted(p, windows["end"].to_numpy(np.int64), side="left") - np.searchsorted(
        p, windows["start"].to_numpy(np.int64), side="left"
    )


def candidate_vetoes(n_default, n_swing, rhythm, min_steps: int = 2) -> dict[str, np.ndarray]:
    """Which windows each gate of :data:`CANDIDATES` vetoes, from the default detector's and the swing stage's step
    counts inside each window and :func:`stride_rhythm`."""
    d = np.asarray(n_default) >= min_steps
    s = np.asarray(n_swing) >= min_steps
    r = np.asarray(rhythm, dtype=bool)
    return {"veto": d, "swing": s, "rhythm": d | r, "swing|rhythm": s | r}


def evidence(rec, windows) -> dict[str, np.ndarray]:
    """``n_swing`` (steps of :func:`swing_peaks` inside each window) and ``rhythm`` (:func:`stride_rhythm`)."""
    return {"n_swing": _count_in(swing_peaks(rec), windows), "rhythm": stride_rhythm(rec, windows)}


def _key(name: str) -> str:
    return "g_" + name.replace("|", "_or_")


def with_gates(preds) -> None:
    """Add ``stat_<gate>`` per candidate: ``stat_std_lp``, +inf where the candidate vetoes."""
    for p in preds:
        v = candidate_vetoes(p["n_in"].to_numpy(), p["n_swing"].to_numpy(), p["rhythm"].to_numpy())
        for name, m in v.items():
            s = p["stat_std_lp"].to_numpy(float).copy()
            s[m] = np.inf
            p[f"stat_{_key(name)}"] = s


def other_sets(data: Path, rate: float, steps_cache: dict, cache: dict) -> list[tuple[str, pd.DataFrame]]:
    """Per model-free set made at ``rate`` and read at 50 Hz: its windows with ``stat_std_lp``, ``n_in`` (from
    :func:`experiments.scripts.still_steps.other_data_steps`), ``n_swing`` and ``rhythm``."""
    from experiments.scripts.still_gate import other_data_sets
    from experiments.scripts.still_steps import other_data_steps
    from gaitml.models import resample_recording

    base = other_data_steps(data, rate, steps_cache)
    key = f"other-{rate:g}"
    if key not in cache:
        ev = []
        for (name, recs), (name2, tabs) in zip(other_data_sets(data), base, strict=True):
            assert name == name2
            per = []
            at50s = [resample_recording(resample_recording(r, rate), 50.0) for r in recs]
            at50s = [r for r in at50s if r.n_samples >= 75]
            for r, w in zip(at50s, tabs, strict=True):
                per.append(evidence(r, w))
            ev.append(per)
        cache[key] = ev
    out = []
    for (name, tabs), per in zip(base, cache[key], strict=True):
        parts = []
        for w, e in zip(tabs, per, strict=True):
            w = w.copy()
            w["n_swing"], w["rhythm"] = e["n_swing"], e["rhythm"]
            parts.append(w)
        out.append((name, pd.concat(parts, ignore_index=True)))
    return out


def other_still(sets, rate: float, thr: float) -> pd.DataFrame:
    """Model-free: per set, the share of windows read still under each gate (``std_lp`` < ``thr`` and not vetoed)."""
    rows = []
    for name, d in sets:
        v = candidate_vetoes(d["n_in"].to_numpy(), d["n_swing"].to_numpy(), d["rhythm"].to_numpy())
        low = d["stat_std_lp"].to_numpy() < thr
        row = {"data": name, "recorded at": f"{rate:g} Hz", "windows": len(d), "std_lp alone": float(np.mean(low))}
        for g in CANDIDATES:
            row[g] = float(np.mean(low & ~v[g]))
        row["rhythm alone, of std_lp-still"] = float(np.mean(d["rhythm"].to_numpy()[low])) if low.any() else 0.0
        rows.append(row)
    return pd.DataFrame(rows)


def adoption_checks(before: dict, after: dict, other_before: dict, other_after: dict) -> tuple[bool, pd.DataFrame]:
    """The rule fixed before scoring: :func:`experiments.scripts.still_steps.adoption_checks` (R1-R3, R4 on the table
    and the desk) against the current veto, and R4 also on the simulated gestures (each rate: fall <= 0.02)."""
    from experiments.scripts.still_steps import adoption_checks as base_checks

    ok, rows = base_checks(before, after, other_before, other_after)
    extra = []
    for r in before:
        for name, share in other_before[r].items():
            if not name.startswith("simulate_nongait gestures"):
                continue
            passed = other_after[r][name] >= share - 0.02 - 1e-9
            extra.append(
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
    return bool(ok), pd.concat([rows, pd.DataFrame(extra)], ignore_index=True)


def _phoning_reach(items, preds, thr) -> pd.DataFrame:
    """Of Phoning's moving windows the gate (``std_lp`` < the fold's threshold) reads still: the share each evidence holds."""
    rows = []
    for motion in ("Phoning", "Texting", "AR"):
        parts = []
        for it, p in zip(items, preds, strict=True):
            if it["motion"] != motion:
                continue
            t = thr[it["subject"]] if isinstance(thr, dict) else thr
            sel = ((p["label"].astype(str) == it["mode"]) & (p["label_fraction"] >= 0.5)).to_numpy() & (p["stat_std_lp"].to_numpy() < t)
            parts.append(
                pd.DataFrame(
                    {
                        "who": it["subject"],
                        "n_in": p["n_in"].to_numpy()[sel],
                        "n_swing": p["n_swing"].to_numpy()[sel],
                        "rhythm": p["rhythm"].to_numpy()[sel],
                    }
                )
            )
        d = pd.concat(parts, ignore_index=True)
        for who in [*PEOPLE, "all"]:
            g = d if who == "all" else d[d["who"] == who]
            if g.empty:
                continue
            rows.append(
                {
                    "motion": motion,
                    "person": who,
                    "moving windows read still": len(g),
                    ">= 2 default steps": float(np.mean(g["n_in"] >= 2)),
                    ">= 2 swing-stage steps": float(np.mean(g["n_swing"] >= 2)),
                    "stride rhythm": float(np.mean(g["rhythm"])),
                    "any": float(np.mean((g["n_in"] >= 2) | (g["n_swing"] >= 2) | g["rhythm"])),
                }
            )
    return pd.DataFrame(rows)


def main(argv=None) -> int:
    from experiments.scripts import tyrex_modes as tm
    from experiments.scripts.still_gate import _standing_stats, equal_standing_threshold, gated_table, per_person
    from experiments.scripts.still_rate import add_statistics
    from experiments.scripts.still_steps import add_steps, emit_verdicts, setup, step_counts
    from gaitml.models import resample_recording
    from gaitml.models._predict import STILL_RANGE_MS2, STILL_STD_LP_MS2

    t0 = time.perf_counter()
    a, items, items20, shipped_model, ship, held = setup(argv, "veto_swing", __doc__.splitlines()[0])
    fs = shipped_model.sampling_rate_hz
    f_steps, f_ev = a.cache / "steps.pkl", a.cache / "veto-swing.pkl"
    steps_cache = pickle.loads(f_steps.read_bytes()) if f_steps.exists() else {}
    ev_cache = pickle.loads(f_ev.read_bytes()) if f_ev.exists() else {}
    n_steps, n_ev = len(steps_cache), len(ev_cache)
    by_rate = {"50": items, "20": items20}
    recs: dict = {}
    for r, its in by_rate.items():
        add_statistics(shipped_model, its, ship[r])
        add_steps(shipped_model, its, ship[r], steps_cache, f"tyrex-{r}")
        recs[r] = [resample_recording(it["recording"], fs) for it in its]
        if f"tyrex-{r}" not in ev_cache:
            ev_cache[f"tyrex-{r}"] = [swing_peaks(rec) for rec in recs[r]]
        for peaks, rec, p in zip(ev_cache[f"tyrex-{r}"], recs[r], ship[r], strict=True):
            p["n_swing"] = _count_in(peaks, p)
            p["rhythm"] = stride_rhythm(rec, p)
    h_items = {r: [] for r in by_rate}
    h_preds = {r: [] for r in by_rate}
    for person in PEOPLE:
        model, d = held[person]
        for r, its in by_rate.items():
            sel = [its[i] for i in d["idx"]]
            add_statistics(model, sel, d[r])
            for i, p in zip(d["idx"], d[r], strict=True):
                c = step_counts(steps_cache[f"tyrex-{r}"][i], p, model.sampling_rate_hz)
                p["n_in"], p["n_near"] = c["in"], c["near"]
                p["n_swing"] = _count_in(ev_cache[f"tyrex-{r}"][i], p)
                p["rhythm"] = stride_rhythm(recs[r][i], p)
            h_items[r] += sel
            h_preds[r] += d[r]
    others = {r: other_sets(a.data, float(r), steps_cache, ev_cache) for r in by_rate}
    if len(steps_cache) != n_steps:
        f_steps.write_bytes(pickle.dumps(steps_cache))
    if len(ev_cache) != n_ev:
        f_ev.write_bytes(pickle.dumps(ev_cache))
    print(f"[veto_swing] statistics, steps and rhythm ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    text: list[str] = []

    def emit(s=""):
        print(s)
        text.append(s)

    # the fold thresholds of the gate without any veto (still_rate's criterion: the baseline's, unchanged)
    chosen = {}
    for person in PEOPLE:
        tr = [(it, p) for it, p in zip(h_items["50"], h_preds["50"], strict=True) if it["subject"] != person]
        sd = np.concatenate(
            [p.loc[(p["label"].astype(str) == "still") & (p["label_fraction"] >= 0.5), "stat_std_lp"].to_numpy() for _, p in tr]
        )
        _, rg = _standing_stats([x[0] for x in tr], [x[1] for x in tr])
        chosen[person] = equal_standing_threshold(sd, rg, STILL_RANGE_MS2)
    emit(
        f"Fold thresholds (std_lp, chosen without the veto on the two training people): {', '.join(f'{p} {chosen[p]:.2f}' for p in PEOPLE)}\n"
    )
    for r in by_rate:
        emit(f"\n### Reach: of the moving windows std_lp reads still, held out, recorded at {r} Hz, the share with each evidence\n")
        emit(tm.md(_phoning_reach(h_items[r], h_preds[r], chosen)))
    with_gates(h_preds["50"] + h_preds["20"] + ship["50"] + ship["20"])
    held_tabs: dict = {}
    summary_rows = []
    for r in by_rate:
        for name in CANDIDATES:
            t = gated_table(h_items[r], h_preds[r], _key(name), chosen)
            s = tm.summarise(t, by="left_out")
            held_tabs[(r, name)] = (s.set_index("motion"), t)
            emit(f"\n### Held out, recorded at {r} Hz, {name}\n")
            emit(tm.md(s))
            emit("\nPer left-out person: right / flagged / silently wrong over the moving windows; standing windows read as a mode\n")
            emit(tm.md(per_person(t)))
            si = s.set_index("motion")
            summary_rows.append(
                {
                    "rate": f"{r} Hz",
                    "gate": name,
                    "Phoning right": si.loc["Phoning", "right"],
                    "Phoning silently wrong": si.loc["Phoning", "silently wrong"],
                    "Phoning right per left-out": si.loc["Phoning", "right per left-out"],
                    "Phoning wrong per left-out": si.loc["Phoning", "wrong per left-out"],
                    "Texting wrong": si.loc["Texting", "silently wrong"],
                    "AR wrong": si.loc["AR", "silently wrong"],
                    "all wrong": si.loc["all", "silently wrong"],
                    "standing read as a mode": si.loc["all", "standing read as a mode"],
                }
            )
    for r in by_rate:
        for name in CANDIDATES:
            t = gated_table(by_rate[r], ship[r], _key(name), STILL_STD_LP_MS2)
            si = tm.summarise(t).set_index("motion")
            summary_rows.append(
                {
                    "rate": f"{r} Hz, in-sample",
                    "gate": name,
                    "Phoning right": si.loc["Phoning", "right"],
                    "Phoning silently wrong": si.loc["Phoning", "silently wrong"],
                    "Phoning right per left-out": "",
                    "Phoning wrong per left-out": "",
                    "Texting wrong": si.loc["Texting", "silently wrong"],
                    "AR wrong": si.loc["AR", "silently wrong"],
                    "all wrong": si.loc["all", "silently wrong"],
                    "standing read as a mode": si.loc["all", "standing read as a mode"],
                }
            )
    emit("\n### Summary: held out (each fold's threshold) and in-sample (models/demo, 0.38)\n")
    emit(tm.md(pd.DataFrame(summary_rows)))
    emit(f"\n### Model-free: the share of 1.5 s windows read still (std_lp < {STILL_STD_LP_MS2:g}) under each gate\n")
    ot = {r: other_still(others[r], float(r), STILL_STD_LP_MS2) for r in by_rate}
    emit(tm.md(pd.concat(list(ot.values()), ignore_index=True)))
    emit_verdicts(
        emit,
        held_tabs,
        ot,
        by_rate,
        "veto",
        CANDIDATES[1:],
        "The adoption rule (fixed before scoring): {cand} against the current veto, held out",
        checks=adoption_checks,
    )
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    print(f"[veto_swing] done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
