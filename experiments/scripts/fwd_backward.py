"""The forward-vector feature group against today's recipe (issue 27, backward walking in the hand): the rule's verdict.

``python -m experiments.scripts.fwd_backward --base-cache DIR --cand-cache DIR --config CONFIG [--seeds 2024,2025,2026]
[--base-csv FILE --cand-csv FILE] [--demo OUT]`` from the repository root.

What it compares. The fold models of two runs of :mod:`experiments.scripts.tyrex_modes` (recipe ``a``, each tyrex
person left out in turn; ``--model-cache DIR`` keeps them in ``DIR/models``): the baseline (today's
``experiments/demo.toml``, feature set ``all52+gyro``) and a candidate (``experiments/demo-fwd.toml``, ``all52+gyro+fwd``:
the forward vector of :mod:`gaitml.features._forward` appended, nothing else changed). Nothing is trained here.

- ``--seeds``: held-out simulated walkers (2 subjects per seed and position, the five positions of the config's
  simulated part, as tyrex_modes scores them), every fold model of each run predicting them through gaitml predict's
  own path, windows summed over the three folds: right per position x mode, exact counts, and the difference.
- ``--base-csv`` / ``--cand-csv``: tyrex_modes' per-recording rows (``--csv``): right and silently wrong per motion,
  pooled over the left-out people and per left-out person, and the difference.
- ``--demo OUT``: ``gaitml demo``'s simulator cross-validation (16 hand-flat subjects, leave-one-subject-out, the demo's
  own settings, :data:`gaitml.demo.DEMO_SETTINGS`) with its feature set as shipped and with ``+fwd``: recall per mode.

The adoption rule (experiments/reports/default-model.md, "Forward vector", FV.0; fixed before any figure was
measured), checked on ``--rule-seeds`` (default 2024, the seed tyrex_modes and section 4 hold out, for the first
candidate; 2027,2028 for the second, whose rule was written after seeds 2024-2026 had been looked at) and the tyrex
rows:

1. hand-flat and hand-tilted backward right >= 0.90;
2. no other position x mode row of the held-out simulator right lower than the baseline's by more than 0.02;
3. tyrex, pooled per motion: right not lower by more than 0.005, silently wrong not higher by more than 0.005.

Other seeds are context (how much a row moves from one set of held-out walkers to the next), not the rule.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["RULE_SEED", "compare_sim", "compare_tyrex", "fold_models", "verdict", "main"]

#: The held-out seed the rule reads (tyrex_modes.HELDOUT_SEED, section 4 of the report).
RULE_SEED = 2024
#: Rule 1: the hand-held backward rows and their floor.
BACKWARD_ROWS = (("hand-flat", "backward"), ("hand-tilted", "backward"))
BACKWARD_FLOOR = 0.90
#: Rule 2: the largest fall of any other simulator row.
SIM_MAX_FALL = 0.02
#: Rule 3: the largest fall of tyrex right and rise of silently wrong, per motion.
TYREX_MAX_MOVE = 0.005


def fold_models(cache: Path) -> list:
    """The fold models a tyrex_modes run kept under ``cache/models`` (one per left-out person), sorted by name."""
    from gaitml.models import load_model

    dirs = sorted(p for p in (Path(cache) / "models").iterdir() if (p / "model.json").exists())
    if not dirs:
        raise SystemExit(f"no fold models under {cache}/models; run experiments.scripts.tyrex_modes with --model-cache {cache} first.")
    return [load_model(d) for d in dirs]


def sim_rows(models: list, recs: list) -> pd.DataFrame:
    """Held-out simulator windows summed over ``models``: n, right per position x mode."""
    from experiments.scripts.tyrex_modes import sim_side_table

    t = pd.concat([sim_side_table(m, recs) for m in models], ignore_index=True)
    return t.groupby(["position", "mode"], sort=False)[["n", "right", "flagged", "wrong", "side"]].sum().reset_index()


def compare_sim(base: pd.DataFrame, cand: pd.DataFrame) -> pd.DataFrame:
    """Side by side: right (share) of the baseline and the candidate per position x mode, and the difference."""
    m = base.merge(cand, on=["position", "mode"], suffixes=("_base", "_cand"))
    m["right_base"] = m["right_base"] / m["n_base"]
    m["right_cand"] = m["right_cand"] / m["n_cand"]
    m["wrong_cand"] = m["wrong_cand"] / m["n_cand"]
    m["change"] = m["right_cand"] - m["right_base"]
    # a side step read as a side step of either direction (in the pockets and the swinging hand predict marks the
    # direction unsure, section 4); context, not the rule
    m["side_base"] = m["side_base"] / m["n_base"]
    m["side_cand"] = m["side_cand"] / m["n_cand"]
    return m[["position", "mode", "n_base", "right_base", "right_cand", "change", "wrong_cand", "side_base", "side_cand"]]


def compare_tyrex(base: pd.DataFrame, cand: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per motion pooled, and per motion x left-out person: right and silently wrong of both, and the differences."""

    def pooled(t, by):
        g = t.groupby(by, sort=False)[["n", "right", "wrong"]].sum()
        return pd.DataFrame({"n": g["n"], "right": g["right"] / g["n"], "wrong": g["wrong"] / g["n"]})

    out = []
    for by in (["motion"], ["motion", "left_out"]):
        b, c = pooled(base, by), pooled(cand, by)
        m = b.merge(c, left_index=True, right_index=True, suffixes=("_base", "_cand"))
        m["right_change"] = m["right_cand"] - m["right_base"]
        m["wrong_change"] = m["wrong_cand"] - m["wrong_base"]
        out.append(m.reset_index())
    return out[0], out[1]


