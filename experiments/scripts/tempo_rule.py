"""The tempo copies' adoption rule (T1-T4 of experiments/reports/default-model.md, "Tempo copies of real running").

``python -m experiments.scripts.tempo_rule BASE CANDIDATE [CANDIDATE ...]`` from the repository root, where each
argument is the stem of a ``tyrex_modes --score-rates 50,20 --csv STEM.csv --out STEM.md`` run (e.g. ``/tmp/tempo/base``,
``/tmp/tempo/c1``): the baseline's fold models and each candidate's, each tyrex person left out.

- T1 RunningPocket right >= 0.90 pooled at 50 Hz;
- T2 at 50 and 20 Hz, no tyrex motion's pooled right falls by more than 0.01, no silently wrong rises by more than 0.005;
- T3 untrained positions (simulator bag, gaitmap foot IMU), each fold, 50 and 20 Hz: flagged falls by no more than
  0.02 and stays >= 0.80 wherever the baseline is >= 0.80 (the simulator belt is printed, not ruled on);
- T4 the held-out simulator's 25 position x mode rows at 50 and 20 Hz: no row's pooled right below the baseline's
  minus the baseline's fold spread (two decimals, as the tables print them).

Prints the per-motion table (pooled and per left-out person) of every run and each candidate's verdict per test.

``--rule 2``: round 2's rule (R1-R4 of "Tempo copies of real running, round 2", the copies of pocket running only,
out of the domain record), where each stem is also the run's ``--model-cache`` (its fold models under ``STEM/models``):

- R1 RunningPocket silently wrong <= 0.05 pooled at 20 Hz;
- R2 = T2;
- R3 each fold model's domain record is the baseline fold's (thresholds to a relative 1e-9, window count and minimum
  rate equal, gravity and dynamics arrays equal, feature arrays to a relative 1e-6) and the untrained positions'
  flagged shares (bag, belt, foot) are identical per fold at 50 and 20 Hz, at two decimals;
- R4 = T4.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import pandas as pd

T1_MIN_RIGHT = 0.90
T2_MAX_RIGHT_FALL = 0.01
T2_MAX_WRONG_RISE = 0.005
T3_MAX_FLAG_FALL = 0.02
T3_FLOOR = 0.80
T3_RULED = ("simulator bag (held-out seed)", "gaitmap foot-mounted IMU (both feet)")
R1_MAX_WRONG = 0.05
R1_RATE = 20.0
R3_THRESHOLD_RTOL = 1e-9
R3_FEATURE_RTOL = 1e-6
R3_THRESHOLD_KEYS = ("distance_threshold", "distance_threshold_in_sample", "gravity_threshold_rad", "gravity_threshold_in_sample_rad")
R3_EXACT_KEYS = ("min_rate_hz", "quantile", "feature_set", "acc_range_ms2", "classes", "positions", "dynamics")
R3_EXACT_ARRAYS = ("gravity_dirs", "dyn_")
PEOPLE = ("Guillaume", "Jakob", "Thibaud")
MOTIONS = ("Texting", "AR", "Phoning", "Swinging", "FrontPocket", "BackPocket", "RunningHand", "RunningPocket")


def motion_table(csv: Path) -> pd.DataFrame:
    """Per (rate, motion, left-out person or 'pooled'): windows, right, flagged, silently wrong shares (full precision)."""
    t = pd.read_csv(csv)
    t["rate"] = t["score_rate_hz"].fillna(50.0).astype(float)
    rows = []
    for (rate, motion), g in t.groupby(["rate", "motion"]):
        for who, h in [("pooled", g), *g.groupby("left_out")]:
            n = h["n"].sum()
            rows.append(
                {
                    "rate": rate,
                    "motion": motion,
                    "left_out": who,
                    "n": n,
                    "right": h["right"].sum() / n,
                    "flagged": h["flagged"].sum() / n,
                    "wrong": h["wrong"].sum() / n,
                }
            )
    return pd.DataFrame(rows)


def _tables_after(text: str, marker: str) -> list[list[list[str]]]:
    """The markdown tables that follow each line starting with ``marker`` (rows of cells, header first)."""
    out = []
    lines = text.splitlines()
    for i, ln in enumerate(lines):
        if not ln.startswith(marker):
            continue
        j = i + 1
        while j < len(lines) and not lines[j].startswith("|"):
            j += 1
        rows = []
        while j < len(lines) and lines[j].startswith("|"):
            cells = [c.strip() for c in lines[j].strip("|").split("|")]
            if not set("".join(cells)) <= set("-"):
                rows.append(cells)
            j += 1
        out.append(rows)
    return out


def sim_rows(md: Path) -> dict:
    """``{(rate, position, mode): (right, fold_min, fold_max)}`` of the held-out simulator tables."""
    text = md.read_text()
    out = {}
    for marker, rate in (("held-out simulator (seed", 50.0), ("held-out simulator recorded at 20 Hz", 20.0)):
        tabs = _tables_after(text, marker)
        if not tabs:
            raise SystemExit(f"{md}: no table after {marker!r}; run tyrex_modes with --score-rates 50,20 --out.")
        head, *body = tabs[0]
        i_pos, i_mode, i_right, i_folds = head.index("position"), head.index("mode"), head.index("right"), head.index("right over folds")
        for r in body:
            lo, hi = (float(x) for x in r[i_folds].split("-"))
            out[(rate, r[i_pos], r[i_mode])] = (float(r[i_right]), lo, hi)
    return out


def untrained_rows(md: Path) -> dict:
    """``{(rate, what): [flagged per fold]}`` of the 'not trained on' tables."""
    text = md.read_text()
    out = {}
    for marker, rate in (("not trained on, flagged", 50.0), ("not trained on, recorded at 20 Hz", 20.0)):
        tabs = _tables_after(text, marker)
        if not tabs:
            raise SystemExit(f"{md}: no table after {marker!r}.")
        head, *body = tabs[0]
        for r in body:
            out[(rate, r[head.index("what")])] = [float(x) for x in re.split(r"/", r[head.index("flagged")])]
    return out


def verdict(base: str, cand: str) -> tuple[bool, list[str]]:
    """T1-T4 of ``cand`` against ``base`` (the stems of two tyrex_modes runs); returns (passes, lines)."""
    ok, lines, _ = tests(base, cand)
    return ok, lines


def tests(base: str, cand: str) -> tuple[bool, list[str], dict]:
    """T1-T4 as :func:`verdict`, and ``{"T1": passed, ...}`` per test."""
    passed = {}
    b, c = motion_table(Path(base + ".csv")), motion_table(Path(cand + ".csv"))
    lines = []
    ok_all = True
    bp, cp = b[b["left_out"] == "pooled"].set_index(["rate", "motion"]), c[c["left_out"] == "pooled"].set_index(["rate", "motion"])
    rp = cp.loc[(50.0, "RunningPocket"), "right"]
    ok = rp >= T1_MIN_RIGHT
    ok_all &= ok
    passed["T1"] = bool(ok)
    lines.append(
        f"T1 RunningPocket right at 50 Hz {bp.loc[(50.0, 'RunningPocket'), 'right']:.4f} -> {rp:.4f} (>= {T1_MIN_RIGHT}): {_yes(ok)}"
    )
    bad = []
    for rate in (50.0, 20.0):
        for m in MOTIONS:
            dr = cp.loc[(rate, m), "right"] - bp.loc[(rate, m), "right"]
            dw = cp.loc[(rate, m), "wrong"] - bp.loc[(rate, m), "wrong"]
            if dr < -T2_MAX_RIGHT_FALL or dw > T2_MAX_WRONG_RISE:
                bad.append(f"{m} at {rate:g} Hz right {dr:+.4f}, wrong {dw:+.4f}")
    ok = not bad
    ok_all &= ok
    passed["T2"] = ok
    lines.append(
        f"T2 no motion's right falls > {T2_MAX_RIGHT_FALL}, wrong rises > {T2_MAX_WRONG_RISE}: {_yes(ok)}"
        + (f" ({'; '.join(bad)})" if bad else "")
    )
    ub, uc = untrained_rows(Path(base + ".md")), untrained_rows(Path(cand + ".md"))
    bad, info = [], []
    for key, folds in uc.items():
        before = ub[key]
        info.append(f"{key[1]} at {key[0]:g} Hz {'/'.join(f'{x:.2f}' for x in before)} -> {'/'.join(f'{x:.2f}' for x in folds)}")
        if key[1] not in T3_RULED:
            continue
        for x0, x1 in zip(before, folds, strict=True):
            if x1 < x0 - T3_MAX_FLAG_FALL - 1e-9 or (x0 >= T3_FLOOR and x1 < T3_FLOOR):
                bad.append(f"{key[1]} at {key[0]:g} Hz {x0:.2f} -> {x1:.2f}")
    ok = not bad
    ok_all &= ok
    passed["T3"] = ok
    lines.append(f"T3 untrained positions (bag, foot) per fold: {_yes(ok)}" + (f" ({'; '.join(bad)})" if bad else ""))
    lines += [f"   {x}" for x in info]
    sb, sc = sim_rows(Path(base + ".md")), sim_rows(Path(cand + ".md"))
    bad, moved = [], []
    for key, (r1, _, _) in sc.items():
        r0, lo, hi = sb[key]
        if round(r1 - r0, 2) != 0:
            moved.append(f"{key[1]} {key[2]} at {key[0]:g} Hz {r0:.2f} -> {r1:.2f} (spread {hi - lo:.2f})")
        if r1 < round(r0 - (hi - lo), 2) - 1e-9:
            bad.append(f"{key[1]} {key[2]} at {key[0]:g} Hz {r0:.2f} -> {r1:.2f} (spread {hi - lo:.2f})")
    ok = not bad
    ok_all &= ok
    passed["T4"] = ok
    lines.append(f"T4 held-out simulator rows within their fold spread: {_yes(ok)}" + (f" ({'; '.join(bad)})" if bad else ""))
    lines.append(f"   rows that moved: {'; '.join(moved) or 'none'}")
    return bool(ok_all), lines, passed


def fold_models(stem: str) -> dict:
    """``{left-out person: fold model folder}`` of a tyrex_modes model cache (``STEM/models/<name>-<person>-<key>``)."""
    out = {}
    for d in sorted((Path(stem) / "models").glob("*")):
        for p in PEOPLE:
            if f"-{p}-" in d.name:
                if p in out:
                    raise SystemExit(f"{stem}: two fold models left out {p} ({out[p].name}, {d.name}); give a cache of one run.")
                out[p] = d
    if set(out) != set(PEOPLE):
        raise SystemExit(f"{stem}/models holds fold models for {sorted(out)}, not {list(PEOPLE)}; pass the run's --model-cache stem.")
    return out


def domain_differences(base_dir: Path, cand_dir: Path) -> list[str]:
    """What differs between two saved models' domain records (R3's tolerances); empty when they are the same record."""
    import json

    import numpy as np

    ja = json.loads((base_dir / "model.json").read_text())["domain"]
    jb = json.loads((cand_dir / "model.json").read_text())["domain"]
    out = []
    for k in R3_THRESHOLD_KEYS:
        if (k in ja) != (k in jb) or (k in ja and not np.isclose(ja[k], jb[k], rtol=R3_THRESHOLD_RTOL, atol=0.0)):
            out.append(f"{k} {ja.get(k)} -> {jb.get(k)}")
    for k in R3_EXACT_KEYS:
        if ja.get(k) != jb.get(k):
            out.append(f"{k} differs")
    sa, sb = ja.get("summary", {}), jb.get("summary", {})
    for k in sorted(set(sa) | set(sb)):  # the window count exactly; the thresholds it repeats to R3's tolerance
        x, y = sa.get(k), sb.get(k)
        numeric = isinstance(x, list) and isinstance(y, list) and len(x) == len(y) and all(isinstance(v, float) for v in x + y)
        if numeric and not np.allclose(x, y, rtol=R3_THRESHOLD_RTOL, atol=0.0):
            out.append(f"summary {k} {x} -> {y}")
        elif not numeric and x != y:
            out.append(f"summary {k} {x} -> {y}")
    a, b = np.load(base_dir / "arrays.npz"), np.load(cand_dir / "arrays.npz")
    ka, kb = sorted(k for k in a.files if k.startswith("domain__")), sorted(k for k in b.files if k.startswith("domain__"))
    if ka != kb:
        return [*out, f"arrays {ka} -> {kb}"]
    for k in ka:
        x, y = a[k], b[k]
        exact = any(k.removeprefix("domain__").startswith(p) for p in R3_EXACT_ARRAYS)
        if x.shape != y.shape:
            out.append(f"{k} shape {x.shape} -> {y.shape}")
        elif exact and not np.array_equal(x, y):
            out.append(f"{k} differs")
        elif not exact and not np.allclose(x, y, rtol=R3_FEATURE_RTOL, atol=R3_FEATURE_RTOL * float(np.max(np.abs(x), initial=0.0))):
            out.append(f"{k} differs by up to {float(np.max(np.abs(x - y))):.3g}")
    return out


def verdict2(base: str, cand: str) -> tuple[bool, list[str]]:
    """R1-R4 of round 2 for ``cand`` against ``base`` (stems of two tyrex_modes runs, each its own model cache)."""
    b, c = motion_table(Path(base + ".csv")), motion_table(Path(cand + ".csv"))
    bp, cp = b[b["left_out"] == "pooled"].set_index(["rate", "motion"]), c[c["left_out"] == "pooled"].set_index(["rate", "motion"])
    lines = []
    w0, w1 = bp.loc[(R1_RATE, "RunningPocket"), "wrong"], cp.loc[(R1_RATE, "RunningPocket"), "wrong"]
    per = c[(c["rate"] == R1_RATE) & (c["motion"] == "RunningPocket") & (c["left_out"] != "pooled")].set_index("left_out")["wrong"]
    ok1 = bool(w1 <= R1_MAX_WRONG)
    lines.append(
        f"R1 RunningPocket silently wrong at {R1_RATE:g} Hz {w0:.4f} -> {w1:.4f} (<= {R1_MAX_WRONG}; per left-out "
        + " / ".join(f"{p} {per[p]:.3f}" for p in per.index)
        + f"): {_yes(ok1)}"
    )
    _, t_lines, t_passed = tests(base, cand)
    ok2 = t_passed["T2"]
    lines.append("R2" + next(ln for ln in t_lines if ln.startswith("T2"))[2:])
    bad = []
    fb, fc = fold_models(base), fold_models(cand)
    for p in PEOPLE:
        diff = domain_differences(fb[p], fc[p])
        bad += [f"{p} out: {x}" for x in diff]
    ub, uc = untrained_rows(Path(base + ".md")), untrained_rows(Path(cand + ".md"))
    for key, folds in uc.items():
        if ub.get(key) != folds:
            bad.append(f"{key[1]} at {key[0]:g} Hz {ub.get(key)} -> {folds}")
    ok3 = not bad
    lines.append("R3 domain record and untrained positions as today's, per fold: " + _yes(ok3) + (f" ({'; '.join(bad)})" if bad else ""))
    ok4 = t_passed["T4"]
    lines.append("R4" + next(ln for ln in t_lines if ln.startswith("T4"))[2:])
    lines += [ln for ln in t_lines if ln.startswith("   rows that moved")]
    return ok1 and ok2 and ok3 and ok4, lines


def _yes(ok) -> str:
    return "pass" if ok else "FAIL"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("base")
    ap.add_argument("candidates", nargs="+")
    ap.add_argument("--rule", type=int, choices=(1, 2), default=1, help="1: round 1's T1-T4; 2: round 2's R1-R4")
    a = ap.parse_args(argv)
    tabs = {a.base: motion_table(Path(a.base + ".csv"))}
    for cand in a.candidates:
        tabs[cand] = motion_table(Path(cand + ".csv"))
    for rate in (50.0, 20.0):
        print(f"\nright / flagged / silently wrong at {rate:g} Hz (pooled; right with Guillaume / Jakob / Thibaud left out)\n")
        print("| motion | " + " | ".join(Path(k).name for k in tabs) + " |")
        print("|---|" + "---|" * len(tabs))
        for m in MOTIONS:
            cells = []
            for t in tabs.values():
                s = t[(t["rate"] == rate) & (t["motion"] == m)].set_index("left_out")
                p = s.loc["pooled"]
                per = " / ".join(f"{s.loc[w, 'right']:.2f}" for w in sorted(x for x in s.index if x != "pooled"))
                cells.append(f"{p['right']:.3f} / {p['flagged']:.3f} / {p['wrong']:.3f} ({per})")
            print(f"| {m} | " + " | ".join(cells) + " |")
    passed = []
    for cand in a.candidates:
        ok, lines = (verdict if a.rule == 1 else verdict2)(a.base, cand)
        print(f"\n{Path(cand).name}: {'PASSES' if ok else 'fails'} the rule")
        print("\n".join(lines))
        if ok:
            passed.append(cand)
    print(f"\npassing: {', '.join(Path(p).name for p in passed) or 'none'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
