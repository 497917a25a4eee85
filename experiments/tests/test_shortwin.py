"""Short-window variability (experiments.scripts.shortwin): known-answer signals, the table logic, real IFSM values."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import scipy.stats

from experiments.scripts import shortwin
from experiments.scripts.shortwin import (
    GROUP_KEY,
    per_recording_table,
    ratio_summary,
    ratio_table,
    real_walks,
    simulated_walks,
    step_shape_statistics,
    step_shape_table,
    walking_part,
    window_dispersion,
)
from experiments.tests.conftest import shared
from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.recording import Recording

FS = 50.0


def test_white_noise_mean_gets_sqrt3_noisier_in_a_third_of_the_window():
    # the mean of n independent samples has sd sigma / sqrt(n): 25 vs 75 samples -> sqrt(3)
    rng = np.random.default_rng(0)
    acc = rng.normal(0.0, 1.0, (int(1200 * FS), 3)) + [0.0, 0.0, GRAVITY_MS2]
    d = window_dispersion(Recording.from_arrays(acc, FS), walk_only=False)
    for f in ("acc_x__mean", "acc_y__mean", "acc_z__mean"):
        assert d.loc[f, "ratio"] == pytest.approx(np.sqrt(3.0), rel=0.05), f
    assert (d["sd_short"] > d["sd_long"]).all()


def test_features_that_do_not_change_between_windows_have_no_ratio():
    # every window is a whole number of 0.5 s periods (25 samples) moved by whole samples: the same
    # values in another order, so every order-free feature is the same in every window
    t = np.arange(int(120 * FS)) / FS
    w = 2 * np.pi * 2.0 * t
    acc = np.column_stack([np.sin(w), 2 * np.sin(w + 1.0) + 0.5 * np.sin(2 * w), GRAVITY_MS2 + 3 * np.cos(w)])
    d = window_dispersion(Recording.from_arrays(acc, FS), walk_only=False)
    # f1 and m4 (squared first / second differences) see the order: the wrap-around difference depends on
    # the phase; so does the magnitude, smoothed inside each window with 2-sample means at the window edges
    order_dependent = d.index.str.startswith("acc_mag__") | d.index.str.endswith(("__f1", "__m4"))
    assert np.isfinite(d.loc[order_dependent, "ratio"]).all()
    others = d[~order_dependent]
    assert len(others) == 36
    assert others["ratio"].isna().all(), others[others["ratio"].notna()]
    assert (others["sd_long"] < 1e-9).all()


def _long(rows: dict[str, tuple[list, list, list, list]]) -> pd.DataFrame:
    """Per-recording table from {feature: (IFSM1, IFSM2, Oxford, sim)} ratio lists."""
    out = []
    for f, groups in rows.items():
        for g, vals in zip(("IFSM1", "IFSM2", "Oxford", "sim"), groups, strict=True):
            out += [{"group": g, "recording": f"{g}_{i}", "feature": f, "ratio": v} for i, v in enumerate(vals)]
    return pd.DataFrame(out)


def test_ratio_table_flags_only_large_differences_with_all_real_values_on_one_side():
    per_rec = _long(
        {
            "up": ([2.0], [2.1], [1.9, 2.0], [1.4, 1.5, 1.6]),  # real 2.0 vs sim 1.5: +33 %
            "mixed": ([2.0], [1.4], [2.0, 2.0], [1.4, 1.5, 1.6]),  # +33 % but IFSM2 below the sim
            "down": ([1.0], [1.0], [1.0, 1.0], [1.5, 1.5, 1.5]),  # -33 %
            "same": ([1.5], [1.6], [1.4, 1.4], [1.5, 1.5, 1.5]),  # 0 %
        }
    )
    t = ratio_table(per_rec)
    assert list(t.index) == ["up", "mixed", "down", "same"]
    assert t.loc["up", "oxford_median"] == pytest.approx(1.95)
    assert t.loc["up", "diff_pct"] == pytest.approx(100 / 3)
    assert list(t["flag"]) == ["REAL>SIM", "", "REAL<SIM", ""]
    s = ratio_summary(t)
    assert (s["n_features"], s["n_within"], s["n_real_gt_sim"], s["n_real_lt_sim"]) == (4, 1, 1, 1)
    assert s["median_diff_pct"] == pytest.approx(100 / 6)
    # a stricter threshold keeps nothing flagged; without Oxford the IFSM columns decide
    assert (ratio_table(per_rec, flag_pct=40)["flag"] == "").all()
    no_ox = ratio_table(per_rec[per_rec["group"] != "Oxford"])
    assert no_ox["oxford_median"].isna().all()
    assert no_ox.loc["up", "flag"] == "REAL>SIM" and no_ox.loc["mixed", "flag"] == ""


def test_tables_need_both_real_and_simulated_recordings():
    per_rec = _long({"a": ([1.0], [1.0], [1.0], [1.0])})
    with pytest.raises(InputError, match="no simulated recording"):
        ratio_table(per_rec[per_rec["group"] != "sim"])
    with pytest.raises(InputError, match="no real recording"):
        ratio_table(per_rec[per_rec["group"] == "sim"])


def test_step_shape_statistics_match_a_per_step_scipy_loop():
    rec = simulated_walks(1)[0].slice(0, int(40 * FS))
    got = step_shape_statistics(rec)
    walk = walking_part(rec)
    pk = shortwin.count_peaks(walk, height_above_g_ms2=shortwin.PEAK_ABOVE_G_MS2, min_distance_s=shortwin.MIN_PEAK_DISTANCE_S)
    mag, y = np.linalg.norm(walk.acc, axis=1), walk.acc[:, 1]
    segs = [(a, b) for a, b in zip(pk[:-1], pk[1:], strict=True) if b - a >= shortwin.MIN_STEP_SAMPLES]
    assert got["n_steps"] == len(segs) > 50
    assert got["step_skew_sd"] == pytest.approx(np.std([scipy.stats.skew(mag[a:b]) for a, b in segs]))
    assert got["step_kurt_sd"] == pytest.approx(np.std([scipy.stats.kurtosis(mag[a:b]) for a, b in segs]))
    assert got["step_ymin_sd_over_ystd"] == pytest.approx(np.std([y[a:b].min() for a, b in segs]) / y.std())
    exc = mag[[a for a, _ in segs]] - GRAVITY_MS2
    assert got["step_peak_cv"] == pytest.approx(exc.std() / exc.mean())


def test_missing_data_is_a_one_line_input_error(tmp_path, capsys):
    with pytest.raises(InputError, match="ifsm-flat-phone") as exc:
        real_walks(tmp_path)
    assert "\n" not in str(exc.value)
    assert shortwin.main([str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ") and "\n" not in err


def test_bad_window_pair_is_rejected():
    rec = Recording.from_arrays(np.tile([0.0, 0.0, GRAVITY_MS2], (500, 1)), FS)
    with pytest.raises(InputError, match="windows_s"):
        window_dispersion(rec, windows_s=(1.5, 0.5), walk_only=False)


@pytest.fixture(scope="module")
def ifsm():
    shared("ifsm-flat-phone", "acceleration_flat_holding_2.xlsx")
    return real_walks(shared(), oxford=False)


@pytest.mark.realdata
def test_real_ifsm_values_and_the_command(ifsm, tmp_path, monkeypatch, capsys):
    assert [r.meta[GROUP_KEY] for r in ifsm] == ["IFSM1", "IFSM2"]
    sims = simulated_walks(2)
    t = ratio_table(per_recording_table(ifsm + sims))
    # snapshot of the real walks (module docstring): |acc| mean 2.05 / 1.45, yz correlation 2.13 / 1.97
    assert t.loc["acc_mag__mean", ["IFSM1", "IFSM2"]].tolist() == pytest.approx([2.05, 1.45], abs=0.01)
    assert t.loc["acc_yz__corr", ["IFSM1", "IFSM2"]].tolist() == pytest.approx([2.13, 1.97], abs=0.01)
    assert len(t) == 52 and t["oxford_median"].isna().all() and set(t["flag"]) <= {"", "REAL>SIM", "REAL<SIM"}
    shape = step_shape_table(ifsm + sims)
    assert shape.loc["step_skew_sd", ["IFSM1", "IFSM2"]].tolist() == pytest.approx([0.300, 0.397], abs=0.002)
    assert shape.loc["step_ymin_sd_over_ystd", ["IFSM1", "IFSM2"]].tolist() == pytest.approx([0.745, 0.706], abs=0.002)
    assert shape.loc["step_peak_cv", ["IFSM1", "IFSM2"]].tolist() == pytest.approx([0.236, 0.411], abs=0.002)
    # the command, without the Oxford files: tables only with --out
    monkeypatch.setattr(shortwin, "real_walks", lambda data_dir: ifsm)
    assert shortwin.main([str(shared()), "--subjects", "2", "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "features within +/-30 %" in out and "step_skew_sd" in out
    written = pd.read_csv(tmp_path / "out" / "ratio.csv", index_col="feature")
    assert written["diff_pct"].to_numpy() == pytest.approx(t["diff_pct"].to_numpy(), nan_ok=True)
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["per_recording.csv", "ratio.csv", "step_shape.csv"]
