"""Every committed config builds; bad configs fail before any work with one-line ConfigErrors."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from gaitml.errors import ConfigError
from gaitml.models import torch_available
from gaitml.pipeline import load_config, parse_config, prepare_data, sweep_grid
from tests.models.synth import write_synth_folder

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = sorted((ROOT / "experiments").glob("*.toml"))


def test_the_committed_configs_are_there():
    names = {p.name for p in CONFIGS}
    assert {
        "paper-svm.toml",
        "window-sweep.toml",
        "torch-mlp.toml",
        "torch-cnn.toml",
        "oxford-position.toml",
        "demo.toml",
        "demo-acc.toml",
    } <= names


@pytest.mark.parametrize("path", CONFIGS, ids=lambda p: p.name)
def test_committed_config_builds(path):
    """Every committed config, of every task, through the one loader (the data folder is checked when it is there)."""
    raw = tomllib.loads(path.read_text())
    if raw.get("model", {}).get("kind") in ("mlp", "cnn1d") and not torch_available():
        pytest.skip("torch extra not installed")
    data_path = raw.get("data", {}).get("path")
    cfg = load_config(path, check_paths=bool(data_path) and (path.parent / data_path).exists())
    assert cfg.name == path.stem
    assert cfg.task in ("classification", "steps")
    if cfg.task == "steps":
        assert cfg["steps"]["detectors"] and cfg["steps"]["tolerance_s"] > 0
        return
    for point in sweep_grid(cfg):
        pcfg = cfg.with_values(point) if point else cfg
        assert pcfg["windows"]["length_s"] > 0


def test_config_names_come_from_the_registries():
    """The names a config accepts are the registries' (no hand-copied list)."""
    from gaitml.evaluation.cv import CV_SCHEMES
    from gaitml.features import FEATURE_SETS
    from gaitml.models import MODEL_KINDS
    from gaitml.pipeline.config import SCHEMA, STEPS_SCHEMA
    from gaitml.simulate.subject import POSES
    from gaitml.steps import detector_names

    assert SCHEMA["features"]["set"].allowed_values() == tuple(FEATURE_SETS)
    assert SCHEMA["model"]["kind"].allowed_values() == tuple(MODEL_KINDS)
    assert SCHEMA["cv"]["scheme"].allowed_values() == tuple(CV_SCHEMES)
    assert SCHEMA["data"]["simulated"]["pose"].allowed_values() == (*POSES, "mixed")
    assert STEPS_SCHEMA["steps"]["detectors"].allowed_values(items=True) == tuple(detector_names())


