"""Zero-velocity detectors on simulated foot-mounted running and walking (issue 30), selection vs held-out seeds.

No shared recording has a foot-mounted IMU on a runner, so :func:`gaitml.simulate.foot.simulate_foot`
simulates one (stance durations from the literature, cited there). Every detector of
:data:`gaitml.zupt.DETECTORS` runs at its defaults, and the two with interval rules
(``pseudo-std``, ``magnitude``) also with each value of ``interval_rules``.

Scores per stance of the instrumented foot (heel strike inside the recording):

- ``interval_recall``: share of true foot-flat intervals overlapped by at least one detected interval;
- ``spurious_per_stance``: detected intervals that overlap no true foot flat, plus every extra
  detected interval on a foot flat beyond the first (a split stance), per stance.

Nothing here is fitted: the interval rules' fractions come from stance physics
(:func:`gaitml.zupt.stride_scaled_stances`). Seeds 0-9 ("selection") were the ones looked at
while writing the simulator and the rules; seeds 100-119 ("held-out") were not looked at before
the table was printed. Both are reported side by side.

    python -m experiments.scripts.zupt_running            # markdown
    python -m experiments.scripts.zupt_running --json
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from gaitml.simulate.foot import simulate_foot
from gaitml.zupt import DETECTORS, get_detector, mask_runs

SELECTION_SEEDS = tuple(range(10))
HELDOUT_SEEDS = tuple(range(100, 120))
#: detector variants: (detector, label, params)
VARIANTS = [(name, "default", {}) for name in DETECTORS] + [
    ("pseudo-std", "interval_rules=fixed", {"interval_rules": "fixed"}),
    ("pseudo-std", "interval_rules=none (paper 001 per sample)", {"interval_rules": "none"}),
    ("magnitude", "interval_rules=fixed (paper 004)", {"interval_rules": "fixed"}),
    ("magnitude", "interval_rules=none", {"interval_rules": "none"}),
]
COLUMNS = [
    "mode",
    "detector",
    "variant",
    "selection_recall",
    "heldout_recall",
    "selection_spurious_per_stance",
    "heldout_spurious_per_stance",
    "heldout_worst_seed_recall",
    "heldout_n_stances",
]


def score(per_sample: np.ndarray, truth_intervals, truth_mask: np.ndarray) -> dict:
    """Recall of the true foot-flat intervals and spurious detected intervals (counts)."""
    s, e = mask_runs(per_sample)
    ts, te = truth_intervals["start"].to_numpy(), truth_intervals["end"].to_numpy()
    hits = np.array([np.sum((s < b) & (e > a)) for a, b in zip(ts, te, strict=True)], dtype=int)
    cs = np.concatenate(([0], np.cumsum(truth_mask)))
    off_truth = int(np.sum((cs[e] - cs[s]) == 0))
    return {"n_stances": len(ts), "n_hit": int(np.sum(hits > 0)), "n_spurious": off_truth + int(np.sum(np.maximum(hits - 1, 0)))}


def run(seeds, mode: str, duration_s: float = 60.0, sampling_rate_hz: float = 100.0) -> dict:
    """Per variant: summed counts over ``seeds`` and the per-seed recall."""
    out: dict = {}
    for seed in seeds:
        rec = simulate_foot(modes=(mode,), duration_s=duration_s, sampling_rate_hz=sampling_rate_hz, seed=seed)
        ref = rec.reference
        for name, label, params in VARIANTS:
            det = get_detector(name, **params).detect(rec)
            sc = score(det.per_sample_zupts_, ref["zupt_intervals"], ref["zupt_mask"])
            acc = out.setdefault((name, label), {"n_stances": 0, "n_hit": 0, "n_spurious": 0, "seed_recall": []})
            for k in ("n_stances", "n_hit", "n_spurious"):
                acc[k] += sc[k]
            acc["seed_recall"].append(sc["n_hit"] / max(sc["n_stances"], 1))
    return out


def table(modes=("run", "walk"), selection=SELECTION_SEEDS, heldout=HELDOUT_SEEDS) -> list[dict]:
    """One row per mode and detector variant: selection and held-out scores side by side."""
    rows = []
    for mode in modes:
        sel, held = run(selection, mode), run(heldout, mode)
        for name, label, _ in VARIANTS:
            a, b = sel[(name, label)], held[(name, label)]
            rows.append(
                {
                    "mode": mode,
                    "detector": name,
                    "variant": label,
                    "selection_recall": a["n_hit"] / a["n_stances"],
                    "heldout_recall": b["n_hit"] / b["n_stances"],
                    "selection_spurious_per_stance": a["n_spurious"] / a["n_stances"],
                    "heldout_spurious_per_stance": b["n_spurious"] / b["n_stances"],
                    "heldout_worst_seed_recall": float(np.min(b["seed_recall"])),
                    "heldout_n_stances": b["n_stances"],
                }
            )
    return rows


def format_markdown(rows: list[dict], columns=COLUMNS) -> str:
    """A markdown table (3 decimals)."""
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        lines.append("| " + " | ".join(f"{r[c]:.3f}" if isinstance(r[c], float) else str(r[c]) for c in columns) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Print the table (markdown, or one JSON object with ``--json``)."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.zupt_running", description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--modes", default="run,walk", help="comma-separated: run, walk")
    args = ap.parse_args(argv)
    rows = table(tuple(m.strip() for m in args.modes.split(",") if m.strip()))
    if args.json:
        json.dump({"rows": rows}, sys.stdout)
        sys.stdout.write("\n")
        return 0
    print(format_markdown(rows))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
