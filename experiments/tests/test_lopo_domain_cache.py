"""experiments.scripts.lopo_domain --cache: the cached simulated windows are keyed on the code that made them."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import gaitml
from experiments.scripts import lopo_domain as ld

PACKAGE = Path(gaitml.__file__).parent


def _copy_sources(dst: Path) -> Path:
    for rel in ld.CACHE_SOURCES:
        src = PACKAGE / rel
        if src.is_dir():
            shutil.copytree(src, dst / rel, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            (dst / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst / rel)
    return dst


def test_the_key_changes_with_the_simulator_and_feature_sources(tmp_path):
    root = _copy_sources(tmp_path / "gaitml")
    key = ld.cache_key()
    assert ld.cache_key(root) == key  # same sources, same version: same key
    (root / "cli.py").write_text("# not a source of the cached windows\n")
    assert ld.cache_key(root) == key
    sim = root / "simulate" / "subject.py"
    sim.write_text(sim.read_text() + "\n# a changed simulator\n")
    changed = ld.cache_key(root)
    assert changed != key
    feat = root / "features" / "_extract.py"
    feat.write_text(feat.read_text() + "\n# changed features\n")
    assert ld.cache_key(root) not in (key, changed)


def test_the_key_changes_with_the_version(monkeypatch):
    key = ld.cache_key()
    monkeypatch.setattr(gaitml, "__version__", gaitml.__version__ + ".post1")
    assert ld.cache_key() != key


def test_a_cache_is_read_only_under_its_own_key(tmp_path):
    arrays = {"tr_y": np.array(["walk", "run"]), "tr_X_phone": np.arange(6.0).reshape(2, 3)}
    ld.save_cache(tmp_path, "k1", arrays)
    hit = ld.load_cache(tmp_path, "k1")
    assert set(hit) == set(arrays) and np.array_equal(hit["tr_X_phone"], arrays["tr_X_phone"])
    assert ld.load_cache(tmp_path, "k2") is None
    np.savez(tmp_path / ld.CACHE_FILE, **arrays)  # a cache of the old unkeyed format
    assert ld.load_cache(tmp_path, "k1") is None
    assert ld.load_cache(tmp_path / "empty", "k1") is None


class _Simulated(Exception):
    pass


def test_build_simulates_again_when_the_key_changed(tmp_path, monkeypatch):
    import gaitml.simulate

    def refuse(*args, **kwargs):
        raise _Simulated

    monkeypatch.setattr(gaitml.simulate, "simulate_dataset", refuse)
    arrays = {"te_y": np.array(["walk"])}
    monkeypatch.setattr(ld, "cache_key", lambda root=None: "simulator v1")
    ld.save_cache(tmp_path, "simulator v1", arrays)
    assert np.array_equal(ld.build(tmp_path)["te_y"], arrays["te_y"])  # a hit: nothing simulated
    monkeypatch.setattr(ld, "cache_key", lambda root=None: "simulator v2")
    with pytest.raises(_Simulated):
        ld.build(tmp_path)  # the stale cache is not used
