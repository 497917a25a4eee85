"""The tempo copies' adoption rules (round 1 T1-T4, round 2 R1-R4) read off tyrex_modes --csv / --out files and model caches (experiments/scripts/tempo_rule.py)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tempo_rule import MOTIONS, verdict, verdict2

PEOPLE = ("Guillaume", "Jakob", "Thibaud")


def _run(
    tmp_path, name, *, pocket_right=95, pocket_wrong20=1, swing_wrong=1, bag="0.84/0.82/0.70", sim_right="0.88", sim_folds="0.88-0.88"
):
    """A tyrex_modes run: 100 windows per person, motion and rate; RunningPocket and Swinging set, the rest 97 right."""
    rows = []
    for rate in (None, 20.0):
        for m in MOTIONS:
            for p in PEOPLE:
                right, wrong = 97, 1
                if m == "RunningPocket":
                    right, wrong = pocket_right, (pocket_wrong20 if rate == 20.0 else 1)
                if m == "Swinging":
                    right, wrong = 99 - swing_wrong, swing_wrong
                rows.append(
                    {
                        "subject": p,
                        "motion": m,
                        "n": 100,
                        "right": right,
                        "flagged": 100 - right - wrong,
                        "wrong": wrong,
                        "left_out": p,
                        "score_rate_hz": rate,
                    }
                )
    pd.DataFrame(rows).to_csv(tmp_path / f"{name}.csv", index=False)
    sim = "| position | mode | n | right | flagged | silently wrong | right over folds |\n|---|---|---|---|---|---|---|\n"
    sim += f"| swinging-hand | backward | 126 | {sim_right} | 0.02 | 0.10 | {sim_folds} |\n"
    untr = f"| what | windows | flagged |\n|---|---|---|\n| simulator bag (held-out seed) | 312 | {bag} |\n| simulator belt (held-out seed) | 312 | 0.15/0.36/0.12 |\n"
    text = f"held-out simulator (seed 2024, 2 subjects)\n\n{sim}\nnot trained on, flagged (one figure per fold)\n\n{untr}\n"
    text += f"held-out simulator recorded at 20 Hz (seed 2024)\n\n{sim}\nnot trained on, recorded at 20 Hz, flagged (one figure per fold)\n\n{untr}"
    (tmp_path / f"{name}.md").write_text(text)
    return str(tmp_path / name)


def test_a_candidate_passes_only_when_every_test_does(tmp_path):
    base = _run(tmp_path, "base", pocket_right=87)
    ok, lines = verdict(base, _run(tmp_path, "good", pocket_right=92))
    assert ok and all("FAIL" not in ln for ln in lines)
    ok, lines = verdict(base, _run(tmp_path, "t1", pocket_right=89))  # 0.89 < 0.90
    assert not ok and lines[0].startswith("T1") and lines[0].endswith("FAIL")
    ok, lines = verdict(base, _run(tmp_path, "t2", pocket_right=92, swing_wrong=2))  # Swinging silently wrong +0.01
    assert not ok and any(ln.startswith("T2") and "Swinging at 50 Hz" in ln for ln in lines)
    ok, lines = verdict(base, _run(tmp_path, "t3", pocket_right=92, bag="0.84/0.79/0.69"))  # 0.82 -> 0.79: below 0.80
    assert not ok and any(ln.startswith("T3") and "0.82 -> 0.79" in ln for ln in lines)
    ok, _ = verdict(base, _run(tmp_path, "t3ok", pocket_right=92, bag="0.84/0.80/0.68"))  # 0.70 -> 0.68: within 0.02
    assert ok
    ok, lines = verdict(base, _run(tmp_path, "t4", pocket_right=92, sim_right="0.87"))  # fold spread 0.00
    assert not ok and any(ln.startswith("T4") and "swinging-hand backward" in ln for ln in lines)


def _folds(stem, threshold=25.6, feature_noise=0.0, gravity_shift=0.0, n_windows=1000):
    """Fold models of a run's model cache (STEM/models), holding only what R3 reads: the domain's json and arrays."""
    rng = np.random.default_rng(0)
    center = rng.normal(size=107)
    for i, p in enumerate(PEOPLE):
        d = Path(stem) / "models" / f"demo-a-{p}-{i:04x}"
        d.mkdir(parents=True)
        dom = {
            "distance_threshold": (threshold + i) * (1.0 + feature_noise),
            "distance_threshold_in_sample": 18.0,
            "gravity_threshold_rad": 0.8,
            "gravity_threshold_in_sample_rad": 0.2,
            "min_rate_hz": 20.0,
            "summary": {"n_windows": n_windows, "distance_threshold_heldout_vs_in_sample": [(threshold + i) * (1.0 + feature_noise), 18.0]},
            "quantile": 0.99,
        }
        (d / "model.json").write_text(json.dumps({"domain": dom}))
        np.savez(
            d / "arrays.npz",
            domain__center=center * (1.0 + feature_noise),
            domain__gravity_dirs=np.ones((4, 3)) + gravity_shift,
        )


def test_round_2_passes_only_when_every_test_does(tmp_path):
    base = _run(tmp_path, "base", pocket_right=87, pocket_wrong20=7)
    _folds(base)

    def cand(name, folds=None, **kw):
        stem = _run(tmp_path, name, **{"pocket_right": 92, "pocket_wrong20": 2, **kw})
        _folds(stem, **(folds or {}))
        return verdict2(base, stem)

    ok, lines = cand("good", folds={"feature_noise": 1e-12})  # rounding in the features and thresholds: the same record
    assert ok and all("FAIL" not in ln for ln in lines), lines
    ok, lines = cand("r1", pocket_wrong20=6)  # 0.06 > 0.05 at 20 Hz
    assert not ok and lines[0].startswith("R1") and lines[0].endswith("FAIL")
    ok, lines = cand("r2", swing_wrong=2)
    assert not ok and any(ln.startswith("R2") and "Swinging at 50 Hz" in ln for ln in lines)
    ok, lines = cand("r3t", folds={"threshold": 25.7})  # a threshold moved
    assert not ok and any(ln.startswith("R3") and "distance_threshold 25.6 -> 25.7" in ln for ln in lines)
    ok, lines = cand("r3g", folds={"gravity_shift": 1e-12})  # gravity arrays must be equal
    assert not ok and any(ln.startswith("R3") and "gravity_dirs differs" in ln for ln in lines)
    ok, lines = cand("r3n", folds={"n_windows": 1001})  # another window count: another record
    assert not ok and any(ln.startswith("R3") and "summary n_windows 1000 -> 1001" in ln for ln in lines)
    ok, lines = cand("r3b", bag="0.84/0.82/0.69")  # an untrained position moved by 0.01: not today's
    assert not ok and any(ln.startswith("R3") and "simulator bag" in ln for ln in lines)
    ok, lines = cand("r4", sim_right="0.87")
    assert not ok and any(ln.startswith("R4") and "swinging-hand backward" in ln for ln in lines)
