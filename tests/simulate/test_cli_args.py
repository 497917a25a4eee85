"""`gaitml simulate` argument validation: exit 2 with one stderr line, before any work."""

from __future__ import annotations

import pytest

from gaitml.cli import main
from gaitml.errors import InputError
from gaitml.simulate import sample_subjects, simulate_recording


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["--seed", "-1"], "--seed"),
        (["--duration-s", "1e7"], "--duration-s"),
        (["--duration-s", "nan"], "--duration-s"),
        (["--subjects", "100000"], "--subjects"),
        (["--subjects", "0"], "--subjects"),
        (["--sampling-rate-hz", "0"], "--sampling-rate-hz"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(tmp_path, capsys, argv, needle):
    out = tmp_path / "sim"
    assert main(["simulate", str(out), *argv]) == 2
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(lines) == 1 and needle in lines[0], lines
    assert not out.exists()


def test_duration_note_only_when_given(tmp_path, capsys):
    assert main(["simulate", str(tmp_path / "a"), "--subjects", "1", "--route", "rectangle", "--modes", "walk"]) == 0
    assert "--duration-s" not in capsys.readouterr().err
    assert main(["simulate", str(tmp_path / "b"), "--subjects", "1", "--route", "rectangle", "--modes", "walk", "--duration-s", "30"]) == 0
    assert "--duration-s is not used" in capsys.readouterr().err


def test_library_validates_seed_duration_and_subjects():
    subj = sample_subjects(1, 0)[0]
    with pytest.raises(InputError, match="seed"):
        simulate_recording(subj, duration_s=10, seed=-1)
    with pytest.raises(InputError, match="duration_s"):
        simulate_recording(subj, duration_s=1e7, seed=0)
    with pytest.raises(InputError, match="seed"):
        sample_subjects(1, -3)
    with pytest.raises(InputError, match="at most"):
        sample_subjects(5000, 0)