def test_window_sweep_covers_the_paper_widths():
    cfg = load_config(ROOT / "experiments" / "window-sweep.toml")
    assert cfg.sweep["windows.length_s"] == [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    assert cfg["cv"]["scheme"] == "train-one-test-rest"


def test_defaults_are_filled():
    cfg = parse_config({"name": "x"})
    assert cfg["windows"] == {"length_s": 1.5, "overlap": 0.5, "min_label_fraction": 0.5, "by": "time", "detector": ""}
    assert cfg["model"]["kind"] == "linear-ovo-svm"
    assert cfg["cv"]["scheme"] == "leave-one-group-out"
    assert sweep_grid(cfg) == [{}]


def test_sweep_grid_is_the_product():
    cfg = parse_config({"name": "x", "sweep": {"windows.length_s": [1.0, 2], "features.set": ["all52", "paper34"]}})
    grid = sweep_grid(cfg)
    assert len(grid) == 4 and grid[1] == {"windows.length_s": 1.0, "features.set": "paper34"}
    assert grid[2]["windows.length_s"] == 2.0  # int promoted to float


BAD = [
    ({"name": "x", "colour": 1}, r"unknown key colour .*allowed keys: name, seed"),
    ({"name": "x", "windows": {"length": 1}}, r"unknown key windows.length in \[windows\]; allowed keys: length_s"),
    ({"name": "x", "windows": {"length_s": "1.5"}}, r"windows.length_s = '1.5' has the wrong type .*expected an integer or number"),
    ({"name": "x", "windows": {"length_s": -1}}, r"windows.length_s = -1 must be > 0"),
    ({"name": "x", "windows": {"overlap": 1.0}}, r"windows.overlap = 1.0 must be in \[0, 1\)"),
    ({"name": "x", "seed": True}, r"seed = True has the wrong type"),
    ({"name": "x", "features": {"set": "all"}}, r"features.set = 'all' is not allowed; allowed: 'all52', 'paper34', 'all52\+gyro'"),
    ({"name": "x", "model": {"kind": "rbf"}}, r"model.kind = 'rbf' is not allowed; allowed: 'linear-ovo-svm', 'mlp', 'cnn1d'"),
    ({"name": "x", "model": {"params": {"gamma": 1}}}, r"model.params.gamma is not a parameter of 'linear-ovo-svm'; allowed: C"),
    ({"name": "x", "cv": {"scheme": "kfold"}}, r"cv.scheme = 'kfold' is not allowed; allowed: 'train-one-test-rest'"),
    ({"name": "x", "cv": {"n_jobs": 0}}, r"cv.n_jobs = 0 must be >= 1, or -1"),
    ({"name": "x", "data": {"source": "web"}}, r"data.source = 'web' is not allowed; allowed: 'simulated', 'folder'"),
    ({"name": "x", "data": {"source": "folder"}}, r"data.source = 'folder' needs data.path"),
    ({"name": "x", "data": {"source": "folder", "path": "no/such/dir"}}, r"data.path = 'no/such/dir' does not exist"),
    ({"name": "x", "data": {"simulated": {"modes": ["walk", "swim"]}}}, r"data.simulated.modes has 'swim'.*allowed: walk, run"),
    ({"name": "x", "data": {"group": "height"}}, r"data.group = 'height' is not a column of simulated data"),
    ({"name": "x", "data": {"labels": ["walk", "jump"]}}, r"data.labels has 'jump', which is not in data.simulated.modes"),
    ({"name": "x", "sweep": {"windows.width": [1]}}, r"sweep key 'windows.width' is not a config key"),
    ({"name": "x", "sweep": {"windows.length_s": []}}, r"must be a non-empty array"),
    ({"name": "x", "sweep": {"windows.length_s": [1.0, "2"]}}, r"sweep.'windows.length_s' = '2' has the wrong type"),
    ({"name": "x", "sweep": {"features.set": ["all52", "paper35"]}}, r"'paper35' is not allowed"),
    ({"seed": 1}, r"the config has no name"),
    ({"name": "x", "model": {"params": {"C": -1}}}, r"model.params for 'linear-ovo-svm': `C` must be a positive number, got -1"),
    (
        {"name": "x", "data": {"simulated": {"subjects": 2.5}}},
        r"data.simulated.subjects = 2.5 has the wrong type \(float\); expected an integer\.",
    ),
    ({"name": "x", "data": {"simulated": {"duration_s": 1.0}}}, r"data.simulated.duration_s = 1.0 must be within 2-86400 s"),
    ({"name": "x", "data": {"simulated": {"duration_s": 1e7}}}, r"data.simulated.duration_s = 10000000.0 must be within"),
    ({"name": "x", "data": {"simulated": {"subjects": 5000}}}, r"data.simulated.subjects = 5000 must be within 1-1000"),
    (
        {"name": "x", "data": {"simulated": {"modes": ["walk"]}}},
        r"data.simulated.modes gives 1 class \(walk\); a classifier needs at least 2",
    ),
    ({"name": "x", "data": {"labels": ["run"]}}, r"data.labels gives 1 class \(run\)"),
    ({"name": "x", "data": {"label": "mode"}}, r"data.label = 'mode' is not a column of simulated data; allowed: 'label'"),
    ({"name": "x", "data": {"label": "position"}}, r"data.label = 'position' needs data.simulated.positions"),
    (
        {"name": "x", "data": {"label": "position", "simulated": {"positions": ["belt"]}}},
        r"data.simulated.positions gives 1 class \(belt\); a classifier needs at least 2: list at least two positions",
    ),
    (
        {"name": "x", "data": {"label": "position", "labels": ["walk", "belt"], "simulated": {"positions": ["belt", "bag"]}}},
        r"data.labels has 'walk', which is not in data.simulated.positions",
    ),
]


@pytest.mark.parametrize(("raw", "pattern"), BAD, ids=[str(i) for i in range(len(BAD))])
def test_bad_config_one_line_error(tmp_path, raw, pattern):
    with pytest.raises(ConfigError, match=pattern) as exc:
        parse_config(raw, base_dir=tmp_path)
    assert "\n" not in str(exc.value)


@pytest.mark.skipif(not torch_available(), reason="torch extra not installed")
@pytest.mark.parametrize(
    ("params", "pattern"),
    [
        ({"epochs": "ten"}, r"`epochs` must be a positive integer, got 'ten'"),
        ({"hidden": [8, 0]}, r"`hidden` must be a list of positive integers"),
        ({"dropout": 1.5}, r"`dropout` must be in \[0, 1\)"),
    ],
)
def test_bad_torch_params_fail_at_load(params, pattern):
    with pytest.raises(ConfigError, match=pattern):
        parse_config({"name": "x", "model": {"kind": "mlp", "params": params}})


def test_bad_toml_and_missing_file(tmp_path):
    with pytest.raises(ConfigError, match="config file not found"):
        load_config(tmp_path / "none.toml")
    p = tmp_path / "bad.toml"
    p.write_text("name = 'x'\n[windows\n")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_config(p)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("synth")
    write_synth_folder(d / "data", n_subjects=3, seconds_per_mode=6.0)
    return d


DATA_BAD = [
    ({"label": "colour"}, {}, r"data.label = 'colour' is not in the data: .*available: per-sample 'label', .*position"),
    ({"labels": ["walk", "fly"]}, {}, r"data.labels has 'fly', which is not a label of the data; labels present: run, side_left, walk"),
    ({"group": "room"}, {}, r"data.group = 'room' is not a meta/manifest column"),
    ({"group": "position", "where": {"position": "InHand"}}, {}, r"needs at least 2 groups, but data.group = 'position' has 1"),
    ({}, {"scheme": "group-kfold", "n_splits": 4}, r"n_splits = 4 needs at least 4 groups, but data.group = 'subject' has 3"),
    ({"where": {"room": "x"}}, {}, r"data.where key 'room' is not a meta/manifest column"),
    ({"where": {"position": "Purse"}}, {}, r"data.where = .* matches no recording; values present"),
    (
        {"label": "position", "where": {"position": "InHand"}},
        {},
        r"data.label = 'position' has 1 class in the data \(InHand\); a classifier needs at least 2",
    ),
]


@pytest.mark.parametrize(("data", "cv", "pattern"), DATA_BAD, ids=[str(i) for i in range(len(DATA_BAD))])
def test_data_dependent_errors_before_any_work(folder, data, cv, pattern):
    raw = {"name": "x", "data": {"source": "folder", "path": "data", **data}, "cv": cv}
    cfg = parse_config(raw, base_dir=folder)
    with pytest.raises(ConfigError, match=pattern) as exc:
        prepare_data(cfg, use_cache=False)
    assert "\n" not in str(exc.value)


def test_meta_label_gives_one_label_per_recording(folder):
    cfg = parse_config({"name": "x", "data": {"source": "folder", "path": "data", "label": "position", "group": "user"}}, base_dir=folder)
    data = prepare_data(cfg, use_cache=False)
    for r in data.recordings:
        assert set(r.labels) == {r.meta["position"]}
    assert sorted(set(data.groups)) == ["u0", "u1", "u2"]


def test_config_path_that_is_a_directory(tmp_path):
    with pytest.raises(ConfigError, match=r"is a directory, not a config file; pass a .toml file"):
        load_config(tmp_path)


def _gait(subject) -> tuple:
    """A subject's parameters without its name and pose (the pose is drawn last)."""
    import dataclasses

    return tuple(v for k, v in dataclasses.asdict(subject).items() if k not in ("subject", "pose"))


@pytest.mark.parametrize("config", ["demo.toml", "demo-acc.toml"])
def test_the_demo_model_never_saw_the_walkers_it_is_evaluated_on(config):
    """The shipped models are trained on other subjects than the PDR route table (seeds 0-19) and the demo walker."""
    from gaitml.demo import DEMO_SETTINGS
    from gaitml.simulate import sample_subjects

    cfg = load_config(ROOT / "experiments" / config)
    sim = cfg["data"]["simulated"]
    trained = {_gait(s) for s in sample_subjects(sim["subjects"], cfg.seed)}
    walkers = {seed: _gait(sample_subjects(1, seed)[0]) for seed in [*range(20), DEMO_SETTINGS["route_seed"]]}
    assert not [seed for seed, g in walkers.items() if g in trained]
    # and the check can fail: a seed-0 training set contains the walker of route seed 0
    assert walkers[0] in {_gait(s) for s in sample_subjects(sim["subjects"], 0)}


def test_simulated_sessions_and_pose_keys(tmp_path):
    text = (ROOT / "experiments" / "demo.toml").read_text()
    cfg = parse_config(tomllib.loads(text), base_dir=ROOT / "experiments")
    assert cfg["data"]["simulated"]["pose"] == "mixed"
    bad = text.replace('pose = "mixed"', 'pose = "upside-down"')
    with pytest.raises(ConfigError, match="data.simulated.pose"):
        parse_config(tomllib.loads(bad), base_dir=ROOT / "experiments")
    bad = text.replace('pose = "mixed"', 'pose = "mixed"\nsessions = 0')
    with pytest.raises(ConfigError, match="data.simulated.sessions"):
        parse_config(tomllib.loads(bad), base_dir=ROOT / "experiments")


def test_sessions_of_one_simulated_subject_are_the_groups():
    raw = {
        "name": "sessions",
        "data": {"source": "simulated", "group": "session", "simulated": {"subjects": 1, "sessions": 3, "duration_s": 20.0}},
        "cv": {"scheme": "leave-one-group-out", "n_jobs": 1},
    }
    data = prepare_data(parse_config(raw, base_dir=ROOT), use_cache=False)
    assert sorted({r.meta["session"] for r in data.recordings}) == ["S01-R1", "S01-R2", "S01-R3"]
