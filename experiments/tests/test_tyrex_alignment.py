"""The tyrex clock-check table (experiments/scripts/tyrex_alignment.py) and the before/after runner (with_align)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts import with_align
from experiments.scripts.tyrex_alignment import markdown, one, summary


def _rows():
    rows = []
    for k, (phone, shift, acc, acc_ok, t0) in enumerate(
        [("Nexus5", 0.020, 0.024, True, 0.5), ("Nexus5", 0.030, 0.010, True, 0.2), ("iPhone5", 0.010, np.nan, False, 0.0)]
    ):
        rows.append(
            {
                "recording": f"r{k}",
                "phone": phone,
                "gyro_shift_s": shift,
                "gyro_corr_file": 0.9,
                "gyro_corr_peak": 0.99,
                "gyro_accepted": True,
                "acc_shift_s": acc,
                "acc_accepted": acc_ok,
                "drift_s": 0.001 * (k + 1),
                "t0_s": t0,
                "t0_dropped_shift_s": shift - t0,
            }
        )
    rows.append({**rows[0], "recording": "r3", "gyro_accepted": False, "gyro_shift_s": 0.9})  # refused: left out of the lags
    return pd.DataFrame(rows)


def test_summary_counts_accepted_lags_per_phone_only():
    s = summary(_rows()).set_index("phone")
    assert s.loc["Nexus5", "recordings"] == 3 and s.loc["Nexus5", "accepted (gyro)"] == 2
    assert s.loc["Nexus5", "shift median (ms)"] == pytest.approx(25.0)
    assert s.loc["Nexus5", "max |shift| (ms)"] == pytest.approx(30.0)  # the refused 900 ms is not a lag
    assert s.loc["Nexus5", "|gyro - acc| median (ms)"] == pytest.approx(12.0)  # |20-24| and |30-10|
    assert s.loc["all", "recordings"] == 4
    md = markdown(s.reset_index())
    assert md.splitlines()[0].startswith("| phone |") and len(md.splitlines()) == 2 + 3


def test_with_align_refuses_an_unknown_alignment(capsys):
    assert with_align.main(["fast", "experiments.scripts.tyrex_steps"]) == 2
    assert "is not one of" in capsys.readouterr().err


@pytest.mark.realdata
def test_one_real_nexus5_row_shows_the_dropped_t0():
    from tests.conftest import shared

    row = one(shared("tyrex-attitude", "android/Thibaud_Nexus5_NoDist_Swinging"))
    assert row["gyro_accepted"] and abs(row["gyro_shift_s"]) < 0.05
    assert row["t0_dropped_shift_s"] == pytest.approx(row["gyro_shift_s"] - row["t0_s"], abs=0.02)
    assert abs(row["drift_s"]) < 0.01
