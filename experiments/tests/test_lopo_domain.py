"""The leave-one-position-out study's windows (experiments/scripts/lopo_domain.py): a carrying position left out of
training is flagged by the domain check fitted on the others."""

from __future__ import annotations

import numpy as np

from gaitml.models.domain import (
    fit_domain,
)


def _position_windows(recs):
    from experiments.scripts.lopo_domain import window_descriptors
    from gaitml.models import build_window_dataset

    ds = build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5, feature_set="all52+gyro")
    grav, dyn, pos = window_descriptors(recs, ds)
    ri = np.asarray(ds.recording_index)
    return ds.inputs("features"), grav, dyn, np.asarray(ds.y), np.asarray(ds.groups), pos.astype(str), ri


def test_a_carrying_position_left_out_of_training_is_flagged():
    """Leave one position out, small: trained on hand, pocket and bag; a swinging hand must be flagged."""
    from gaitml.features import feature_names
    from gaitml.simulate import simulate_dataset

    trained = ("hand-flat", "front-pocket", "bag")
    train = simulate_dataset(n_subjects=6, duration_s=50.0, pose="mixed", seed=1000, positions=trained)
    test = simulate_dataset(n_subjects=2, duration_s=50.0, pose="mixed", seed=2024, positions=(*trained, "swinging-hand"))
    X, g, q, y, grp, pos, ri = _position_windows(train)
    dom = fit_domain(
        X,
        y,
        grp,
        g,
        feature_names=feature_names("all52+gyro"),
        feature_set="all52+gyro",
        frame="phone",
        positions=pos,
        dynamics=q,
        sequence=ri,
    )
    Xt, gt, qt, _, _, post, rit = _position_windows(test)
    flagged = np.zeros(len(Xt), dtype=bool)
    for r in np.unique(rit):
        rows = np.flatnonzero(rit == r)
        flagged[rows] = ~dom.check(Xt[rows], gt[rows], qt[rows])["in_domain"]
    left_out = post == "swinging-hand"
    # the target is 80 % (experiments/reports/model-domain.md gives the full run's figure); this small run's floor 78 %
    assert flagged[left_out].mean() >= 0.78
    assert flagged[~left_out].mean() <= 0.1
