"""`gaitml train CONFIG [--out MODEL_DIR]`: fit the config's model on all its windows and save it."""

from __future__ import annotations

import argparse

from gaitml.commands._util import log

#: The command's one-line description in ``gaitml --help``.
HELP = "train a model from an experiment config"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml train`` on its parser ``p``."""
    p.add_argument("config", metavar="CONFIG")
    p.add_argument("--out", metavar="MODEL_DIR")


def run(args) -> int:
    from gaitml.pipeline import load_config, train_config

    cfg = load_config(args.config)
    model = train_config(cfg, out_dir=args.out)
    cv = model.info.get("cv_scores") or {}
    extra = (
        f"; CV ({cv.get('scheme')}) accuracy {cv['accuracy_before']:.4f} before / {cv['accuracy_after']:.4f} after correction" if cv else ""
    )
    log(f"gaitml train: {model.kind} on {model.info['training_data']['n_windows']} windows, labels {', '.join(model.labels)}{extra}")
    log(f"gaitml train: model written to {model.path}")
    return 0
