"""The adoption rule of data.augment.rates read off two tyrex_modes --out files (experiments/scripts/rates_adoption.py)."""

from __future__ import annotations

from experiments.scripts.rates_adoption import main, read_tables

MOTION = "| motion | right | flagged | silently wrong | right per left-out |\n|---|---|---|---|---|\n"
SIM = "| position | mode | right | flagged | silently wrong | right over folds |\n|---|---|---|---|---|---|\n"


def _file(path, native_walk: str, sim_back: str, low_right: str, low_wrong: str, base: bool):
    txt = "### recipe a (all52+gyro), each tyrex person left out in turn\n\n" + MOTION
    txt += f"| Texting | {native_walk} | 0.00 | 0.03 | 0.90-0.99 |\n| all | {native_walk} | 0.00 | 0.03 | 0.90-0.99 |\n"
    txt += "\nheld-out simulator (seed 2024, 2 subjects)\n\n" + SIM + f"| back-pocket | backward | {sim_back} | 0.00 | 0.50 | 0.41-0.49 |\n"
    low = MOTION + f"| Texting | {low_right} | 0.00 | {low_wrong} | 0.80-0.95 |\n| all | {low_right} | 0.00 | {low_wrong} | 0.80-0.95 |\n"
    txt += "\n#### recipe a: the left-out people recorded at 20 Hz (each tyrex person left out in turn)\n\n"
    if base:  # the rate check flags all; the features-alone table follows
        txt += MOTION + "| Texting | 0.00 | 1.00 | 0.00 | 0.00-0.00 |\n| all | 0.00 | 1.00 | 0.00 | 0.00-0.00 |\n"
        txt += "\nthe same without the rate check (what the features alone answer at 20 Hz):\n\n" + low
    else:
        txt += low
    path.write_text(txt)
    return path


def test_tables_are_read_by_title_and_repeated_titles_numbered(tmp_path):
    p = tmp_path / "t.md"
    p.write_text("a title\n\n| x | y |\n|---|---|\n| 1 | 2 |\n\na title\n\n| x | y |\n|---|---|\n| 3 | 4 |\n")
    t = read_tables(p)
    assert t == {"a title": [{"x": "1", "y": "2"}], "a title #2": [{"x": "3", "y": "4"}]}


def test_the_rule_adopts_only_when_20_hz_improves_and_no_native_row_falls_beyond_its_spread(tmp_path, capsys):
    base = _file(tmp_path / "b.md", "0.97", "0.44", "0.90", "0.09", base=True)
    good = _file(tmp_path / "g.md", "0.96", "0.40", "0.93", "0.05", base=False)  # falls within the spreads (0.09, 0.08)
    assert main([str(base), str(good)]) == 0
    assert capsys.readouterr().out.strip().endswith("adopt: True")
    falls = _file(tmp_path / "f.md", "0.97", "0.32", "0.93", "0.05", base=False)  # back-pocket backward beyond 0.08
    main([str(base), str(falls)])
    out = capsys.readouterr().out
    assert "simulator back-pocket backward | 0.44 | 0.32 | 0.08 | FALLS" in out and out.strip().endswith("adopt: False")
    worse = _file(tmp_path / "w.md", "0.97", "0.44", "0.93", "0.10", base=False)  # more silently wrong at 20 Hz
    main([str(base), str(worse)])
    assert capsys.readouterr().out.strip().endswith("adopt: False")
