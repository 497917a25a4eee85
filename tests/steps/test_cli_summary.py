"""`gaitml steps` text summary: period, interval and cadence agree with each other."""

from __future__ import annotations

import re

from gaitml.cli import main
from tests.conftest import shared


def test_summary_period_and_cadence_are_consistent(capsys):
    path = shared("ifsm-flat-phone", "acceleration_flat_holding_2.xlsx")
    assert main(["steps", str(path)]) == 0
    out = capsys.readouterr().out
    assert "319 steps" in out
    period = float(re.search(r"step period \(period_s[^)]*\): median ([0-9.]+) s", out).group(1))
    interval, cadence = map(float, re.search(r"step interval: median ([0-9.]+) s = cadence ([0-9.]+) steps/min", out).groups())
    assert abs(cadence - 60.0 / interval) < 0.2
    assert abs(period - interval) <= 0.15 * interval
    assert "pauses included" in out