def verdict(sim: pd.DataFrame | None, tyrex: pd.DataFrame | None) -> list[tuple[str, bool, str]]:
    """The three parts of the rule: (name, holds, what decided it)."""
    out = []
    if sim is not None:
        key = sim.set_index(["position", "mode"])
        back = [(p, m, float(key.loc[(p, m), "right_cand"])) for p, m in BACKWARD_ROWS]
        out.append(
            ("1 hand-held backward >= 0.90", all(v >= BACKWARD_FLOOR for *_, v in back), ", ".join(f"{p} {v:.3f}" for p, _, v in back))
        )
        others = sim[~sim.set_index(["position", "mode"]).index.isin(BACKWARD_ROWS)]
        bad = others[others["change"] < -SIM_MAX_FALL]
        out.append(
            (
                "2 no other simulator row down by > 0.02",
                bad.empty,
                "; ".join(f"{r.position} {r.mode} {r.right_base:.3f} -> {r.right_cand:.3f}" for r in bad.itertuples()) or "none",
            )
        )
    if tyrex is not None:
        bad = tyrex[(tyrex["right_change"] < -TYREX_MAX_MOVE) | (tyrex["wrong_change"] > TYREX_MAX_MOVE)]
        out.append(
            (
                "3 tyrex right / silently wrong within 0.005",
                bad.empty,
                "; ".join(
                    f"{r.motion} right {r.right_base:.4f} -> {r.right_cand:.4f}, wrong {r.wrong_base:.4f} -> {r.wrong_cand:.4f}"
                    for r in bad.itertuples()
                )
                or "none",
            )
        )
    return out


def demo_cv(out: Path) -> pd.DataFrame:
    """``gaitml demo``'s cross-validation with its feature set as shipped and with ``+fwd``: recall per mode (after the correction)."""
    from gaitml.demo import DEMO_SETTINGS, run_demo

    cols = {}
    for fset in (DEMO_SETTINGS["features"], DEMO_SETTINGS["features"] + "+fwd"):
        s = run_demo(out / fset.replace("+", "_"), settings={**DEMO_SETTINGS, "features": fset}, progress=False)
        cv = s["cross_validation"]
        rec = {m: float(v["recall"]) for m, v in cv["per_class"].items()}
        rec["accuracy before -> after the correction"] = f"{cv['accuracy_before_correction']:.3f} -> {cv['accuracy_after_correction']:.3f}"
        cols[fset] = rec
    return pd.DataFrame(cols)


