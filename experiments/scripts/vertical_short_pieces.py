"""Re-choose the gait check's vertical-symmetry rule with short real walks in the selection.

The vertical test (``gaitml.steps._gait_evidence``, ``max_stride_vertical_fraction``) was chosen on whole tyrex
recordings, where a swinging hand's bouts are >= 30 steps and exempt; short pieces of the same walks lose steps to
it. This study cuts every tyrex recording (all motions, AR included) into pieces of 8, 12 and 15 s (from 5 s in,
back to back, up to 5 s before the end), runs ``adaptive`` with the gait check off on each piece and on the
simulated non-gait recordings (``gaitml.simulate.nongait``: gestures and desk, 120 s, selection seeds 0-39 and
held-out seeds 100-119), and keeps one row per bout (:func:`gaitml.steps._gait_evidence.gait_evidence` with the
acceleration: rotation at the step and stride frequency, vertical share at the stride frequency, the rotation
test's verdict). The rules are bout filters after detection, so the choice runs on the cached bouts.

Candidates (a short bout, < ``LONG_BOUT_STEPS`` steps, that the rotation test passes is left out when):

- ``thr``: its vertical share exceeds F (F in 0.4 ... 0.95; inf = off, the default);
- ``swing``: its vertical share exceeds F and its rotation at the stride frequency is below R rad/s (a swinging
  arm turns the phone strongly once per stride: above R the vertical test is skipped);
- ``ratio``: its vertical share exceeds F and its stride rotation is below K times its step rotation (a
  swinging arm's rotation is a clean once-per-stride pendulum: a stride-over-step ratio of K or more skips it).

Choice, leave-one-person-out: a candidate is admissible when each of the two training people loses at most 1 %
of their short-piece steps (pooled over the three piece lengths; steps the rotation test keeps and the candidate
removes, over the steps ``adaptive`` finds with the check off) in every motion; among those, the one leaving the
fewest steps per minute on the simulated gestures + desk selection seeds 0-39 (ties: the least loss on the two
people). Then, once, the chosen rule is scored on the held-out seeds 100-119 and on the left-out person's pieces.

    python -m experiments.scripts.vertical_short_pieces --data ../shared/data --cache /tmp/vertical   # ~3 min
    python -m experiments.scripts.vertical_short_pieces --cache /tmp/vertical --select             # choices only
    python -m experiments.scripts.vertical_short_pieces --cache /tmp/vertical --select --heldout   # scored once
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.steps import get_detector
from gaitml.steps._gait_evidence import LONG_BOUT_STEPS, gait_evidence

PIECES_S = (8.0, 12.0, 15.0)
EDGE_S = 5.0
PEOPLE = ("Guillaume", "Jakob", "Thibaud")
SELECTION_SEEDS = range(40)
HELDOUT_SEEDS = range(100, 120)
KINDS = ("gestures", "desk")
SIM_S = 120.0
MAX_LOSS = 0.01

FRACTIONS = (0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, np.inf)
SWING_R = (0.5, 0.75, 1.0, 1.25, 1.5, 2.0)
RATIO_K = (1.5, 2.0, 3.0, 4.0, 6.0)


def _bouts(rec) -> pd.DataFrame:
    """``adaptive``'s steps (check off) on ``rec``, one row per bout with its gait evidence (vertical share measured)."""
    st = get_detector("adaptive", gait_check=False).detect(rec).steps_
    ev = gait_evidence(rec.gyr, rec.sampling_rate_hz, st, acc=rec.acc)
    return ev[["n_steps", "rotation_step_rad_s", "rotation_stride_rad_s", "stride_vertical_fraction", "reason"]]


def _motion(name: str) -> str:
    m = name.split("_")[-1]
    return "BackPocket" if m.lower() == "backpocket" else m


def collect_tyrex(data: Path, cache: Path) -> pd.DataFrame:
    """Bouts of every tyrex recording's 8 / 12 / 15 s pieces (cached per recording)."""
    from gaitml.io import list_tyrex_folders, read_tyrex

    out = []
    folders = [f for f in list_tyrex_folders(data / "tyrex-attitude") if not f.name.endswith("_old")]
    for i, f in enumerate(folders):
        path = cache / "tyrex" / f"{f.name}.pkl"
        if path.exists():
            out.append(pd.read_pickle(path))
            continue
        try:
            recs = [read_tyrex(f)]
        except Exception:  # a recording with gaps: its segments
            recs = read_tyrex(f, segments=True)
            recs = recs if isinstance(recs, list) else [recs]
        rows = []
        for rec in recs:
            fs = rec.sampling_rate_hz
            for piece in PIECES_S:
                n = int(piece * fs)
                for k, s in enumerate(range(int(EDGE_S * fs), rec.n_samples - n - int(EDGE_S * fs), n)):
                    try:
                        b = _bouts(rec.slice(s, s + n))
                    except Exception as exc:  # too short for adaptive: no steps
                        print(f"  {f.name} piece {piece} {k}: {exc}", file=sys.stderr)
                        continue
                    b = b.assign(piece_s=piece, piece=k)
                    rows.append(b)
        df = pd.concat(rows, ignore_index=True) if rows else pd.DataFrame()
        df = df.assign(person=f.name.split("_")[0], motion=_motion(f.name), recording=f.name)
        path.parent.mkdir(parents=True, exist_ok=True)
        df.to_pickle(path)
        out.append(df)
        print(f"[{i + 1}/{len(folders)}] {f.name}: {int(df['n_steps'].sum()) if len(df) else 0} steps", file=sys.stderr)
    return pd.concat(out, ignore_index=True)


