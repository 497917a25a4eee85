"""Every PDR target of issue 27 in one table: ``gaitml pdr`` at its defaults, uncalibrated and with the step length calibrated on the other tyrex people.

``python -m experiments.scripts.tyrex_pdr_targets [--data ../shared/data] [--model models/demo] [--cache FILE] [--json-dir DIR] [--csv FILE] [--out FILE] [--no-gyrocal] [--fold-models DIR] [--short-runs W]``
from the repository root. Nothing new is built here: the per-recording runs are
:func:`experiments.scripts.tyrex_steplen.prepare`'s (``gaitml pdr``'s defaults: the default step
detector, the guarded HDE heading, gyroscope bias ``auto``; forward-only and ``--model``), the step
lengths are :func:`experiments.scripts.tyrex_steplen.fit_fold`'s calibration (paper 003 eq. 12 for
``walk``, Weinberg eq. 13 for ``run``, :func:`gaitml.pdr.calibrate.fit_step_lengths`) and the rows are
:func:`experiments.scripts.tyrex_steplen.run_all`'s: each person left out (fitted on the other two,
scored on the left-out one: held out) and ``all`` (fitted and scored on all three: in sample). The
references (``baseline``, ``bound``, ``still``) are :mod:`experiments.scripts.tyrex_pdr`'s.

Configurations scored (the ``gaitml pdr`` command a user types; ``FOLD.json`` is the calibration of
the people other than the one scored, written to ``--json-dir``):

- ``gaitml pdr`` (uncalibrated, forward-only) and ``gaitml pdr --model models/demo`` (model modes);
- ``gaitml pdr --step-length FOLD.json`` and ``gaitml pdr --model models/demo --step-length FOLD.json``,
  held out and in sample.

With ``--gyro-bias-from`` (branch gyrocal; leave out with ``--no-gyrocal``): the same four runs with the gyroscope
bias of the phone's still log (``gaitml pdr --gyro-bias-from LOG``: started from it, then tracked, the option's
default), LOG chosen by :mod:`experiments.scripts.tyrex_gyrocal`'s rule (the phone's still gyroscope log with the
most still seconds; chosen on no walk); a second set of per-recording runs, cached beside ``--cache``.

The user-facing path is checked, not assumed: for every fold and both runs, ``gaitml pdr DIR
--step-length FOLD.json [--model models/demo] --out CSV`` (the command line, in process) is run on
one recording of the fold without a sensor gap and its positions are compared with the table's.

Issue 27's targets per motion (AR is mostly standing: reported, not targeted), each with its
margin, positive when met (fixed before the first run of this script, from the issue's wording):

1. distance ratio 0.9-1.1: margin ``0.1 - |ratio - 1|``, met when >= 0;
2. 10 s error at most 1.25 x the bound's: margin ``1.25 bound - error`` (points), met when >= 0;
3. 10 s error below standing still's wherever the bound is below it: margin ``still - error``, met
   when > 0; "n/a" where the bound's error is not below still's;
4. walking-direction drift no worse than the plain integrated gyroscope's (the baseline's heading):
   margin ``|drift| plain - |drift|`` (deg/min), met when >= 0;
5. model modes no worse than forward-only (same step length): margin ``error forward-only - error``,
   met when >= 0;
6. the baseline beaten: margin ``error baseline - error``, met when > 0.

Each is judged on the median over the recordings of a motion (NoDist: 9 per motion, as the issue's
figures; and all recordings: 18 per walking motion, 9 per running one), and per person on the median
over that person's recordings (all of them), the range of the margin and how many of the three meet it.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_gyrocal import CALIBRATION_GLOBS, still_logs
from experiments.scripts.tyrex_pdr import MOTION_ORDER, load_tyrex, md
from experiments.scripts.tyrex_steplen import RUN_MOTIONS, SUCCESS_MOTIONS, WALK_MOTIONS, _lengths, _positions, load_or_prepare, run_all

__all__ = [
    "CONFIGS",
    "CONFIGS_GYROCAL",
    "TARGETS",
    "check_cli",
    "count_met",
    "judge",
    "main",
    "person_margins",
    "target_table",
    "verdict_matrix",
]

#: configurations: label -> (variant in tyrex_steplen's table, held out?, forward-only variant to compare model modes with)
CONFIGS = {
    "uncalibrated": ("fwd/default", True, None),
    "uncalibrated --model": ("model/default", True, "fwd/default"),
    "calibrated, held out": ("fwd/cal", True, None),
    "calibrated --model, held out": ("model/cal", True, "fwd/cal"),
    "calibrated, in sample": ("fwd/cal", False, None),
    "calibrated --model, in sample": ("model/cal", False, "fwd/cal"),
}
#: the same with ``--gyro-bias-from LOG`` (branch gyrocal: the bias of the phone's still log, then tracked)
GYROCAL = " +gyrocal"
CONFIGS_GYROCAL = {
    "--gyro-bias-from, uncalibrated": ("fwd/default" + GYROCAL, True, None),
    "--gyro-bias-from --model, uncalibrated": ("model/default" + GYROCAL, True, "fwd/default" + GYROCAL),
    "--gyro-bias-from, calibrated, held out": ("fwd/cal" + GYROCAL, True, None),
    "--gyro-bias-from --model, calibrated, held out": ("model/cal" + GYROCAL, True, "fwd/cal" + GYROCAL),
    "--gyro-bias-from --model, calibrated, in sample": ("model/cal" + GYROCAL, False, "fwd/cal" + GYROCAL),
}
#: the targets of issue 27 ("What it must show", PDR table), in the order printed
TARGETS = (
    "distance ratio 0.9-1.1",
    "10 s error <= 1.25 x bound",
    "10 s error < still (where bound < still)",
    "drift <= plain gyro",
    "model modes no worse than forward-only",
    "baseline beaten",
)
#: the command-line options of each tyrex_steplen run
RUN_OPTIONS = {"fwd": [], "model": ["--model"]}


def _medians(table: pd.DataFrame) -> pd.DataFrame:
    """Median per (variant, motion) of the distance ratio, 10 s error and |drift|."""
    t = table.assign(abs_drift=table["drift_deg_per_min"].abs())
    return t.groupby(["variant", "motion"])[["distance_ratio", "error_10s_pct", "abs_drift"]].median()


def judge(med: pd.DataFrame, variant: str, forward: str | None, motion: str) -> dict[str, dict]:
    """The six targets for one variant and motion from a table of medians (:func:`_medians`).

    Returns target -> {value, reference, margin, met}; a target that does not apply has
    ``met`` None (model modes for a forward-only run; below still where the bound is not).
    """

    def get(v, col):
        return float(med.loc[(v, motion), col]) if (v, motion) in med.index else float("nan")

    d, e, dr = get(variant, "distance_ratio"), get(variant, "error_10s_pct"), get(variant, "abs_drift")
    b, s = get("bound", "error_10s_pct"), get("still", "error_10s_pct")
    base_e, base_dr = get("baseline", "error_10s_pct"), get("baseline", "abs_drift")
    out = {
        TARGETS[0]: {"value": d, "reference": "0.9-1.1", "margin": 0.1 - abs(d - 1.0), "ge": True},
        TARGETS[1]: {"value": e, "reference": 1.25 * b, "margin": 1.25 * b - e, "ge": True},
        TARGETS[2]: {"value": e, "reference": s, "margin": s - e if b < s else float("nan"), "ge": False},
        TARGETS[3]: {"value": dr, "reference": base_dr, "margin": base_dr - dr, "ge": True},
        TARGETS[4]: {
            "value": e,
            "reference": get(forward, "error_10s_pct") if forward else float("nan"),
            "margin": float("nan"),
            "ge": True,
        },
        TARGETS[5]: {"value": e, "reference": base_e, "margin": base_e - e, "ge": False},
    }
    if forward:
        out[TARGETS[4]]["margin"] = out[TARGETS[4]]["reference"] - e
    for t in out.values():
        m = t.pop("margin")
        ge = t.pop("ge")
        t["margin"] = m
        # a tie with forward-only is "no worse" (the same trajectory); round off float noise
        t["met"] = None if not np.isfinite(m) else bool(m >= -1e-9 if ge else m > 1e-9)
    return out


def target_table(table: pd.DataFrame, variant: str, forward: str | None, *, held_out: bool) -> pd.DataFrame:
    """Long table: one row per (subset, motion, target) with value, reference, margin and met.

    Subsets: ``NoDist`` and ``all`` (medians over the recordings of a motion) and each person
    (medians over that person's recordings of the motion)."""
    sel = table[table["held_out"] == held_out]
    subsets = {"NoDist": sel[sel["disturbance"] == "NoDist"], "all": sel}
    for person in sorted(sel["subject"].unique()):
        subsets[person] = sel[sel["subject"] == person]
    rows = []
    for name, sub in subsets.items():
        med = _medians(sub)
        for motion in [m for m in MOTION_ORDER if m in set(sub["motion"])]:
            for target, r in judge(med, variant, forward, motion).items():
                rows.append({"subset": name, "motion": motion, "target": target, **r})
    return pd.DataFrame(rows)


def person_margins(long: pd.DataFrame) -> pd.DataFrame:
    """Per (motion, target): the range of the value and of the margin over the people, and how many meet it."""
    per = long[~long["subset"].isin(["NoDist", "all"])]
    rows = []
    for (motion, target), g in per.groupby(["motion", "target"], sort=False):
        judged = g[g["met"].notna()]
        rows.append(
            {
                "motion": motion,
                "target": target,
                "value_min": g["value"].min(),
                "value_max": g["value"].max(),
                "margin_min": judged["margin"].min() if len(judged) else float("nan"),
                "margin_max": judged["margin"].max() if len(judged) else float("nan"),
                "people_met": int(judged["met"].astype(bool).sum()),
                "people_judged": len(judged),
            }
        )
    return pd.DataFrame(rows)


def _fmt(v, fmt: str) -> str:
    return fmt.format(v) if isinstance(v, (int, float, np.floating)) and np.isfinite(v) else ("-" if not isinstance(v, str) else v)


_VALUE_FMT = {TARGETS[0]: "{:.2f}", TARGETS[3]: "{:.0f}"}


def _verdict(r, fmt: str) -> str:
    if r["met"] is None:
        return "n/a"
    return f"{'met' if r['met'] else '**not met**'} ({'+' if r['margin'] >= 0 else ''}{_fmt(r['margin'], fmt)})"


def main_table(long: pd.DataFrame) -> pd.DataFrame:
    """The targets table of one configuration: NoDist and all recordings (value vs reference, verdict with margin) and the people."""
    persons = person_margins(long).set_index(["motion", "target"])
    rows = []
    for motion in [m for m in MOTION_ORDER if m in set(long["motion"])]:
        for target in TARGETS:
            fmt = _VALUE_FMT.get(target, "{:.1f}")
            row = {"motion": motion if motion in SUCCESS_MOTIONS else f"{motion} (reported)", "target": target}
            for subset in ("NoDist", "all"):
                r = long[(long["subset"] == subset) & (long["motion"] == motion) & (long["target"] == target)].iloc[0]
                row[f"{subset}: ours vs reference"] = f"{_fmt(r['value'], fmt)} vs {_fmt(r['reference'], fmt)}"
                row[f"{subset} verdict (margin)"] = _verdict(r, fmt) if motion in SUCCESS_MOTIONS else "reported"
            p = persons.loc[(motion, target)]
            row["per person: ours"] = f"{_fmt(p['value_min'], fmt)}-{_fmt(p['value_max'], fmt)}"
            row["per person: margin, met"] = (
                f"{_fmt(p['margin_min'], fmt)} to {_fmt(p['margin_max'], fmt)}, {int(p['people_met'])}/{int(p['people_judged'])}"
                if p["people_judged"]
                else "n/a"
            )
            rows.append(row)
    return pd.DataFrame(rows).set_index(["motion", "target"])


def verdict_matrix(longs: dict[str, pd.DataFrame], subset: str) -> pd.DataFrame:
    """Per (targeted motion, target): every configuration's verdict with its margin, on one subset."""
    rows = []
    for motion in SUCCESS_MOTIONS:
        for target in TARGETS:
            fmt = _VALUE_FMT.get(target, "{:.1f}")
            row = {"motion": motion, "target": target}
            for label, long in longs.items():
                r = long[(long["subset"] == subset) & (long["motion"] == motion) & (long["target"] == target)]
                row[label] = _verdict(r.iloc[0], fmt) if len(r) else "-"
            rows.append(row)
    return pd.DataFrame(rows).set_index(["motion", "target"])


def count_met(long: pd.DataFrame, subset: str) -> str:
    """'met/judged' over the targeted motions of one subset (targets that do not apply are not counted)."""
    sel = long[(long["subset"] == subset) & long["motion"].isin(SUCCESS_MOTIONS)]
    judged = [bool(m) for m in sel["met"] if m is not None and not (isinstance(m, float) and np.isnan(m))]
    return f"{sum(judged)}/{len(judged)}"


def check_cli(
    items, preps, fitted: dict, root: Path, json_dir: Path, model_path: str | None, extra_argv=None
) -> list[tuple[str, str, str, float]]:
    """Per fold and run, ``gaitml pdr DIR --step-length FOLD.json [--model ...] --out CSV`` against the table's positions.

    ``root`` is the tyrex-attitude folder. Writes each fold's calibration to ``json_dir/steplength-<fold>.json`` (what a user passes).
    Checked on one walking and one running recording of the fold without a sensor gap; on fold ``all``'s
    two recordings also without ``--step-length`` (the uncalibrated rows).
    ``extra_argv(item)``, when given, adds options to every command (``--gyro-bias-from LOG``).
    Returns (fold, run, file, largest position difference in m)."""
    from gaitml.pdr.step_length import StepLengthModel

    out = []
    for fold, models in fitted.items():
        path = json_dir / f"steplength-{fold}.json"
        if path.exists() and StepLengthModel.load(path).to_dict() != models["cal"].to_dict():
            raise SystemExit(f"error: {path} holds another calibration than this run's fold {fold}; delete it or pass another --json-dir.")
        models["cal"].save(path)
        for motions in (WALK_MOTIONS, RUN_MOTIONS):
            k = next(
                i
                for i, it in enumerate(items)
                if (fold == "all" or it["subject"] == fold) and it["n_segments"] == 1 and it["motion"] in motions
            )
            extra = extra_argv(items[k]) if extra_argv else []
            out += _check_one(items[k], preps[k], fold, models, path, root, model_path, extra)
            if fold == "all":  # the uncalibrated rows: the same command without --step-length
                out += _check_one(items[k], preps[k], "uncalibrated", models, None, root, model_path, extra)
    return out


def _check_one(it, pr, fold, models, path, root, model_path, extra=()) -> list[tuple[str, str, str, float]]:
    """One recording: the command line's positions (forward-only and ``--model``) against the table's rebuilt ones
    (``path`` None: without ``--step-length``, against the uncalibrated rows)."""
    from gaitml.cli import main as cli_main

    out = []
    model_path = model_path[it["subject"]] if isinstance(model_path, dict) else model_path
    for run in ("fwd", "model"):
        if run not in pr["runs"] or (run == "model" and not model_path):
            continue
        with tempfile.TemporaryDirectory() as tmp:
            csv = Path(tmp) / "traj.csv"
            argv = ["pdr", str(root / it["file"]), "--out", str(csv)] + (["--step-length", str(path)] if path else [])
            argv += (["--model", model_path] if run == "model" else []) + list(extra)
            with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
                rc = cli_main(argv)
            if rc != 0:
                raise SystemExit(f"error: gaitml {' '.join(argv)} exited {rc}")
            got = pd.read_csv(csv)[["x_m", "y_m"]].to_numpy()
        want = _positions(pr["runs"][run], _lengths(pr["runs"][run], "cal" if path else "default", models, it["motion"]))
        diff = float(np.max(np.abs(got - want))) if got.shape == want.shape else float("inf")
        out.append((fold, run, it["file"], diff))
    return out


def fold_model_paths(cache: Path, people: list[str]) -> dict[str, str]:
    """Each person's fold model in a ``tyrex_modes --model-cache`` folder (``models/<name>-<recipe>-<Person>-<hash>``,
    trained without that person)."""
    out = {}
    for person in people:
        found = sorted((cache / "models").glob(f"*-{person}-*"))
        if len(found) != 1:
            raise SystemExit(
                f"error: {cache}/models holds {len(found)} fold models for {person} (need 1); pass tyrex_modes' --model-cache of one recipe."
            )
        out[person] = str(found[0])
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_pdr_targets", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--model", default="models/demo", help="model for the --model rows")
    p.add_argument(
        "--fold-models",
        metavar="DIR",
        help="tyrex_modes' --model-cache of the shipped recipe (DIR/models/<name>-a-<Person>-<hash>): each person's runs take the "
        "model trained without them, so the model modes are held out too (use another --cache and --json-dir)",
    )
    p.add_argument(
        "--short-runs",
        type=float,
        default=None,
        metavar="WINDOWS",
        help="gaitml pdr --short-runs WINDOWS in every run (run_pdr's short_run_windows; default: gaitml pdr's own); use "
        "another --cache and --json-dir",
    )
    p.add_argument("--cache", default="/tmp/pdrtargets/preps.pkl", help="pickle of the per-recording runs (tyrex_steplen's format)")
    p.add_argument("--json-dir", default="/tmp/pdrtargets", help="where each fold's step-length JSON is written")
    p.add_argument("--csv", metavar="FILE", help="write the long targets table (every configuration, subset, motion, target)")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    p.add_argument(
        "--no-gyrocal",
        dest="gyrocal",
        action="store_false",
        help="leave out the --gyro-bias-from rows (the bias of each phone's still log; a second set of runs, cached beside --cache)",
    )
    args = p.parse_args(argv)
    if not args.model:
        raise SystemExit("error: --model is needed (the targets compare model modes with forward-only); pass --model models/demo.")
    t0 = time.perf_counter()
    items = load_tyrex(Path(args.data))
    from gaitml.models import load_model

    model, model_arg = load_model(args.model), args.model
    if args.fold_models:
        model_arg = fold_model_paths(Path(args.fold_models), sorted({it["subject"] for it in items}))
        model = {person: load_model(path) for person, path in model_arg.items()}
    short = {} if args.short_runs is None else {"short_run_windows": args.short_runs}
    short_argv = [] if args.short_runs is None else ["--short-runs", f"{args.short_runs:g}"]
    preps = load_or_prepare(items, model, args.cache, t0, options_of=(lambda it: dict(short)) if short else None)
    table, fitted, checks = run_all(items, preps, model)
    json_dir = Path(args.json_dir)
    json_dir.mkdir(parents=True, exist_ok=True)
    root = Path(args.data) / "tyrex-attitude"
    cli = check_cli(items, preps, fitted, root, json_dir, model_arg, extra_argv=(lambda it: list(short_argv)) if short else None)
    configs = dict(CONFIGS)
    lines = []
    if args.gyrocal:
        # the phone's still log with the most still seconds (tyrex_gyrocal's rule, fixed there before measuring)
        logs = {phone: found[0] for phone, found in still_logs(Path(args.data)).items() if found}
        missing = sorted({it["phone"] for it in items} - set(logs))
        if missing:
            raise SystemExit(f"error: no usable still gyroscope log for {missing}; pass --no-gyrocal.")
        cache_gc = str(Path(args.cache).with_name(Path(args.cache).stem + "-gyrocal.pkl"))
        preps_gc = load_or_prepare(items, model, cache_gc, t0, options_of=lambda it: {"gyro_bias_start": logs[it["phone"]][1], **short})
        table_gc, fitted_gc, checks_gc = run_all(items, preps_gc, model)
        kept = table_gc[table_gc["variant"].isin(["fwd/default", "model/default", "fwd/cal", "model/cal"])]
        table = pd.concat([table, kept.assign(variant=kept["variant"] + GYROCAL)], ignore_index=True)
        checks += checks_gc

        def log_argv(it):
            return ["--gyro-bias-from", str(root / CALIBRATION_GLOBS[it["phone"]].split("/")[0] / logs[it["phone"]][0]), *short_argv]

        cli_gc = check_cli(items, preps_gc, fitted_gc, root, json_dir, model_arg, extra_argv=log_argv)
        cli += [(f"{c[0]} gyrocal", *c[1:]) for c in cli_gc]
        configs.update(CONFIGS_GYROCAL)
        lines += [
            "still logs (--gyro-bias-from): " + ", ".join(f"{ph} {lg[0]} ({lg[1].still_s:.0f} s still)" for ph, lg in logs.items()),
            "",
        ]
    longs = {label: target_table(table, v, fwd, held_out=h) for label, (v, h, fwd) in configs.items()}
    if args.csv:
        pd.concat([lg.assign(config=label) for label, lg in longs.items()]).to_csv(args.csv, index=False)
    lines = [
        *lines,
        f"same code path: rebuilt trajectories vs run_pdr(step_length=...) at most {max(c[2] for c in checks):.2e} m ({len(checks)} checks); "
        f"vs the command line `gaitml pdr DIR [--step-length FOLD.json] [--model]` at most {max(c[3] for c in cli):.2e} m "
        f"({len(cli)} runs: {', '.join(f'{c[0]}/{c[1]} {c[2]}' for c in cli)})",
        "",
    ]
    shown = ("calibrated --model, held out", "uncalibrated", "calibrated --model, in sample")
    for label in shown + (("--gyro-bias-from --model, calibrated, held out",) if args.gyrocal else ()):
        lines += [f"### issue 27 targets: {label}", md(main_table(longs[label])), ""]
    for subset, name in (("NoDist", "NoDist medians (9 per motion)"), ("all", "all recordings")):
        lines += [f"### verdicts (margin) of every configuration, {name}", md(verdict_matrix(longs, subset)), ""]
    for subset in ("NoDist", "all"):
        lines.append(f"targets met ({subset}): " + "; ".join(f"{label} {count_met(lg, subset)}" for label, lg in longs.items()))
    lines.append("")
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
