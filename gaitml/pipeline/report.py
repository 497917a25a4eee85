"""Run folders: resolved config, metrics JSON, CSV tables, markdown report, PNG plots.

Everything is written into a temporary folder that replaces ``run_dir`` only
when complete (:func:`gaitml.io.atomic_dir`), so a failed run leaves nothing
half-written. Plots use matplotlib's Agg backend (no display needed).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["write_run", "plot_confusion", "plot_sweep"]


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def plot_confusion(path: Path, labels: list[str], before: list, after: list, title: str) -> None:
    """Two row-normalised confusion matrices (before / after the correction) side by side."""
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8), constrained_layout=True)
    for ax, cm, sub in zip(axes, (before, after), ("before correction", "after correction"), strict=True):
        m = np.asarray(cm, dtype=float)
        with np.errstate(invalid="ignore", divide="ignore"):
            norm = np.where(m.sum(axis=1, keepdims=True) > 0, m / m.sum(axis=1, keepdims=True), 0.0)
        ax.imshow(norm, vmin=0, vmax=1, cmap="Blues")
        acc = np.trace(m) / m.sum() if m.sum() else float("nan")
        ax.set_title(f"{sub} (accuracy {acc:.3f})")
        ax.set_xticks(range(len(labels)), labels, rotation=40, ha="right")
        ax.set_yticks(range(len(labels)), labels)
        ax.set_xlabel("predicted")
        ax.set_ylabel("true")
        for i in range(len(labels)):
            for j in range(len(labels)):
                if m[i, j]:
                    ax.text(j, i, f"{int(m[i, j])}", ha="center", va="center", fontsize=7, color="white" if norm[i, j] > 0.6 else "black")
    fig.suptitle(title)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_sweep(path: Path, rows: list[dict], keys: list[str], title: str) -> None:
    """Accuracy (before/after correction) per sweep point; numeric single keys on a numeric axis."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
    df = pd.DataFrame(rows)
    numeric = len(keys) == 1 and pd.api.types.is_numeric_dtype(df[keys[0]])
    x = df[keys[0]].to_numpy(dtype=float) if numeric else np.arange(len(df))
    ax.plot(x, df["accuracy_before"], "o-", label="before correction")
    ax.plot(x, df["accuracy_after"], "s--", label="after correction")
    if "fold_accuracy_std_before" in df:
        ax.errorbar(
            x,
            df["fold_accuracy_mean_before"],
            yerr=df["fold_accuracy_std_before"],
            fmt="none",
            ecolor="grey",
            capsize=3,
            label="fold mean +/- std (before)",
        )
    if numeric:
        ax.set_xlabel(keys[0])
    else:
        ax.set_xticks(x, [", ".join(str(r[k]) for k in keys) for r in rows], rotation=30, ha="right")
        ax.set_xlabel(" / ".join(keys))
    ax.set_ylabel("accuracy")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(title)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.4f}"
    return str(v)


def _md_table(df: pd.DataFrame) -> str:
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, r in df.iterrows():
        lines.append("| " + " | ".join(_fmt(r[c]) for c in cols) + " |")
    return "\n".join(lines)


def _point_files(folder: Path, cfg, point: dict, title: str) -> dict:
    res, ds = point["cv"], point["dataset"]
    folder.mkdir(parents=True, exist_ok=True)
    res.folds.to_csv(folder / "folds.csv", index=False)
    per_class = pd.DataFrame(
        [
            {
                "label": lab,
                **{f"{k}_before": v for k, v in res.before["per_class"][lab].items()},
                **{f"{k}_after": v for k, v in res.after["per_class"][lab].items() if k != "support"},
            }
            for lab in res.labels
        ]
    )
    per_class.to_csv(folder / "per_class.csv", index=False)
    from gaitml.evaluation.classification import confusion_table

    confusion_table(res.before).to_csv(folder / "confusion_before.csv")
    confusion_table(res.after).to_csv(folder / "confusion_after.csv")
    pred = res.predictions.copy()
    scored = point.get("test_dataset", ds)  # the windows the folds were scored on (copies are not scored)
    pred["recording"] = [scored.recording_names[i] for i in pred["recording"]]
    pred.to_csv(folder / "predictions.csv", index=False)
    plot_confusion(folder / "confusion.png", res.labels, res.before["confusion"], res.after["confusion"], title)
    return {"per_class": per_class}


