"""experiments/scripts/compare_runs.py: one row per sweep point of a run folder."""

from __future__ import annotations

from experiments.scripts.compare_runs import compare_runs
from gaitml.pipeline import evaluate_config, parse_config


def test_compare_runs_lists_every_sweep_point_of_a_run(tmp_path):
    raw = {
        "name": "tiny-linear-ovo-svm",
        "seed": 1,
        "data": {"source": "simulated", "simulated": {"subjects": 3, "duration_s": 60.0, "modes": ["walk", "run", "side_left"]}},
        "model": {"kind": "linear-ovo-svm", "params": {}},
        "sweep": {"windows.length_s": [0.5, 1.5]},
    }
    evaluate_config(parse_config(raw), out_dir=tmp_path / "run", progress=False)
    table = compare_runs([tmp_path / "run"])
    assert list(table["window_s"]) == [0.5, 1.5] and table["acc_after"].between(0, 1).all()
