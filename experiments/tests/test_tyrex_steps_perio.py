"""The weak-window classes of tyrex_steps_perio (no data needed)."""

import numpy as np

from experiments.scripts.tyrex_steps_perio import WINDOW_CLASSES, main, window_class


def test_window_class_follows_the_reliefs_tests_in_order():
    assert window_class(0.1, 0.9, -0.9, 25.0, 25.0) == "rms<0.2"  # a steady phone, whatever its rhythm
    assert window_class(0.5, 0.2, -0.9, 25.0, 25.0) == "corr<0.3"
    assert window_class(0.5, 0.9, np.nan, np.nan, 25.0) == "corr<0.3"  # no stride period found
    assert window_class(0.5, 0.9, 0.2, 25.0, 25.0) == "half>0"
    assert window_class(0.5, 0.9, -0.5, 30.0, 25.0) == "match"  # within 25 %
    assert window_class(0.5, 0.9, -0.5, 50.0, 25.0) == "swing step ~2T"  # a half-step window
    assert window_class(0.5, 0.9, -0.5, 12.5, 25.0) == "swing step ~T/2"
    assert window_class(0.5, 0.9, -0.5, 35.0, 25.0) == "other ratio"
    assert set(WINDOW_CLASSES) == {"rms<0.2", "corr<0.3", "half>0", "match", "swing step ~2T", "swing step ~T/2", "other ratio"}


def test_missing_data_is_refused_in_one_line(tmp_path, capsys):
    assert main(["--data", str(tmp_path), "--part", "counts"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "tyrex-attitude" in err[0]
