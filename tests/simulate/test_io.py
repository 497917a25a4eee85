"""Writing simulated data sets (DESIGN sec. 3), reading them back, reproducibility, CLI."""

from __future__ import annotations

import hashlib

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.io import read_dataset
from gaitml.simulate import simulate_dataset, simulate_route, write_simulation


def _digest(folder):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir()) if p.is_file()}


def test_write_and_read_back(tmp_path):
    recs = simulate_dataset(2, 20.0, seed=1) + [simulate_route("random", seed=1, duration_s=15.0)]
    paths = write_simulation(recs, tmp_path)
    assert [p.name for p in paths] == ["S01-R1.csv", "S02-R1.csv", "S01-random.csv"]
    names = {p.name for p in tmp_path.iterdir()}
    for rid in ("S01-R1", "S02-R1", "S01-random"):
        assert {f"{rid}.csv", f"{rid}.steps.csv", f"{rid}.trajectory.csv"} <= names
    man = pd.read_csv(tmp_path / "manifest.csv")
    assert list(man.columns[:3]) == ["file", "subject", "session"]
    assert {"height_m", "walk_cadence_hz", "pose", "acc_noise_ms2", "route", "n_steps_true"} <= set(man.columns)
    back = read_dataset(tmp_path)
    assert len(back) == 3
    for a, b in zip(recs, back, strict=True):
        assert b.meta["subject"] == a.meta["subject"] and b.meta["session"] == a.meta["session"]
        assert b.sampling_rate_hz == a.sampling_rate_hz
        np.testing.assert_array_equal(b.acc, a.acc)
        np.testing.assert_array_equal(b.gyr, a.gyr)
        np.testing.assert_array_equal(b.labels, a.labels)
        np.testing.assert_allclose(b.reference["steps_t_s"], a.reference["steps_t_s"])
        pd.testing.assert_frame_equal(b.reference["steps"], a.reference["steps"], check_dtype=False)
        pd.testing.assert_frame_equal(b.reference["trajectory"], a.reference["trajectory"], check_dtype=False)
        assert b.meta["walk_cadence_hz"] == pytest.approx(a.meta["walk_cadence_hz"], abs=1e-6)


def test_same_seed_gives_byte_identical_files(tmp_path):
    for name in ("a", "b"):
        write_simulation(simulate_dataset(2, 15.0, seed=7, pauses=True) + [simulate_route("rectangle", seed=7)], tmp_path / name)
    da, db = _digest(tmp_path / "a"), _digest(tmp_path / "b")
    assert da == db and len(da) == 10
    write_simulation(simulate_dataset(2, 15.0, seed=8, pauses=True), tmp_path / "c")
    dc = _digest(tmp_path / "c")
    assert dc["S01-R1.csv"] != da["S01-R1.csv"]


def test_first_subjects_do_not_depend_on_the_number_of_subjects():
    a = simulate_dataset(1, 10.0, seed=3)[0]
    b = simulate_dataset(3, 10.0, seed=3)[0]
    np.testing.assert_array_equal(a.acc, b.acc)


def test_cli_simulate(tmp_path, capsys):
    out = tmp_path / "sim"
    rc = main(
        ["simulate", str(out), "--subjects", "2", "--duration-s", "12", "--modes", "walk,run", "--seed", "2", "--sampling-rate-hz", "100"]
    )
    assert rc == 0
    recs = read_dataset(out)
    assert len(recs) == 2
    assert all(r.sampling_rate_hz == 100.0 and set(r.labels) <= {"walk", "run"} for r in recs)
    assert capsys.readouterr().out == ""


def test_cli_simulate_route(tmp_path):
    rc = main(["simulate", str(tmp_path / "r"), "--subjects", "1", "--route", "rectangle", "--seed", "1"])
    assert rc == 0
    rec = read_dataset(tmp_path / "r")[0]
    assert rec.meta["route"] == "rectangle"
    assert rec.reference["steps"]["step_length_m"].sum() == pytest.approx(262.0, abs=0.5)


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["--modes", "walk,fly"], "unknown motion mode"),
        (["--route", "moon"], "unknown --route"),
        (["--subjects", "0"], "--subjects"),
        (["--sampling-rate-hz", "3"], "--sampling-rate-hz"),
    ],
)
def test_cli_bad_arguments(tmp_path, capsys, argv, match):
    rc = main(["simulate", str(tmp_path / "x"), "--duration-s", "5", *argv])
    assert rc == 2
    err = capsys.readouterr().err
    assert match in err and "Traceback" not in err
