"""`gaitml demo` cross-validates the pipeline the shipped model was trained with (features and windows)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _shipped_config() -> dict:
    path = ROOT / "models" / "demo" / "model.json"
    if not path.is_file():
        pytest.skip(f"no shipped model at {path}")
    doc = json.loads(path.read_text(encoding="utf-8"))

    def find(d):
        if isinstance(d, dict):
            if "features" in d and "windows" in d and isinstance(d["features"], dict):
                return d
            for v in d.values():
                got = find(v)
                if got is not None:
                    return got
        return None

    cfg = find(doc)
    if cfg is None:
        pytest.skip("the shipped model's card holds no training config")
    return cfg


def test_the_demo_uses_the_shipped_models_features_and_windows(tmp_path):
    from gaitml.demo import DEMO_SETTINGS, _config

    shipped = _shipped_config()
    (tmp_path / "data").mkdir()
    cfg = _config(tmp_path / "data", tmp_path, DEMO_SETTINGS)
    assert cfg["features"]["set"] == shipped["features"]["set"]
    assert cfg["windows"]["length_s"] == shipped["windows"]["length_s"]
    assert cfg["windows"]["overlap"] == shipped["windows"]["overlap"]