def write_run(run_dir: str | Path, cfg, result: dict, points: list[dict], rows: list[dict]) -> Path:
    """Write the run folder of :func:`gaitml.pipeline.runner.evaluate_config` atomically."""
    from gaitml.io import atomic_dir
    from gaitml.io._atomic import _json_default

    run_dir = Path(run_dir)
    with atomic_dir(run_dir) as tmp:
        if cfg.source is not None and cfg.source.exists():
            shutil.copyfile(cfg.source, tmp / "config.toml")
        (tmp / "config.resolved.json").write_text(json.dumps(cfg.resolved(), indent=2, default=_json_default) + "\n")
        (tmp / "metrics.json").write_text(json.dumps(result, indent=2, default=_json_default) + "\n")
        multi = len(points) > 1
        best_point = result.get("best", {})
        for i, p in enumerate(points):
            sub = tmp / f"point-{i:02d}" if multi else tmp
            title = f"{cfg.name}: {', '.join(f'{k}={v}' for k, v in p['point'].items())}" if p["point"] else cfg.name
            _point_files(sub, cfg, p, title)
            if multi:
                s = p["cv"].summary()
                (sub / "metrics.json").write_text(
                    json.dumps(
                        {"point": p["point"], **s, "before": p["cv"].before, "after": p["cv"].after}, indent=2, default=_json_default
                    )
                    + "\n"
                )
        if multi:
            best_i = next(i for i, p in enumerate(points) if p["point"] == best_point)
            for f in ("confusion.png", "folds.csv", "per_class.csv", "confusion_before.csv", "confusion_after.csv"):
                shutil.copyfile(tmp / f"point-{best_i:02d}" / f, tmp / f)
        if cfg.sweep:
            pd.DataFrame(rows).to_csv(tmp / "sweep.csv", index=False)
            plot_sweep(tmp / "sweep.png", rows, list(cfg.sweep), f"{cfg.name}: {cfg['cv']['scheme']}")
        (tmp / "report.md").write_text(_report_md(cfg, result, rows, points))
    return run_dir


def _report_md(cfg, result: dict, rows: list[dict], points: list[dict]) -> str:
    v = cfg.values
    lines = [
        f"# {cfg.name}",
        "",
        v.get("description") or "",
        "",
        f"- data: {v['data']['source']}"
        + (f" `{cfg.data_path}`" if cfg.data_path else "")
        + f"; label `{v['data']['label']}`, group `{v['data']['group']}`, "
        f"{result['n_recordings']} recordings, {result['n_groups']} groups, resampled to {v['data']['resample_hz']:g} Hz",
        (
            f"- windows: {result['window_length_s']} s, overlap {v['windows']['overlap']}, "
            if result.get("window_by", "time") == "time"
            else f"- windows: one per detected {result['window_by'].rstrip('s')} ({result['window_detector']}), "
        )
        + f"min_label_fraction {v['windows']['min_label_fraction']}: "
        f"{result['n_windows']} kept of {result['n_windows_total']} ({result['n_dropped_label_fraction']} below the label fraction, "
        f"{result['n_dropped_other_labels']} with labels not kept {result['dropped_labels'] or ''})",
        f"- model: `{result['model_kind']}` {v['model']['params'] or ''}; features `{result['feature_set']}`",
        f"- cross-validation: `{v['cv']['scheme']}`, {len(result['folds'])} folds, seed {cfg.seed}",
        f"- adjacent-window correction (paper 003 sec. 3.4) per recording in time order over the kept windows: "
        f"{'applied to the headline' if result['correction_applied'] else 'reported, not applied to the headline'}",
        "",
    ]
    for n in result.get("notes", []):
        lines.append(f"- note: {n}")
    if result.get("skipped_recordings"):
        lines.append(f"- skipped (shorter than one window): {', '.join(result['skipped_recordings'])}")
    lines += [
        "",
        "## Result" + (" (best sweep point: " + ", ".join(f"{k}={x}" for k, x in result["best"].items()) + ")" if cfg.sweep else ""),
        "",
    ]
    lines.append("| | accuracy | macro-F1 |\n|---|---|---|")
    lines.append(f"| before correction | {result['accuracy_before_correction']:.4f} | {result['macro_f1_before_correction']:.4f} |")
    lines.append(f"| after correction | {result['accuracy_after_correction']:.4f} | {result['macro_f1_after_correction']:.4f} |")
    lines += ["", "Pooled over all test predictions of all folds.", ""]
    if cfg.sweep:
        lines += ["## Sweep", "", _md_table(pd.DataFrame(rows)), "", "![sweep](sweep.png)", ""]
    lines += ["## Per class", "", _md_table(pd.DataFrame([{"label": k, **x} for k, x in result["per_class"].items()])), ""]
    lines += ["## Folds", "", _md_table(pd.DataFrame(result["folds"])), "", "![confusion](confusion.png)", ""]
    return "\n".join(lines) + "\n"
