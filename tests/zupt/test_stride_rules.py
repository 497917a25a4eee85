"""Interval rules that follow the local stride period (issue 30): one stance per stride, at any cadence."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import InputError
from gaitml.signal import magnitude
from gaitml.simulate.foot import simulate_foot
from gaitml.zupt import get_detector, local_stride_period, mask_runs, stride_scaled_stances
from gaitml.zupt.magnitude import magnitude_zupts

FS = 100.0


def _recall_and_spurious(rec, mask):
    s, e = mask_runs(mask)
    iv = rec.reference["zupt_intervals"]
    hits = np.array([np.sum((s < b) & (e > a)) for a, b in zip(iv["start"], iv["end"], strict=True)])
    cs = np.concatenate(([0], np.cumsum(rec.reference["zupt_mask"])))
    spurious = np.sum((cs[e] - cs[s]) == 0) + np.sum(np.maximum(hits - 1, 0))
    return float(np.mean(hits > 0)), float(spurious / len(iv))


@pytest.mark.parametrize("period_s", [0.45, 0.7, 1.1, 2.0])
def test_local_stride_period_finds_the_period_not_a_multiple(period_s):
    rng = np.random.default_rng(1)
    t = np.arange(int(30 * FS)) / FS
    ph = (t / period_s) % 1.0
    # one big swing per stride plus a smaller bump (the other foot's impact) at half a stride
    x = np.exp(-(((ph - 0.7) / 0.08) ** 2)) * 8 + np.exp(-(((ph - 0.2) / 0.03) ** 2)) * 2 + rng.normal(0, 0.2, len(t))
    est = local_stride_period(x, FS)
    assert np.nanmax(np.abs(est / period_s - 1)) < 0.03


def test_local_stride_period_is_nan_without_gait():
    x = np.random.default_rng(2).normal(0, 1, int(20 * FS))
    assert np.isnan(local_stride_period(x, FS)).all()


def test_stride_scaled_stances_keeps_the_strongest_short_run_of_each_stride():
    n = 400
    m = np.zeros(n, bool)
    m[50:53] = True  # short stance, alone within half a stride: kept
    m[150:190] = True  # long stance: kept
    m[200:203] = True  # short dip 10 samples after it: dropped (the long run is stronger)
    m[300:304] = True  # short dip ...
    m[330:333] = True  # ... and a weaker one close by: the stronger kept
    t = np.full(n, 1.0)  # stride 1 s = 100 samples, neighbourhood +-50
    out = stride_scaled_stances(m, t, FS, merge_gap_samples=0, min_interval_samples=11)
    s, e = mask_runs(out)
    assert list(zip(s.tolist(), e.tolist(), strict=True)) == [(50, 53), (150, 190), (300, 304)]
    # no periodic gait: short runs are dropped, as with fixed rules
    s, _ = mask_runs(stride_scaled_stances(m, np.full(n, np.nan), FS, merge_gap_samples=0, min_interval_samples=11))
    assert s.tolist() == [150]
    # both rules 0: the per-sample mask unchanged
    assert np.array_equal(stride_scaled_stances(m, t, FS, merge_gap_samples=0, min_interval_samples=0), m)


def test_stride_scaled_merge_is_capped_at_a_quarter_stride():
    m = np.zeros(200, bool)
    m[20:60] = True
    m[74:120] = True  # gap of 14 samples
    out = stride_scaled_stances(m, np.full(200, 1.0), FS, merge_gap_samples=20, min_interval_samples=0)
    assert out[60:74].all()
    # a stride of 0.5 s (a quarter is 12.5 samples) is too short for a 14-sample gap to be inside one stance
    out = stride_scaled_stances(m, np.full(200, 0.5), FS, merge_gap_samples=20, min_interval_samples=0)
    assert not out[60:74].any()
    # gaps up to a quarter of the shortest stride searched (0.4 s: 10 samples) need no period
    called = []
    m[60:70] = True  # gap of 4 samples
    stride_scaled_stances(m, lambda: called.append(1) or np.full(200, 1.0), FS, merge_gap_samples=20, min_interval_samples=0)
    assert called == []


@pytest.mark.parametrize("bad", ["paper", None, "Stride"])
def test_interval_rules_must_be_a_known_name(bad):
    rec = simulate_foot(modes=("walk",), duration_s=6, seed=0)
    for name in ("pseudo-std", "magnitude"):
        with pytest.raises(InputError, match="interval_rules.*'stride', 'fixed', 'none'"):
            get_detector(name, interval_rules=bad).detect(rec)


def test_pseudo_std_none_is_the_per_sample_rule():
    rec = simulate_foot(modes=("run",), duration_s=20, seed=3)
    a = get_detector("pseudo-std", interval_rules="none").detect(rec)
    b = get_detector("pseudo-std", merge_gap_s=0, min_interval_s=0).detect(rec)
    assert np.array_equal(a.per_sample_zupts_, b.per_sample_zupts_)
    assert np.array_equal(a.per_sample_zupts_, a.statistic_ < a.threshold_rads_)


def test_magnitude_fixed_is_paper_004():
    rec = simulate_foot(modes=("walk",), duration_s=20, seed=4)
    det = get_detector("magnitude", interval_rules="fixed").detect(rec)
    assert np.array_equal(det.per_sample_zupts_, magnitude_zupts(magnitude(rec.acc), FS))


@pytest.mark.parametrize("name", ["pseudo-std", "magnitude", "shoe"])
def test_running_foot_stances_are_kept_by_the_default_rules(name):
    """Simulated foot running (seeds not used to write the rules): recall >= 0.95, spurious <= 0.05 per stance."""
    recalls, spurious = [], []
    for seed in (200, 201, 202):
        rec = simulate_foot(modes=("run",), duration_s=40, seed=seed)
        r, sp = _recall_and_spurious(rec, get_detector(name).detect(rec).per_sample_zupts_)
        recalls.append(r)
        spurious.append(sp)
    assert np.mean(recalls) >= 0.95
    assert np.mean(spurious) <= 0.05


def test_fixed_rules_lose_running_stances_that_the_stride_rules_keep():
    rec = simulate_foot(modes=("run",), duration_s=40, seed=205)
    fixed, _ = _recall_and_spurious(rec, get_detector("pseudo-std", interval_rules="fixed").detect(rec).per_sample_zupts_)
    stride, sp = _recall_and_spurious(rec, get_detector("pseudo-std").detect(rec).per_sample_zupts_)
    per_sample, sp0 = _recall_and_spurious(rec, get_detector("pseudo-std", interval_rules="none").detect(rec).per_sample_zupts_)
    assert stride >= per_sample - 0.03 and stride > fixed + 0.3
    assert sp < sp0


def test_walking_foot_keeps_one_interval_per_stance():
    rec = simulate_foot(modes=("walk",), duration_s=40, seed=206)
    r, sp = _recall_and_spurious(rec, get_detector("pseudo-std").detect(rec).per_sample_zupts_)
    assert r == 1.0 and sp <= 0.05


def test_cli_interval_rules_through_zupt_and_segment(tmp_path, capsys):
    import json

    from gaitml.cli import main
    from gaitml.io.gaitml_csv import write_gaitml_csv

    rec = simulate_foot(modes=("run",), duration_s=20, seed=207)
    path = write_gaitml_csv(rec, tmp_path / "run.csv")
    n_true = len(rec.reference["zupt_intervals"])
    counts = {}
    for rules in ("stride", "fixed", "none"):
        assert main(["zupt", str(path), "--interval-rules", rules, "--json"]) == 0
        obj = json.loads(capsys.readouterr().out)
        assert obj["interval_rules"] == rules
        counts[rules] = obj["n_intervals"]
    assert counts["fixed"] < n_true // 2 < 0.8 * n_true <= counts["stride"] < counts["none"]
    out = tmp_path / "seg.csv"
    assert main(["segment", str(path), "--by", "zupt", "--interval-rules", "none", "--out", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n_segments"] == counts["none"]
    assert main(["zupt", str(path), "--detector", "shoe", "--interval-rules", "none"]) == 2
    assert "--interval-rules applies to pseudo-std, magnitude only" in capsys.readouterr().err
    assert main(["segment", str(path), "--by", "steps", "--interval-rules", "fixed", "--out", str(tmp_path / "s.csv")]) == 2
    assert not (tmp_path / "s.csv").exists()


@pytest.mark.parametrize("name", ["pseudo-std", "magnitude"])
def test_stride_rules_do_not_depend_on_where_the_recording_starts(name):
    """The period is estimated in blocks centred on the runs that need it: a slice decides as the whole does."""
    rec = simulate_foot(modes=("run",), duration_s=40, seed=208)
    whole = get_detector(name).detect(rec).per_sample_zupts_
    off = 637  # not a multiple of any block or hop
    part = get_detector(name).detect(rec.slice(off, rec.n_samples)).per_sample_zupts_
    inner = slice(off + 500, rec.n_samples - 500)  # 5 s from the slice's start and the end
    assert np.array_equal(part[inner.start - off : inner.stop - off], whole[inner])
