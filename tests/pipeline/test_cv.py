"""Metrics known answers, splitters, and the cross-validation runner."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import ConfigError
from gaitml.evaluation.classification import classification_metrics, confusion_table
from gaitml.evaluation.cv import check_groups, cross_validate, make_splits
from gaitml.models import build_window_dataset
from tests.models.synth import synth_set


def test_metrics_known_answer():
    t = ["a", "a", "a", "b", "b", "c"]
    p = ["a", "a", "b", "b", "c", "c"]
    m = classification_metrics(t, p, labels=["a", "b", "c"])
    assert m["accuracy"] == pytest.approx(4 / 6)
    assert m["confusion"] == [[2, 1, 0], [0, 1, 1], [0, 0, 1]]
    pa, ra = 1.0, 2 / 3
    pb, rb = 1 / 2, 1 / 2
    pc, rc = 1 / 2, 1.0
    f = [2 * p_ * r_ / (p_ + r_) for p_, r_ in ((pa, ra), (pb, rb), (pc, rc))]
    assert m["per_class"]["a"]["precision"] == pytest.approx(pa) and m["per_class"]["a"]["recall"] == pytest.approx(ra)
    assert m["per_class"]["c"]["support"] == 1
    assert m["macro_f1"] == pytest.approx(np.mean(f))
    assert list(confusion_table(m).index) == ["a", "b", "c"]


def test_metrics_absent_class_and_perfect():
    m = classification_metrics(["a", "b"], ["a", "b"], labels=["a", "b", "z"])
    assert m["accuracy"] == 1.0 and m["macro_f1"] == 1.0  # z has no support: not averaged
    assert m["per_class"]["z"] == {"precision": 0.0, "recall": 0.0, "f1": 0.0, "support": 0}


G = np.array(["s1"] * 3 + ["s2"] * 2 + ["s3"] * 4)


def test_train_one_test_rest_trains_on_one_group():
    splits = make_splits("train-one-test-rest", G)
    assert len(splits) == 3
    for tr, te in splits:
        assert len(set(G[tr])) == 1 and set(G[tr]).isdisjoint(set(G[te]))
        assert len(tr) + len(te) == len(G)


def test_leave_one_group_out_and_group_kfold():
    logo = make_splits("leave-one-group-out", G)
    assert sorted(tuple(sorted(set(G[te]))) for _, te in logo) == [("s1",), ("s2",), ("s3",)]
    gk = make_splits("group-kfold", G, n_splits=2)
    assert len(gk) == 2
    for tr, te in gk:
        assert set(G[tr]).isdisjoint(set(G[te]))


@pytest.mark.parametrize(
    ("scheme", "groups", "n", "pattern"),
    [
        ("leave-one-group-out", ["a"] * 5, 5, "needs at least 2 groups"),
        ("train-one-test-rest", ["a"] * 5, 5, "needs at least 2 groups"),
        ("group-kfold", ["a", "b", "c"], 5, "n_splits = 5 needs at least 5 groups"),
        ("kfold", ["a", "b"], 2, "allowed: train-one-test-rest"),
    ],
)
def test_too_few_groups(scheme, groups, n, pattern):
    with pytest.raises(ConfigError, match=pattern):
        check_groups(scheme, groups, n)


def test_cross_validate_outputs():
    recs = synth_set(3, seconds_per_mode=8.0)
    ds = build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5)
    res = cross_validate(ds, "linear-ovo-svm", scheme="train-one-test-rest", progress=False, labels=["walk", "run", "side_left"])
    assert len(res.folds) == 3 and (res.folds["n_train"] + res.folds["n_test"] == len(ds)).all()
    assert len(res.predictions) == 2 * len(ds)  # every window tested by the two folds that did not train on it
    assert res.before["labels"] == ["walk", "run", "side_left"]
    s = res.summary()
    assert s["n_folds"] == 3 and 0 <= s["accuracy_before"] <= 1
    assert res.after["n"] == res.before["n"]


def test_train_groups_are_filled_for_every_scheme():
    recs = synth_set(3, seconds_per_mode=8.0)
    groups = [r.meta["subject"] for r in recs]
    ds = build_window_dataset(recs, groups=groups, length_s=1.5, overlap=0.5)
    res = cross_validate(ds, "linear-ovo-svm", scheme="leave-one-group-out", progress=False)
    for _, row in res.folds.iterrows():
        train = set(row["train_groups"].split(";"))
        assert train == set(groups) - {row["test_groups"]}, row


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.sampled_from("abc"), st.integers(0, 2)), min_size=1, max_size=40), st.randoms(use_true_random=False))
def test_correction_per_recording_ignores_input_order(items, rnd):
    from gaitml.evaluation.classification import correct_by_recording
    from gaitml.postprocess import adjacent_window_correction

    pred = np.array([p for p, _ in items])
    rec = np.array([r for _, r in items])
    t = np.arange(len(items), dtype=float)
    base = correct_by_recording(pred, rec, t)
    for r in set(rec):  # equals the sequence rule applied to each recording alone
        m = rec == r
        assert list(base[m]) == list(adjacent_window_correction(pred[m]))
    perm = list(range(len(items)))
    rnd.shuffle(perm)
    perm = np.array(perm)
    shuffled = correct_by_recording(pred[perm], rec[perm], t[perm])
    assert list(shuffled) == list(base[perm])
