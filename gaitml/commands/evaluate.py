"""`gaitml evaluate CONFIG [--out RUN_DIR] [--data DIR] [--json]`: run a config and write its run folder."""

from __future__ import annotations

from pathlib import Path

from gaitml.commands._util import emit_json, log


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
