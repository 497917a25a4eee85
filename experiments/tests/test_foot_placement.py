"""The lab script of the foot-placement rule (experiments/scripts/foot_placement.py) on small simulated inputs."""

from __future__ import annotations

import numpy as np

from experiments.scripts import foot_placement as fp
from gaitml.simulate import simulate_dataset
from gaitml.simulate.foot import simulate_foot


def test_the_foot_is_read_at_the_model_rate_with_the_unit_check():
    rec = fp.foot_at_model_rate(simulate_foot(modes=("run",), duration_s=20.0, sampling_rate_hz=100.0, seed=111))
    assert rec.sampling_rate_hz == fp.FS_HZ and rec.n_samples == 1000
    walk = fp.foot_at_model_rate(simulate_foot(modes=("walk",), duration_s=30.0, sampling_rate_hz=100.0, seed=1))
    n, k = fp.rule_counts([walk])
    assert n > 30 and k / n >= 0.7


def test_the_selection_grid_marks_the_shipped_values_once_and_counts_every_position():
    phones = simulate_dataset(n_subjects=1, duration_s=30.0, pose="flat", seed=3, positions=("hand-flat",))
    foot = [fp.foot_at_model_rate(simulate_foot(modes=("walk",), duration_s=30.0, sampling_rate_hz=100.0, seed=2))]
    sel = {p: phones for p in fp.PHONE_POSITIONS} | {"foot (walk)": foot, "foot (run)": foot}
    gyro, acc = fp.selection_tables(sel)
    for t, grid in ((gyro, fp.GYRO_GRID), (acc, fp.ACC_GRID)):
        assert len(t) == int(np.prod([len(v) for v in grid.values()]))
        assert (t["chosen"] != "").sum() == 1
        assert t["foot (walk)"].between(0, 1).all() and (t["worst phone position"] <= 1).all()
    chosen = gyro[gyro["chosen"] != ""].iloc[0]
    assert chosen["foot (walk)"] > chosen["worst phone position"]
    assert fp.md(gyro.head(2)).count("\n") == 3
