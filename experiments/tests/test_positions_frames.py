"""experiments.scripts.positions_frames: per-position tables from run folders of simulated-position configs."""

from __future__ import annotations

import pandas as pd
import pytest

from experiments.scripts.positions_frames import main, mode_tables, position_of, position_tables, read_points
from gaitml.errors import InputError
from gaitml.pipeline import evaluate_config, parse_config


def test_position_of_names():
    assert position_of("S01-R1-front-pocket") == "front-pocket" and position_of("S12-R3-bag") == "bag"
    with pytest.raises(InputError, match="is not named S<n>-R<n>-<position>"):
        position_of("walk01")


def test_mode_tables_from_a_frame_sweep(tmp_path, capsys):
    sim = {"subjects": 3, "duration_s": 20.0, "modes": ["walk", "run"], "positions": ["front-pocket", "hand-flat"]}
    cfg = parse_config({"name": "pf", "data": {"source": "simulated", "simulated": sim}, "sweep": {"features.frame": ["phone", "gravity"]}})
    res = evaluate_config(cfg, out_dir=tmp_path / "run", progress=False)
    points = read_points([tmp_path / "run"])
    assert [n for n, _ in points] == ["SVM phone", "SVM gravity"]
    summary, cells = mode_tables(points)
    for (name, df), row in zip(points, res["sweep"], strict=True):
        acc = float(summary.loc[summary["row"] == "all", name].item().split(" / ")[0])
        assert acc == pytest.approx(row["accuracy_after"], abs=5e-4)  # headline: after the correction
        # a position's accuracy is over that position's windows only
        sel = df[df["position"] == "hand-flat"]
        got = float(summary.loc[summary["row"] == "position hand-flat", name].item().split(" / ")[0])
        assert got == pytest.approx((sel["label"] == sel["pred"]).mean(), abs=5e-4)
    assert len(cells) == 4 and set(cells["position"]) == {"front-pocket", "hand-flat"}
    # the position labels of the windows: each recording's position
    raw = pd.read_csv(tmp_path / "run" / "point-00" / "predictions.csv")
    assert (points[0][1]["position"] == raw["recording"].str.split("-", n=2).str[2]).all()
    with pytest.raises(InputError, match="not found"):
        read_points([tmp_path / "nothing"])
    assert main([str(tmp_path / "run"), "--task", "position"]) == 0  # modes as classes still tabulate
    assert "| all |" in capsys.readouterr().out
    assert len(position_tables(points)) == 3
