"""tempo_gravity's command line (no data needed): bad input is refused in one line before any data is read."""

from experiments.scripts.tempo_gravity import main


def test_missing_data_and_bad_factors_are_refused_in_one_line(tmp_path, capsys):
    assert main(["--data", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "tyrex-attitude" in err[0]
    (tmp_path / "tyrex-attitude").mkdir()
    for bad in ("fast", "", "-1"):
        assert main(["--data", str(tmp_path), "--factors", bad]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--factors" in err[0]