def collect_sim(cache: Path) -> pd.DataFrame:
    """Bouts of the simulated non-gait recordings, selection and held-out seeds (cached per recording)."""
    from gaitml.simulate.nongait import simulate_nongait

    out = []
    for kind in KINDS:
        for seed in [*SELECTION_SEEDS, *HELDOUT_SEEDS]:
            path = cache / "sim" / f"{kind}_{seed}.pkl"
            if path.exists():
                out.append(pd.read_pickle(path))
                continue
            b = _bouts(simulate_nongait(kind, duration_s=SIM_S, seed=seed)).assign(kind=kind, seed=seed)
            path.parent.mkdir(parents=True, exist_ok=True)
            b.to_pickle(path)
            out.append(b)
        print(f"sim {kind} done", file=sys.stderr)
    return pd.concat(out, ignore_index=True)


def candidates() -> list[tuple[str, float, float]]:
    """(family, F, R or K): ``thr`` (F), ``swing`` (F, R), ``ratio`` (F, K)."""
    c = [("thr", f, np.nan) for f in FRACTIONS]
    c += [("swing", f, r) for f in FRACTIONS[:-1] for r in SWING_R]
    c += [("ratio", f, k) for f in FRACTIONS[:-1] for k in RATIO_K]
    return c


def removed(b: pd.DataFrame, cand: tuple[str, float, float]) -> np.ndarray:
    """Bouts the candidate removes beyond the rotation test (short bouts the rotation test passes)."""
    fam, f, p = cand
    vf = b["stride_vertical_fraction"].to_numpy(dtype=float)
    short = b["n_steps"].to_numpy() < LONG_BOUT_STEPS
    passes = (b["reason"] == "").to_numpy()
    hit = np.isfinite(vf) & (vf > f) & short & passes
    rr = b["rotation_stride_rad_s"].to_numpy(dtype=float)
    rs = b["rotation_step_rad_s"].to_numpy(dtype=float)
    if fam == "swing":
        hit &= ~(rr >= p)
    elif fam == "ratio":
        hit &= ~(rr >= p * rs)
    return hit


def kept_rate(sim: pd.DataFrame, seeds, cand, kind: str | None = None) -> float:
    """Mean steps per minute left on the simulated recordings of ``seeds`` (both kinds, or ``kind``)."""
    s = sim[sim["seed"].isin(list(seeds)) & ((sim["kind"] == kind) if kind else True)]
    keep = (s["reason"] == "").to_numpy() & ~removed(s, cand)
    n_rec = len(list(seeds)) * (1 if kind else len(KINDS))
    return float((s["n_steps"].to_numpy() * keep).sum() / n_rec / (SIM_S / 60.0))


def losses(ty: pd.DataFrame, cand, people) -> pd.DataFrame:
    """Per person and motion: steps found (check off), lost to the rotation test, lost to the candidate, its share."""
    t = ty[ty["person"].isin(people)].copy()
    t["lost"] = t["n_steps"] * removed(t, cand)
    t["rot"] = t["n_steps"] * (t["reason"] == "rotation")
    g = t.groupby(["person", "motion"]).agg(steps=("n_steps", "sum"), rot=("rot", "sum"), lost=("lost", "sum"))
    g["share"] = g["lost"] / g["steps"].clip(lower=1)
    return g


def _name(c) -> str:
    fam, f, p = c
    if fam == "thr":
        return "off" if not np.isfinite(f) else f"F>{f:g}"
    return f"F>{f:g}, stride rot < {p:g} rad/s" if fam == "swing" else f"F>{f:g}, stride rot < {p:g} x step rot"


