"""`gaitml evaluate CONFIG [--out RUN_DIR] [--data DIR] [--json]`: run a config and write its run folder."""

from __future__ import annotations

import argparse
from pathlib import Path

from gaitml.commands._util import emit_json, log

#: The command's one-line description in ``gaitml --help``.
HELP = "run an experiment config (cross-validation, or the step-detector evaluation)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml evaluate`` on its parser ``p``."""
    p.add_argument("config", metavar="CONFIG")
    p.add_argument("--out", metavar="RUN_DIR")
    p.add_argument("--data", metavar="DIR", help="read the data from DIR instead of the config's data.path")
    p.add_argument("--json", action="store_true")
    p.add_argument("--backend", default="joblib", help="joblib | dask")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address (with --backend dask)")


def run(args) -> int:
    from gaitml.parallel import parallel_backend
    from gaitml.pipeline import evaluate_config, load_config

    data = getattr(args, "data", None)
    cfg = load_config(args.config, check_paths=data is None)
    if data is not None:
        cfg = cfg.with_data_path(data)
    if cfg.task == "steps":
        result = evaluate_config(cfg, out_dir=args.out)
        if args.json:
            emit_json(result)
        else:
            print(Path(result["run_dir"], "report.md").read_text(), end="")
            log(f"gaitml evaluate {cfg.name}: {len(cfg['steps']['detectors'])} step detectors; run folder {result['run_dir']}")
        return 0
    backend = getattr(args, "backend", "joblib") or "joblib"
    with parallel_backend(backend, getattr(args, "scheduler", None)) as info:
        n_jobs = -1 if info["backend"] == "dask" else None
        result = evaluate_config(cfg, out_dir=args.out, n_jobs=n_jobs)
    result["backend"] = info
    if args.json:
        emit_json(result)
    else:
        log(
            f"gaitml evaluate {cfg.name}: accuracy {result['accuracy_before_correction']:.4f} before / "
            f"{result['accuracy_after_correction']:.4f} after correction, macro-F1 {result['macro_f1']:.4f} "
            f"({result['scheme']}, {len(result['folds'])} folds, {result['n_windows']} windows)"
        )
        if "sweep" in result:
            for row in result["sweep"]:
                keys = [k for k in cfg.sweep]
                log("  " + ", ".join(f"{k}={row[k]}" for k in keys) + f": {row['accuracy_before']:.4f} / {row['accuracy_after']:.4f}")
        log(f"gaitml evaluate: run folder {result['run_dir']}")
    return 0
