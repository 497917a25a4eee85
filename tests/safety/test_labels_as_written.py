"""Issue 28 finding 6: labels are the strings as written, the same in every file."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.io import read_recording
from gaitml.io.columns_csv import read_columns_csv


def _write(path, labels, fs=50.0):
    n = len(labels)
    t = np.arange(n) / fs
    acc = np.column_stack([np.zeros(n), 0.3 * np.sin(2 * np.pi * 2 * t), 9.81 + 2 * np.sin(2 * np.pi * 2 * t)])
    body = "".join(f"{a:.3f},{x:.4f},{y:.4f},{z:.4f},{lab}\n" for a, (x, y, z), lab in zip(t, acc, labels, strict=True))
    path.write_text("t,acc_x,acc_y,acc_z,label\n" + body, encoding="utf-8")
    return path


def test_codes_keep_their_leading_zeros_in_every_file(tmp_path):
    # one file holds only numeric-looking codes (pandas would read them as integers), the other a text label too
    a = read_recording(_write(tmp_path / "a.csv", ["01"] * 100 + ["02"] * 100 + ["05"] * 100))
    b = read_recording(_write(tmp_path / "b.csv", ["04"] * 100 + ["05"] * 100 + ["walk"] * 100))
    assert set(a.labels) == {"01", "02", "05"} and set(b.labels) == {"04", "05", "walk"}
    assert "05" in set(a.labels) & set(b.labels)  # one class, not "5" and "05"


def test_na_and_none_are_labels(tmp_path):
    rec = read_recording(_write(tmp_path / "na.csv", ["NA"] * 100 + ["None"] * 100 + ["null"] * 100))
    assert set(rec.labels) == {"NA", "None", "null"}


def test_an_empty_label_is_refused(tmp_path):
    with pytest.raises(InputError, match="empty label at line 52"):
        read_recording(_write(tmp_path / "e.csv", ["walk"] * 50 + [""] + ["walk"] * 249))


def test_a_nul_byte_is_refused_not_a_new_class(tmp_path):
    with pytest.raises(InputError, match="control character"):
        read_recording(_write(tmp_path / "nul.csv", ["walk"] * 50 + ["wa\x00lk"] + ["walk"] * 249))


def test_columns_csv_labels_as_written(tmp_path):
    n = 300
    t = np.arange(n) / 50.0
    df = pd.DataFrame({"time": t, "ax": 0.0, "ay": 0.1 * np.sin(t), "az": 9.81 + np.sin(4 * np.pi * t), "lab": ["01"] * 150 + ["NA"] * 150})
    df.to_csv(tmp_path / "c.csv", index=False)
    rec = read_columns_csv(tmp_path / "c.csv", {"t": "time", "acc_x": "ax", "acc_y": "ay", "acc_z": "az", "label": "lab"})
    assert set(rec.labels) == {"01", "NA"}
