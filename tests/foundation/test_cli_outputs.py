"""Failing commands write nothing; too-short recordings are one-line errors (exit 2)."""

from __future__ import annotations

import pytest

from gaitml.cli import main
from tests.conftest import ROOT

SHORT = "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n" + "".join(f"{i / 50},0.1,0.2,9.8,0,0,0\n" for i in range(10))
NAN = "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n" + "".join(f"{i / 50},{'nan' if i == 30 else 0.1},0.2,9.8,0,0,0\n" for i in range(200))


@pytest.mark.parametrize(
    "argv",
    [
        ["steps", "{inp}", "--out", "{out}"],
        ["zupt", "{inp}", "--out", "{out}"],
        ["features", "{inp}", "--out", "{out}"],
        ["predict", str(ROOT / "models" / "demo"), "{inp}", "--out", "{out}"],
        ["pdr", "{inp}", "--out", "{out}", "--plot", "{out}.png"],
    ],
)
@pytest.mark.parametrize("content", [NAN, ""], ids=["nan", "empty"])
def test_failed_command_writes_nothing(tmp_path, capsys, argv, content):
    inp = tmp_path / "in.csv"
    inp.write_text(content)
    out = tmp_path / "result" / "out.csv"
    code = main([a.format(inp=inp, out=out) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert not out.exists() and not (tmp_path / "result" / "out.csv.png").exists()
    leftovers = [p for p in tmp_path.rglob("*") if p.is_file() and p.name != "in.csv"]
    assert leftovers == []


@pytest.mark.parametrize(
    "argv, match",
    [
        (["features", "{inp}", "--window-s", "1.5"], "1.5"),
        (["predict", str(ROOT / "models" / "demo"), "{inp}"], "too short"),
        (["steps", "{inp}", "--detector", "autocorr"], "too short"),
    ],
)
def test_too_short_recording(tmp_path, capsys, argv, match):
    inp = tmp_path / "short.csv"
    inp.write_text(SHORT)
    code = main([a.format(inp=inp) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and match in err and len(err.strip().splitlines()) == 1


def test_simulate_bad_arguments_write_nothing(tmp_path, capsys):
    out = tmp_path / "sim"
    assert main(["simulate", str(out), "--modes", "walk,moonwalk"]) == 2
    assert "moonwalk" in capsys.readouterr().err
    assert not out.exists()


def test_evaluate_missing_config(tmp_path, capsys):
    assert main(["evaluate", str(tmp_path / "nope.toml"), "--out", str(tmp_path / "run")]) == 2
    assert not (tmp_path / "run").exists()
