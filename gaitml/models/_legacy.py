"""Conversion of an old pickle model (``format_version`` 1, ``model.joblib``) to the data-only format.

This module is the only place in gaitml that unpickles a model, and only when a
user runs ``gaitml model convert OLD_DIR NEW_DIR`` (or :func:`convert_model`) on a
model they trust: unpickling runs whatever code the file names. The old
artifact's checks (sha256 of ``model.joblib``, settings hash, library versions,
feature set) run before the pickle is opened, as the old ``load_model`` did.
After conversion the new folder is loaded back through the data-only
:func:`~gaitml.models.load_model` and must predict the same labels as the
unpickled estimator on probe inputs drawn around the training mean.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from gaitml.errors import ModelError
from gaitml.models._persist import (
    JSON_NAME,
    LEGACY_NAME,
    TrainedModel,
    _check_feature_set,
    check_versions,
    load_model,
    save_model,
    settings_sha256,
    sha256_file,
)

__all__ = ["convert_model", "load_legacy_model"]

#: Entries of a format-1 model.json that the new format replaces.
_DROP = ("format", "format_version", "sha256", "settings_sha256", "versions", "created_utc", "security_note")


def load_legacy_model(path: str | os.PathLike) -> TrainedModel:
    """Check and UNPICKLE a format-1 model folder. Only for models from a trusted source.

    Raises
    ------
    ModelError
        Not a format-1 folder, a hash mismatch (``model.joblib`` or ``model.json``
        changed), other library versions, or an unreadable pickle.
    """
    p = Path(path)
    jpath, mpath = p / JSON_NAME, p / LEGACY_NAME
    if not jpath.is_file():
        raise ModelError(f"{jpath} not found; 'gaitml model convert' takes an old model folder with model.json and model.joblib.")
    try:
        info = json.loads(jpath.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"cannot read {jpath} ({exc}); the old model is corrupt.") from exc
    if not isinstance(info, dict) or info.get("format") != "gaitml-model" or info.get("format_version") != 1:
        raise ModelError(f"{jpath} is not an old (format_version 1) gaitml model; a current model needs no conversion.")
    if not mpath.is_file():
        raise ModelError(f"{mpath} not found; 'gaitml model convert' takes an old model folder with model.json and model.joblib.")
    for key in ("sha256", "settings_sha256"):
        if not isinstance(info.get(key), str):
            raise ModelError(f"{jpath} has no {key} entry, so the old model cannot be verified; it cannot be converted.")
    digest = sha256_file(mpath)
    if digest != info["sha256"]:
        raise ModelError(
            f"sha256 of {mpath.name} ({digest[:12]}...) does not match model.json: the file was changed; refusing to unpickle it."
        )
    body = {k: v for k, v in info.items() if k not in ("sha256", "settings_sha256")}
    if settings_sha256(body) != info["settings_sha256"]:
        raise ModelError(f"model.json in {p} was edited after training (settings_sha256 mismatch); refusing to convert it.")
    check_versions(info)
    _check_feature_set(info, jpath)
    import joblib

    try:
        est = joblib.load(mpath)  # the one unpickling in gaitml: trusted models only
    except Exception as exc:  # unpickling errors come in many types
        raise ModelError(f"cannot unpickle {mpath} ({type(exc).__name__}: {exc}); the old model is corrupt.") from exc
    return TrainedModel(estimator=est, info=info, path=p)


def _probe_inputs(est, n: int = 256) -> np.ndarray:
    """Inputs around the training mean (within +-3 scale) to compare old and new predictions."""
    rng = np.random.default_rng(0)
    mean, scale = np.asarray(est.mean_, dtype=float), np.asarray(est.scale_, dtype=float)
    if hasattr(est, "window_shape_"):
        shape = tuple(est.window_shape_)
        return mean + scale * rng.uniform(-3, 3, size=(n, *shape))
    return mean + scale * rng.uniform(-3, 3, size=(n, len(mean)))


def convert_model(old_dir: str | os.PathLike, new_dir: str | os.PathLike) -> TrainedModel:
    """Convert a trusted format-1 pickle model to a data-only model folder.

    The settings, training config and scores are kept; ``created_utc`` keeps the
    training time and ``converted_from`` records the old format, its sha256 and
    versions. The new folder gets a ``MODEL.md``.

    Returns
    -------
    TrainedModel
        The new model, loaded back through :func:`~gaitml.models.load_model`.

    Raises
    ------
    ModelError
        The old folder fails its checks, or ``new_dir`` is ``old_dir``, or the
        converted model predicts differently from the unpickled one.
    """
    src, dst = Path(old_dir), Path(new_dir)
    if dst.resolve() == src.resolve():
        raise ModelError(f"NEW_DIR is the old model folder {src}; give another folder, e.g. {src}-v2.")
    old = load_legacy_model(src)
    info = {k: v for k, v in old.info.items() if k not in _DROP}
    info["converted_from"] = {
        "format_version": 1,
        "file": LEGACY_NAME,
        "sha256": old.info["sha256"],
        "versions": old.info.get("versions"),
    }
    save_model(dst, old.estimator, info, created_utc=old.info.get("created_utc"))
    new = load_model(dst)
    X = _probe_inputs(old.estimator)
    if not np.array_equal(np.asarray(old.estimator.predict(X)), np.asarray(new.estimator.predict(X))):
        import shutil

        shutil.rmtree(dst, ignore_errors=True)
        raise ModelError(f"the converted model in {dst} predicts differently from {src}; it was removed. Retrain the model instead.")
    return new
