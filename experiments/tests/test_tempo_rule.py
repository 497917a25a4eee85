"""The tempo copies' adoption rule T1-T4 read off tyrex_modes --csv / --out files (experiments/scripts/tempo_rule.py)."""

from __future__ import annotations

import pandas as pd

from experiments.scripts.tempo_rule import MOTIONS, verdict

PEOPLE = ("Guillaume", "Jakob", "Thibaud")


def _run(tmp_path, name, *, pocket_right=95, swing_wrong=1, bag="0.84/0.82/0.70", sim_right="0.88", sim_folds="0.88-0.88"):
    """A tyrex_modes run: 100 windows per person, motion and rate; RunningPocket and Swinging set, the rest 97 right."""
    rows = []
    for rate in (None, 20.0):
        for m in MOTIONS:
            for p in PEOPLE:
                right, wrong = 97, 1
                if m == "RunningPocket":
                    right, wrong = pocket_right, 1
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
