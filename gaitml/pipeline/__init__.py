"""Experiment configs (TOML), cross-validation runs, sweeps, training and run reports.

- :func:`load_config` / :func:`parse_config`: validated :class:`ExperimentConfig` (one
  schema for every config; ``task = "classification"`` or ``"steps"``);
- :func:`evaluate_config`: cross-validate (every ``[sweep]`` point), or for a steps
  config evaluate the step detectors on the real recordings
  (:mod:`~gaitml.pipeline.steps_real`), and write the run folder;
- :func:`train_config`: fit on all windows and save a model artifact;
- :mod:`~gaitml.pipeline.pdr_routes`: PDR variants on simulated routes (the demo and
  ``experiments/scripts/pdr_report.py``).
"""

from gaitml.pipeline.config import ExperimentConfig, load_config, parse_config, sweep_grid
from gaitml.pipeline.runner import build_dataset, evaluate_config, prepare_data, train_config

__all__ = [
    "ExperimentConfig",
    "build_dataset",
    "evaluate_config",
    "load_config",
    "parse_config",
    "prepare_data",
    "sweep_grid",
    "train_config",
]
