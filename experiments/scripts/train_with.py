"""Train a config's model with some settings overridden (a variant to measure beside the shipped one).

``python -m experiments.scripts.train_with CONFIG OUT_DIR [--set KEY=VALUE ...] [--no-cv]`` from the repository root.

``--set`` takes a dotted config key and a TOML value (``features.acc_range_ms2=19.6``,
``train.cross_validate=false``); the config is validated again with the overrides
(:meth:`gaitml.pipeline.config.ExperimentConfig.with_values`), then trained by
:func:`gaitml.pipeline.train_config`, the same path as ``gaitml train``.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path


def parse_set(items: list[str]) -> dict:
    """``KEY=VALUE`` strings as a dict of dotted keys and TOML-parsed values."""
    out = {}
    for s in items:
        key, sep, value = s.partition("=")
        if not sep or not key.strip():
            raise SystemExit(f"--set {s!r}: give KEY=VALUE, e.g. features.acc_range_ms2=19.6")
        out[key.strip()] = tomllib.loads(f"v = {value.strip()}")["v"]
    return out


def main(argv=None) -> int:
    from gaitml.pipeline import train_config
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", type=Path)
    ap.add_argument("out", type=Path)
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--no-cv", action="store_true", help="skip the cross-validation (train.cross_validate = false)")
    a = ap.parse_args(argv)
    over = parse_set(a.sets)
    if a.no_cv:
        over["train.cross_validate"] = False
    cfg = load_config(a.config)
    if over:
        cfg = cfg.with_values(over)
    model = train_config(cfg, out_dir=a.out, progress=True)
    print(f"[train_with] {a.out}: {model.info['training_data']['n_windows']} windows; overrides {over}", file=sys.stderr)
    for n in model.info["training_data"]["notes"]:
        print(f"[train_with]   {n}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
