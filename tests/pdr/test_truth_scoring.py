"""Scoring a trajectory against landmarks or a dense truth (gaitml.evaluation.positioning, gaitml.io.truth)."""

from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.errors import InputError
from gaitml.evaluation.positioning import apply_alignment, score_positions
from gaitml.io.truth import project_latlon, read_truth, truth_from_table


def _l_route(n=400):
    """An L-shaped walk: 40 m north then 30 m east at 1 m/s, sampled at 10 Hz."""
    t = np.linspace(0, 70, n)
    x = np.where(t < 40, 0.0, t - 40)
    y = np.where(t < 40, t, 40.0)
    return t, np.column_stack([x, y])


def _rot(xy, a):
    c, s = np.cos(a), np.sin(a)
    return xy @ np.array([[c, s], [-s, c]])


def test_rotated_shifted_copy_scores_zero_after_start_heading_alignment():
    t, xy = _l_route()
    est = _rot(xy, 0.7) + [5.0, -3.0]  # unknown heading and origin
    truth = truth_from_table(t, xy).table
    pts, sm = score_positions(t, est, truth)
    assert sm["mean_error_m"] < 1e-9 and sm["p75_error_m"] < 1e-9
    assert sm["rotation_rad"] == pytest.approx(-0.7, abs=1e-9)
    np.testing.assert_allclose(apply_alignment(est, sm), xy, atol=1e-9)
    # position-only alignment keeps the wrong heading: errors grow with distance
    _, sm2 = score_positions(t, est, truth, align="start")
    assert sm2["end_error_m"] == pytest.approx(2 * np.sin(0.35) * np.hypot(30, 40), rel=1e-6)


def test_known_errors_mean_p75_and_percent_of_distance():
    t, xy = _l_route()
    lm_idx = np.searchsorted(t, [0, 10, 20, 30, 40, 50, 60, 70])
    truth = truth_from_table(t[lm_idx], xy[lm_idx]).table
    est = xy.copy()
    est[:, 0] += 0.05 * t  # a drift east growing by 0.05 m/s, from 0 at the start
    pts, sm = score_positions(t, est, truth, align="start")
    expected = 0.05 * t[lm_idx][1:]
    assert sm["n_points"] == 7
    assert sm["mean_error_m"] == pytest.approx(expected.mean(), rel=1e-3)
    assert sm["p75_error_m"] == pytest.approx(np.percentile(expected, 75), rel=1e-3)
    assert sm["distance_m"] == pytest.approx(70.0, rel=1e-3)
    assert sm["end_error_pct_distance"] == pytest.approx(100 * 3.5 / 70, rel=1e-3)
    assert list(pts["role"])[:2] == ["anchor", "scored"]


def test_sparse_and_dense_truth_agree_on_the_same_route():
    t, xy = _l_route(1400)
    rng = np.random.default_rng(0)
    est = xy + np.cumsum(rng.normal(0, 0.02, xy.shape), axis=0)
    dense = truth_from_table(t, xy)
    keep = np.r_[0:1400:100, 1399]
    sparse = truth_from_table(t[keep], xy[keep])
    assert dense.kind == "dense" and sparse.kind == "landmarks"
    _, sd = score_positions(t, est, dense.table, align="start")
    _, ss = score_positions(t, est, sparse.table, align="start")
    assert ss["end_error_m"] == pytest.approx(sd["end_error_m"], abs=1e-9)  # same last point
    assert ss["mean_error_m"] == pytest.approx(sd["mean_error_m"], rel=0.25)


def test_points_outside_the_recording_are_not_scored():
    t, xy = _l_route()
    truth = truth_from_table(np.r_[t, 100.0], np.vstack([xy, [[99, 99]]])).table
    _, sm = score_positions(t, xy, truth, t_end_s=70.0)
    assert sm["n_outside"] == 1 and sm["max_error_m"] < 1e-9


def test_floor_changes_split_segments():
    t = np.arange(6) * 10.0
    xy = np.column_stack([np.zeros(6), t])
    truth = truth_from_table(t, xy, floor=[0, 0, 0, 1, 1, 1])
    assert list(truth.table["segment"]) == [0, 0, 0, 1, 1, 1]
    assert any("changes floor 1 time" in n for n in truth.notes)
    _, sm = score_positions(t, xy, truth.table)
    assert [g["floor"] for g in sm["segments"]] == [0.0, 1.0]


