"""The dynamics part on a grid of windows: the check computes every ``every``-th window's descriptors.

Each piece is checked against a plain loop: the running median (bit for bit against
``np.nanmedian``), the span median of the computed windows, the check on the grid
(computed windows only or every window given: the same numbers), its edge cases, the
threshold fitted on the same grid, and the descriptors computed from the windows' own
samples (a subset of windows, windows of many lengths, past the end, other rates).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from gaitml.errors import ModelError
from gaitml.models.domain import (
    DYNAMICS_EVERY,
    DYNAMICS_NAMES,
    DYNAMICS_SPAN,
    DomainModel,
    dynamics_grid_step,
    fit_domain,
    orientation_dynamics,
    running_median,
    span_medians,
)
from tests.domain.test_dynamics import _fit, _reference_dynamics, _walk


def _nanmedian(values) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN spans: NaN
        return float(np.nanmedian(np.asarray(values, dtype=float))) if len(values) else np.nan


def _sequences(n: int, rng) -> np.ndarray:
    """Three recordings whose rows are interleaved (time order kept within each)."""
    return rng.choice(np.array(["r1", "r2", "r3"]), n)


def _distances(n: int, rng) -> np.ndarray:
    d = rng.random(n) * 5
    d[rng.random(n) < 0.1] = np.nan
    d[rng.random(n) < 0.05] = np.inf  # non-finite descriptors give inf distances
    return d


def test_running_median_is_nanmedian_of_each_span_bit_for_bit():
    rng = np.random.default_rng(11)
    d, seq = _distances(120, rng), _sequences(120, rng)
    d[:7] = np.nan  # spans of NaN only
    for span in (1, 2, 3, 5, 10, 20, 25):
        got = running_median(d, span, seq)
        ref = []
        for i in range(len(d)):
            own = np.flatnonzero(seq[: i + 1] == seq[i])[-span:]
            ref.append(_nanmedian(d[own]))
        np.testing.assert_array_equal(got, ref, err_msg=f"span {span}")
    np.testing.assert_array_equal(running_median(d[:30], 4), [_nanmedian(d[max(0, i - 3) : i + 1]) for i in range(30)])
    assert running_median(np.zeros(0), 5).shape == (0,)


def test_span_medians_are_the_median_of_the_computed_windows_in_each_span():
    rng = np.random.default_rng(12)
    d, seq = _distances(150, rng), _sequences(150, rng)
    for span, every in ((20, 1), (20, 2), (20, 4), (20, 5), (6, 3), (1, 1), (2, 2)):
        for phase in range(every):
            got = span_medians(d, span, every, seq, phase)
            ref = []
            for i in range(len(d)):
                own = np.flatnonzero(seq[: i + 1] == seq[i])  # this recording's windows up to this one
                rank = len(own) - 1
                ref.append(_nanmedian([d[own[j]] for j in range(max(0, rank - span + 1), rank + 1) if j % every == phase]))
            np.testing.assert_array_equal(got, ref, err_msg=f"span {span}, every {every}, phase {phase}")
    np.testing.assert_array_equal(span_medians(d, 20, 1, seq), running_median(d, 20, seq))
    np.testing.assert_array_equal(span_medians(d[:40], 20, 2), span_medians(d[:40], 20, 2, np.zeros(40)))
    for bad in (0, 3):
        with pytest.raises(ModelError, match="divide"):
            span_medians(d, 20, bad)


def test_grid_step_divides_the_span():
    assert DYNAMICS_EVERY == dynamics_grid_step(DYNAMICS_SPAN) == 2
    assert [dynamics_grid_step(s) for s in (1, 2, 3, 5, 7, 9, 10)] == [1, 2, 1, 1, 1, 1, 2]  # span shorter than the step: 1 or 2


def _grid_record(every: int, span: int = DYNAMICS_SPAN):
    """The record of ``_fit`` with another grid step / span written into its JSON (what an older or other record says)."""
    dom, Q, _, _ = _fit()
    info, arrays = dom.to_json(), dom.to_arrays()
    info["dynamics"] = {**info["dynamics"], "every": every, "span": span}
    if every is None:
        del info["dynamics"]["every"]
    return DomainModel.from_json(info, arrays), Q


def _plain(dom, Q, n):
    """Window i: the median of the dynamics distances of windows 0, every, ... among its last span windows."""
    span, every = dom.dynamics["span"], dom.dynamics_every
    d = dict(zip(range(0, n, every), dom.dynamics_distances(Q[:n:every]), strict=True))  # the computed windows' distances
    return np.array([np.median([d[j] for j in range(max(0, i - span + 1), i + 1) if j % every == 0]) for i in range(n)])


@pytest.mark.parametrize("every, span", [(2, 20), (4, 20), (5, 20), (1, 20), (3, 3), (2, 2), (1, 1)])
def test_the_check_on_the_grid_equals_a_plain_loop_for_any_number_of_windows(every, span):
    dom, Q = _grid_record(every, span)
    assert dom.dynamics_every == every
    for n in (1, 2, every - 1, every, every + 1, 23, 60):
        if n < 1:
            continue
        X, grav = np.zeros((n, 4)), np.tile([0.0, 0.0, 1.0], (n, 1))
        q = Q[:n] + np.linspace(0.0, 6.0, n)[:, None]  # drifting away from the training data
        rows = dom.dynamics_rows(n)
        np.testing.assert_array_equal(rows, np.arange(0, n, every))
        res = dom.check(X, grav, q[rows])
        np.testing.assert_array_equal(res["dynamics_distance"], _plain(dom, q, n))
        np.testing.assert_array_equal(
            res["in_domain"], (dom.distances(X) <= dom.distance_threshold) & (_plain(dom, q, n) <= dom.dynamics["threshold"])
        )
        full = dom.check(X, grav, q)  # every window given: the computed ones are read
        for k in res:
            np.testing.assert_array_equal(full[k], res[k])
    with pytest.raises(ModelError, match="dynamics rows"):
        dom.check(np.zeros((10, 4)), np.tile([0.0, 0.0, 1.0], (10, 1)), Q[:7])


def test_nan_descriptors_count_as_far_where_computed_and_are_not_read_elsewhere():
    dom, Q = _grid_record(2)
    n = 30
    X, grav = np.zeros((n, 4)), np.tile([0.0, 0.0, 1.0], (n, 1))
    base = dom.check(X, grav, Q[:n])
    q = Q[:n].copy()
    q[5] = np.nan  # not a computed window: not read
    np.testing.assert_array_equal(dom.check(X, grav, q)["dynamics_distance"], base["dynamics_distance"])
    q[[4, 6, 8]] = np.nan  # computed windows: distance inf, the median of spans holding 3 of them rises
    res = dom.check(X, grav, q)
    np.testing.assert_array_equal(res["dynamics_distance"], _plain(dom, q, n))
    assert np.isinf(res["dynamics_distance"][6:8]).all() and not res["in_domain"][6:8].any()
    assert (res["dynamics_distance"] >= base["dynamics_distance"]).all()


def test_records_without_a_grid_step_check_every_window_as_they_were_fitted():
    old, Q = _grid_record(None)
    assert old.dynamics["every"] == old.dynamics_every == 1
    n = 40
    res = old.check(np.zeros((n, 4)), np.tile([0.0, 0.0, 1.0], (n, 1)), Q[:n] + 2.0)
    np.testing.assert_array_equal(res["dynamics_distance"], running_median(old.dynamics_distances(Q[:n] + 2.0), DYNAMICS_SPAN))
    assert DomainModel.from_json(old.to_json(), old.to_arrays()).dynamics["every"] == 1
    dom, _ = _grid_record(2)
    info = dom.to_json()
    assert info["dynamics"]["every"] == 2
    info["dynamics"]["every"] = 3  # does not divide the span
    with pytest.raises(ModelError, match="grid step"):
        DomainModel.from_json(info, dom.to_arrays())


@pytest.mark.parametrize("every, span", [(1, None), (2, None), (4, None), (2, 10), (None, 40), (None, 30), (4, 60)])
def test_the_threshold_is_fitted_on_the_grid_the_check_uses(every, span):
    """One training group: the threshold is the quantile of the in-sample span medians, pooled over the grid's phases.

    ``dynamics_span`` (None: :data:`DYNAMICS_SPAN`) is the span recorded and fitted; the grid
    step defaults to :func:`dynamics_grid_step` of it.
    """
    rng = np.random.default_rng(0 if every is None else every)
    q = len(DYNAMICS_NAMES)
    n = 400
    y = np.repeat(["walk", "run"], n // 2)
    Q = rng.standard_normal((n, q)) + (y == "run")[:, None] * 2.0
    Q[17] = np.nan
    seq = np.repeat(np.arange(8), 50)
    dom = fit_domain(
        rng.standard_normal((n, 3)),
        y,
        np.zeros(n),
        np.tile([0.0, 0.0, 1.0], (n, 1)),
        feature_names=list("abc"),
        feature_set="test",
        frame="gravity",
        dynamics=Q,
        sequence=seq,
        dynamics_every=every,
        dynamics_span=span,
    )
    span = DYNAMICS_SPAN if span is None else span
    every = dynamics_grid_step(span) if every is None else every
    assert dom.dynamics["every"] == every and dom.dynamics["span"] == span
    d = dom.dynamics_distances(Q)
    pooled = np.concatenate([span_medians(d, span, every, seq, p) for p in range(every)])
    assert dom.dynamics["threshold"] == dom.dynamics["threshold_in_sample"]
    np.testing.assert_allclose(dom.dynamics["threshold"], np.nanquantile(pooled, 0.99), rtol=1e-9)
    # what the check of one training recording gives is that statistic at phase 0
    rec = seq == 3
    np.testing.assert_allclose(
        dom.check(np.zeros((50, 3)), None, Q[rec])["dynamics_distance"], span_medians(d[rec], span, every), rtol=1e-12
    )


@pytest.mark.parametrize("span", [0, -3])
def test_a_dynamics_span_below_one_window_is_refused(span):
    n = 40
    with pytest.raises(ModelError, match="dynamics span must be at least 1"):
        fit_domain(
            np.zeros((n, 3)),
            np.repeat(["walk", "run"], n // 2),
            np.zeros(n),
            np.tile([0.0, 0.0, 1.0], (n, 1)),
            feature_names=list("abc"),
            feature_set="test",
            frame="gravity",
            dynamics=np.zeros((n, len(DYNAMICS_NAMES))),
            sequence=np.zeros(n),
            dynamics_span=span,
        )


# ---------------------------------------------------------------- the descriptors from the windows' own samples
def test_descriptors_of_some_windows_are_those_of_all_windows():
    acc, gyr = _walk(4, 1200)
    starts = np.arange(0, 1200 - 75 + 1, 37)
    every = orientation_dynamics(acc, gyr, starts, starts + 75, 50.0)
    for rows in (np.arange(0, len(starts), 2), np.arange(1, len(starts), 3), np.array([5]), np.array([0, 1, 2, 9, 30])):
        np.testing.assert_allclose(
            orientation_dynamics(acc, gyr, starts[rows], starts[rows] + 75, 50.0), every[rows], rtol=1e-12, atol=1e-12
        )
    # a C- or Fortran-ordered signal, evenly spaced (strided view) or not (gathered): the same
    f_acc, f_gyr = np.asfortranarray(acc), np.asfortranarray(gyr)
    np.testing.assert_allclose(orientation_dynamics(f_acc, f_gyr, starts, starts + 75, 50.0), every, rtol=1e-12, atol=1e-12)
    assert orientation_dynamics(acc, gyr, [], [], 50.0).shape == (0, len(DYNAMICS_NAMES))


@pytest.mark.parametrize("fs", [50.0, 100.0, 20.0])
def test_descriptors_of_windows_of_many_lengths_match_the_loop(fs):
    step = max(1, int(fs // 25.0))
    chunk = max(1, int(round(0.3 * fs / step)))
    n = int(24 * fs)
    t = np.arange(n) / fs
    rng = np.random.default_rng(int(fs))
    acc = np.column_stack([np.sin(2 * np.pi * 1.7 * t), 0.5 * np.cos(2 * np.pi * 0.8 * t), 9.8 + np.sin(2 * np.pi * 1.7 * t + 0.4)])
    acc = acc + 0.2 * rng.standard_normal(acc.shape)
    gyr = np.column_stack([0.5 * np.sin(2 * np.pi * 0.8 * t), 0.3 * np.cos(t), 0.1 * t / t[-1]]) + 0.05 * rng.standard_normal(acc.shape)
    starts = np.sort(rng.integers(0, n - 10, 40))
    ends = starts + rng.integers(1, int(4 * fs), 40)  # from one sample (NaN) to 4 s, some past the end
    got = orientation_dynamics(acc, gyr, starts, ends, fs)
    for i, (s, e) in enumerate(zip(starts, ends, strict=True)):
        keep = np.arange(s, min(e, n))
        keep = keep[keep % step == 0]
        if len(keep) < 2:
            assert np.isnan(got[i]).all()
            continue
        ref = _reference_dynamics(acc[keep], gyr[keep], chunk)
        angles = [0, 6]  # near 0 deg the arccos amplifies rounding (a window of one chunk: its own direction)
        other = [c for c in range(len(DYNAMICS_NAMES)) if c not in angles + [7]]
        np.testing.assert_allclose(got[i, angles], ref[angles], rtol=1e-7, atol=1e-5)
        np.testing.assert_allclose(got[i, other], ref[other], rtol=1e-7, atol=1e-9)
        if len(keep) > 3:  # skewness of 2-3 samples is rounding noise over rounding noise
            np.testing.assert_allclose(got[i, 7], ref[7], rtol=1e-6, atol=1e-6)


def test_descriptors_in_batches_equal_one_block(monkeypatch):
    import gaitml.models.domain._descriptors as dm

    acc, gyr = _walk(6, 900)
    starts = np.arange(0, 900 - 75 + 1, 37)
    ends = starts + 75
    ends[4] = starts[4] + 1  # too short: NaN, whatever the batch
    whole = orientation_dynamics(acc, gyr, starts, ends, 50.0)
    monkeypatch.setattr(dm, "_DYNAMICS_BATCH", 3)
    np.testing.assert_allclose(orientation_dynamics(acc, gyr, starts, ends, 50.0), whole, rtol=1e-12, atol=1e-12)
    assert np.isnan(whole[4]).all() and np.isfinite(np.delete(whole, 4, axis=0)).all()
