"""The bag study's rules (experiments.scripts.bag_gait_check): the exemption keeps a bag walk, the old rule did not."""

from __future__ import annotations

from experiments.scripts.bag_gait_check import main, rules, walk_recording


def test_rules_on_a_bag_walk_and_on_a_belt_walk():
    bag = rules(walk_recording("bag", 2, duration_s=40.0))
    assert bag["now"] == bag["off"] > 50
    assert bag["before"] < 0.5 * bag["off"]  # the rotation test on every bout lost the walk
    belt = rules(walk_recording("belt", 2, duration_s=40.0))
    assert belt["now"] == belt["before"] == belt["off"]


def test_main_rejects_nothing_it_should_not(tmp_path, capsys, monkeypatch):
    import experiments.scripts.bag_gait_check as m

    monkeypatch.setattr(m, "SELECTION_SEEDS", (0,))
    monkeypatch.setattr(m, "HELDOUT_SEEDS", (100,))
    monkeypatch.setattr(m, "POSITIONS", ("bag",))
    assert main(["--skip-tyrex", "--cache", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "## Simulated walks, 60 s, held-out seeds 100-129" in out and "| bag |" in out
    assert "0 of >= 30 steps" in out
    assert any(tmp_path.iterdir())  # cached per recording