def test_projection_matches_known_distances():
    # one arc-second of latitude is about 30.87 m at 45 deg; longitude scaled by cos(lat)
    xy = project_latlon([45.0, 45.0 + 1 / 3600, 45.0], [7.0, 7.0, 7.0 + 1 / 3600])
    assert xy[1, 1] == pytest.approx(30.87, abs=0.02) and xy[2, 0] == pytest.approx(21.89, abs=0.02)
    with pytest.raises(InputError, match="swapped"):
        project_latlon([120.0, 45.0], [7.0, 7.0])


def test_csv_truth_variants(tmp_path):
    p = tmp_path / "lm.csv"
    p.write_text("t,x_mm,y_mm\n1.0,0,0\n2.0,1000,0\n")
    tr = read_truth(p, t0_original_s=0.5)
    assert list(tr.table["x_m"]) == [0.0, 1.0] and list(tr.table["t_s"]) == [0.5, 1.5]
    q = tmp_path / "ll.csv"
    q.write_text("t,lat,lon,floor\n0,40.0,-3.7,0\n10,40.0001,-3.7,1\n")
    tr = read_truth(q)
    assert tr.table["y_m"].iloc[1] == pytest.approx(11.1, abs=0.05) and tr.table["segment"].iloc[1] == 1
    r = tmp_path / "bad.csv"
    r.write_text("when,a,b\n0,1,2\n")
    with pytest.raises(InputError, match="no time column"):
        read_truth(r)


def test_cli_pdr_truth_on_simulated_route(tmp_path):
    """Through the command a user runs: dense truth and landmarks from the same simulated route."""
    out = tmp_path / "sim"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["simulate", str(out), "--subjects", "1", "--route", "rectangle", "--seed", "1"]) == 0
    rec = out / "S01-rectangle.csv"
    traj = pd.read_csv(out / "S01-rectangle.trajectory.csv")
    lm = traj.iloc[::250][["t", "x_m", "y_m"]]
    lm = pd.concat([lm, traj.iloc[[-1]][["t", "x_m", "y_m"]]])
    lm.to_csv(tmp_path / "lm.csv", index=False)
    res = {}
    for name, truth in (("dense", str(out / "S01-rectangle.trajectory.csv")), ("landmarks", str(tmp_path / "lm.csv"))):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            assert main(["pdr", str(rec), "--truth", truth, "--json", "--plot", str(tmp_path / f"{name}.png")]) == 0
        res[name] = json.loads(buf.getvalue())["truth"]
        assert res[name]["kind"] == name and (tmp_path / f"{name}.png").stat().st_size > 0
    # the same last point, the same distance walked (the landmarks lie on the rectangle's corners or sides)
    assert res["landmarks"]["end_error_m"] == pytest.approx(res["dense"]["end_error_m"], abs=0.05)
    assert res["landmarks"]["distance_m"] == pytest.approx(res["dense"]["distance_m"], rel=0.05)
    # a PDR on a 262 m rectangle: the mean error stays well below the distance walked (a floor, not a pin)
    assert res["dense"]["mean_error_m"] < 0.1 * res["dense"]["distance_m"]


def _run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_getsensordata_posi_without_coordinates_refused(tmp_path):
    from gaitml.io.getsensordata import write_getsensordata
    from tests.io_apps._make import acc_true, gyr_true, jittered_times

    t = jittered_times(0, 30, 100, 1)
    lm = pd.DataFrame({"t_s": [1.0, 15.0, 29.0], "lat_deg": [0.0] * 3, "lon_deg": [0.0] * 3, "floor": [0] * 3})
    p = write_getsensordata(tmp_path / "walk.txt", t, acc_true(t), t_gyr_s=t, gyr=gyr_true(t), landmarks=lm)
    code, out, err = _run(["pdr", str(p), "--truth", "self", "--json"])
    assert code == 2 and out == "" and "no coordinates" in err and len(err.strip().splitlines()) == 1


def test_tyrex_motion_capture_as_truth(shared_data):
    folder = shared_data / "tyrex-attitude" / "android" / "Guillaume_Nexus5_NoDist_Texting"
    if not folder.is_dir():
        pytest.skip("tyrex-attitude not in the shared data")
    code, out, err = _run(["pdr", str(folder), "--truth", "self", "--detector", "adaptive", "--json"])
    assert code == 0, err
    tr = json.loads(out)["truth"]
    assert tr["kind"] == "dense" and tr["source"].startswith("tyrex:")
    # 120 s of motion capture at 60 Hz; a walk of tens of metres in a 5 m room
    assert tr["n_points"] > 60 * 100 and 10 < tr["distance_m"] < 200
    # the errors are bounded by the room (the walker never leaves it), whatever the PDR does
    assert 0 < tr["mean_error_m"] < 50