def select(ty: pd.DataFrame, sim: pd.DataFrame, heldout: bool = False) -> None:
    """Print the LOPO choices; with ``heldout`` also their scores on held-out seeds and the left-out people."""
    cands = candidates()
    off = ("thr", np.inf, np.nan)
    shipped = ("thr", 0.4, np.nan)
    print("## in-sample reference (all people, selection seeds 0-39)\n")
    print("| rule | gestures sel | desk sel | worst person x motion loss (all 3 people) |")
    print("|---|---|---|---|")
    for c in (off, shipped):
        lo = losses(ty, c, PEOPLE)
        w = lo["share"].idxmax()
        print(
            f"| {_name(c)} | {kept_rate(sim, SELECTION_SEEDS, c, 'gestures'):.3f} | {kept_rate(sim, SELECTION_SEEDS, c, 'desk'):.3f} "
            f"| {lo['share'].max():.3f} ({w[0]} {w[1]}) |"
        )
    choices = {}
    print("\n## leave-one-person-out\n")
    for left in PEOPLE:
        train = [p for p in PEOPLE if p != left]
        best = None
        n_adm = 0
        for c in cands:
            lo = losses(ty, c, train)
            if lo["share"].max() > MAX_LOSS:
                continue
            n_adm += 1
            key = (kept_rate(sim, SELECTION_SEEDS, c), float(lo["lost"].sum()))
            if best is None or key < best[0]:
                best = (key, c)
        c = best[1]
        choices[left] = c
        lo_in = losses(ty, c, train)
        lo_out = losses(ty, c, [left])
        print(f"### {left} left out: chosen `{_name(c)}` ({n_adm} of {len(cands)} candidates admissible)\n")
        print(
            f"- selection seeds 0-39 (in sample): gestures {kept_rate(sim, SELECTION_SEEDS, c, 'gestures'):.3f}, "
            f"desk {kept_rate(sim, SELECTION_SEEDS, c, 'desk'):.3f} steps/min (off: "
            f"{kept_rate(sim, SELECTION_SEEDS, off, 'gestures'):.3f} / {kept_rate(sim, SELECTION_SEEDS, off, 'desk'):.3f})"
        )
        print(f"- training people, worst motion loss (in sample): {lo_in['share'].max():.4f}")
        if not heldout:
            print()
            continue
        print(
            f"- held-out seeds 100-119: gestures {kept_rate(sim, HELDOUT_SEEDS, c, 'gestures'):.3f}, "
            f"desk {kept_rate(sim, HELDOUT_SEEDS, c, 'desk'):.3f} steps/min (off: "
            f"{kept_rate(sim, HELDOUT_SEEDS, off, 'gestures'):.3f} / {kept_rate(sim, HELDOUT_SEEDS, off, 'desk'):.3f})"
        )
        print(f"- left-out {left}, short-piece steps lost per motion (held out):\n")
        print("| motion | steps (check off) | lost to rotation test | lost to the rule | share |")
        print("|---|---|---|---|---|")
        for (_, m), r in lo_out.iterrows():
            print(f"| {m} | {int(r.steps)} | {int(r.rot)} | {int(r.lost)} | {r.share:.4f} |")
        print()
    if not heldout:
        return
    print("## per piece length, each fold's choice on its left-out person\n")
    print("| left out | piece s | steps | lost to the rule | worst motion share |")
    print("|---|---|---|---|---|")
    for left, c in choices.items():
        for piece in PIECES_S:
            lo = losses(ty[ty["piece_s"] == piece], c, [left])
            print(f"| {left} | {piece:g} | {int(lo['steps'].sum())} | {int(lo['lost'].sum())} | {lo['share'].max():.4f} |")
    # the rule chosen on all three people (what would ship)
    best = None
    for c in cands:
        lo = losses(ty, c, PEOPLE)
        if lo["share"].max() > MAX_LOSS:
            continue
        key = (kept_rate(sim, SELECTION_SEEDS, c), float(lo["lost"].sum()))
        if best is None or key < best[0]:
            best = (key, c)
    c = best[1]
    print(f"\n## chosen on all three people: `{_name(c)}`")
    print(
        f"selection gestures {kept_rate(sim, SELECTION_SEEDS, c, 'gestures'):.3f} desk {kept_rate(sim, SELECTION_SEEDS, c, 'desk'):.3f}; "
        f"held-out gestures {kept_rate(sim, HELDOUT_SEEDS, c, 'gestures'):.3f} desk {kept_rate(sim, HELDOUT_SEEDS, c, 'desk'):.3f} "
        f"(off: {kept_rate(sim, HELDOUT_SEEDS, off, 'gestures'):.3f} / {kept_rate(sim, HELDOUT_SEEDS, off, 'desk'):.3f}; "
        f"F>0.4: {kept_rate(sim, HELDOUT_SEEDS, shipped, 'gestures'):.3f} / {kept_rate(sim, HELDOUT_SEEDS, shipped, 'desk'):.3f})"
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--cache", type=Path, required=True)
    ap.add_argument("--select", action="store_true", help="choose on the cached bouts (collect first)")
    ap.add_argument("--heldout", action="store_true", help="with --select: score the choices on held-out data (once)")
    ap.add_argument("--only", choices=("tyrex", "sim"), default=None, help="collect one set only")
    a = ap.parse_args(argv)
    if a.select:
        ty = pd.concat([pd.read_pickle(p) for p in sorted((a.cache / "tyrex").glob("*.pkl"))], ignore_index=True)
        sim = pd.concat([pd.read_pickle(p) for p in sorted((a.cache / "sim").glob("*.pkl"))], ignore_index=True)
        select(ty, sim, heldout=a.heldout)
        return 0
    if a.only in (None, "sim"):
        collect_sim(a.cache)
    if a.only in (None, "tyrex"):
        collect_tyrex(a.data, a.cache)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
