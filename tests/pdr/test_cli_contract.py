"""`gaitml pdr` CLI contract: one stderr line on bad input, no partial outputs, notes only on success."""

from __future__ import annotations

import pytest

from gaitml.cli import main
from gaitml.io import write_gaitml_csv
from tests.conftest import shared
from tests.pdr.synth import synth_walk

LEGS = [("walk", 12, 0.0), ("side_left", 8, 0.0)]


@pytest.fixture(scope="module")
def rec_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("pdr") / "walk.csv"
    write_gaitml_csv(synth_walk(LEGS, pitch_deg=10, noise=0.05), path)
    return path


def _err_lines(capsys):
    return [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]


def test_plot_under_a_file_fails_before_work_and_writes_nothing(rec_path, tmp_path, capsys):
    (tmp_path / "bad").write_text("a file")
    out = tmp_path / "traj.csv"
    assert main(["pdr", str(rec_path), "--out", str(out), "--plot", str(tmp_path / "bad" / "x.png")]) == 2
    lines = _err_lines(capsys)
    assert len(lines) == 1 and "--plot" in lines[0] and "is a file" in lines[0]
    assert not out.exists()


def test_plot_failure_while_rendering_leaves_no_csv(rec_path, tmp_path, capsys, monkeypatch):
    import gaitml.pdr.plot as plot_mod

    def boom(*a, **k):
        raise FileExistsError(17, "File exists", "x")

    monkeypatch.setattr(plot_mod, "plot_trajectory", boom)
    out = tmp_path / "traj.csv"
    assert main(["pdr", str(rec_path), "--out", str(out), "--plot", str(tmp_path / "p.png")]) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no CSV, no plot, no temporaries


def test_same_out_and_plot_is_a_usage_error(rec_path, tmp_path, capsys):
    x = tmp_path / "x.png"
    assert main(["pdr", str(rec_path), "--out", str(x), "--plot", str(tmp_path / "." / "x.png")]) == 2
    lines = _err_lines(capsys)
    assert len(lines) == 1 and "same file" in lines[0]
    assert not x.exists()


def test_modes_model_without_model_prints_one_line(rec_path, capsys):
    assert main(["pdr", str(rec_path), "--modes", "model"]) == 2
    lines = _err_lines(capsys)
    assert len(lines) == 1 and "--model" in lines[0]


def test_no_gyro_prints_one_line_without_notes(capsys):
    path = shared("ifsm-flat-phone", "acceleration_flat_holding_1.xlsx")
    assert main(["pdr", str(path)]) == 2
    lines = _err_lines(capsys)
    assert len(lines) == 1 and "gyroscope" in lines[0]


def test_notes_come_after_success(rec_path, tmp_path, capsys):
    out, png = tmp_path / "t.csv", tmp_path / "t.png"
    assert main(["pdr", str(rec_path), "--out", str(out), "--plot", str(png)]) == 0
    assert out.is_file() and png.is_file()
    assert any(ln.startswith("note:") for ln in _err_lines(capsys))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.csv", "t.png"]