def _md(df: pd.DataFrame) -> str:
    """A markdown table, shares to 3 decimals (the rule's bounds are 0.005 and 0.02)."""

    def cell(v):
        return f"{v:.3f}" if isinstance(v, float | np.floating) else str(v)

    lines = ["| " + " | ".join(map(str, df.columns)) + " |", "|" + "---|" * len(df.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join(lines)


def main(argv=None) -> int:
    from experiments.scripts.tyrex_modes import _sim, simulated_part
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base-cache", type=Path, help="tyrex_modes --model-cache of the baseline run")
    ap.add_argument("--cand-cache", type=Path, help="tyrex_modes --model-cache of the candidate run")
    ap.add_argument("--config", type=Path, default=Path("experiments/demo-fwd.toml"), help="the simulated part's settings")
    ap.add_argument("--seeds", default="", help="comma-separated held-out simulator seeds ('' = none)")
    ap.add_argument(
        "--rule-seeds",
        default=str(RULE_SEED),
        help="the seeds the rule reads, windows summed over them (default %(default)s; the second candidate's rule: 2027,2028)",
    )
    ap.add_argument("--base-csv", type=Path, default=None)
    ap.add_argument("--cand-csv", type=Path, default=None)
    ap.add_argument("--demo", type=Path, default=None, metavar="OUT", help="also run gaitml demo's cross-validation both ways into OUT")
    a = ap.parse_args(argv)
    sim_rule = tyrex_rule = None
    if a.seeds:
        if a.base_cache is None or a.cand_cache is None:
            raise SystemExit("--seeds needs --base-cache and --cand-cache.")
        cfg = simulated_part(load_config(a.config))
        positions = cfg["data"]["simulated"]["positions"]
        base_models, cand_models = fold_models(a.base_cache), fold_models(a.cand_cache)
        rule_seeds = [int(s) for s in a.rule_seeds.split(",") if s]
        pooled_b, pooled_c = [], []
        for seed in [int(s) for s in a.seeds.split(",") if s]:
            # simulated as tyrex_modes simulates its held-out walkers (bag and belt too, so the same walkers come out)
            recs = [r for r in _sim(cfg, seed, 2, [*positions, "bag", "belt"]) if r.meta["position"] in positions]
            b, c = sim_rows(base_models, recs), sim_rows(cand_models, recs)
            t = compare_sim(b, c)
            which = "a seed the rule reads" if seed in rule_seeds else "context, not the rule"
            print(f"\n### held-out simulator, seed {seed} ({which}): right, windows summed over the {len(base_models)} fold models\n")
            print(_md(t))
            if seed in rule_seeds:
                pooled_b.append(b)
                pooled_c.append(c)
            print(f"[fwd_backward] seed {seed} scored", file=sys.stderr)
        if pooled_b:

            def total(ts):
                cols = ["n", "right", "flagged", "wrong", "side"]
                return pd.concat(ts).groupby(["position", "mode"], sort=False)[cols].sum().reset_index()

            sim_rule = compare_sim(total(pooled_b), total(pooled_c))
            if len(pooled_b) > 1:
                print(f"\n### held-out simulator, the rule's seeds {a.rule_seeds} together\n")
                print(_md(sim_rule))
    if a.base_csv is not None and a.cand_csv is not None:
        pooled, per = compare_tyrex(pd.read_csv(a.base_csv), pd.read_csv(a.cand_csv))
        print("\n### tyrex, each person left out (speed rule): pooled per motion\n")
        print(_md(pooled))
        print("\n### tyrex, per left-out person\n")
        print(_md(per))
        tyrex_rule = pooled
    if a.demo is not None:
        print("\n### gaitml demo's cross-validation (16 simulated hand-flat subjects, leave-one-subject-out): recall per mode\n")
        print(_md(demo_cv(a.demo).reset_index(names="mode")))
    rule = verdict(sim_rule, tyrex_rule)
    if rule:
        print("\n### the adoption rule\n")
        for name, ok, why in rule:
            print(f"- {name}: {'holds' if ok else 'FAILS'} ({why})")
        if len(rule) == 3:
            print(f"\nverdict: {'ADOPT' if all(ok for _, ok, _ in rule) else 'do not adopt'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
