"""Model artifacts: a folder with ``model.joblib`` and ``model.json`` (DESIGN sec. 3).

``model.json`` records what is needed to use the model correctly and to trust
it: the gaitml, scikit-learn, numpy and torch versions, the model kind, the
feature set with its feature names in order (or the raw channels), the window
length and overlap, the sampling rate, the label set, the training config, the
cross-validation scores, the sha256 of ``model.joblib`` and ``settings_sha256``, the
sha256 of the canonical JSON of every other entry of ``model.json`` (sorted keys,
compact separators; the two hash fields left out), so that an edit of the settings
(say ``window.length_s``) is detected as well.

:func:`load_model` refuses (``ModelError``) a missing or unreadable file, a
hash mismatch (the joblib file was changed), a different gaitml/scikit-learn/
torch major.minor version, an edited ``model.json`` (settings hash mismatch), a
missing required entry, or a feature set whose names no longer match.

Security: ``model.joblib`` is a pickle. Loading a pickle runs code chosen by
whoever wrote it; load model folders only from sources you trust. The hash
check detects accidental corruption and edits that did not update
``model.json``; it is not a signature.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import hashlib
import json
import os
import platform
from pathlib import Path
from typing import Any

from gaitml.errors import ModelError

__all__ = ["TrainedModel", "save_model", "load_model", "library_versions", "sha256_file", "settings_sha256", "MODEL_FORMAT_VERSION"]

MODEL_FORMAT_VERSION = 1
JOBLIB_NAME = "model.joblib"
JSON_NAME = "model.json"
#: The entries of model.json that hold hashes (left out of the settings hash).
HASH_KEYS = ("sha256", "settings_sha256")
#: Entries a model.json must have to be used (``window`` also needs ``length_s`` and ``overlap``).
REQUIRED_KEYS = ("model_kind", "input_kind", "feature_set", "feature_names", "window", "sampling_rate_hz", "labels", "versions")


def settings_sha256(info: dict) -> str:
    """Hex sha256 of the canonical JSON of ``info`` without its hash entries.

    Canonical: ``json.dumps(..., sort_keys=True, separators=(",", ":"), ensure_ascii=True)``
    of the JSON-decoded settings, so the value does not depend on indentation or key order.
    """
    from gaitml.io._atomic import _json_default

    body = {k: v for k, v in info.items() if k not in HASH_KEYS}
    body = json.loads(json.dumps(body, default=_json_default))  # numpy scalars, tuples -> plain JSON
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def sha256_file(path: str | os.PathLike) -> str:
    """Hex sha256 of a file."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def library_versions(with_torch: bool) -> dict[str, str]:
    """Versions recorded in (and checked against) an artifact."""
    import numpy
    import sklearn

    import gaitml

    v = {"gaitml": gaitml.__version__, "scikit-learn": sklearn.__version__, "numpy": numpy.__version__, "python": platform.python_version()}
    if with_torch:
        import torch

        v["torch"] = torch.__version__
    return v


@dataclasses.dataclass
class TrainedModel:
    """A fitted estimator with the settings it needs (``info`` is model.json)."""

    estimator: Any
    info: dict
    path: Path | None = None

    @property
    def kind(self) -> str:
        return self.info["model_kind"]

    @property
    def input_kind(self) -> str:
        return self.info["input_kind"]

    @property
    def feature_set(self) -> str:
        return self.info["feature_set"]

    @property
    def feature_names(self) -> list[str]:
        return list(self.info["feature_names"])

    @property
    def raw_channels(self) -> list[str]:
        return list(self.info.get("raw_channels", []))

    @property
    def sampling_rate_hz(self) -> float:
        return float(self.info["sampling_rate_hz"])

    @property
    def length_s(self) -> float:
        return float(self.info["window"]["length_s"])

    @property
    def overlap(self) -> float:
        return float(self.info["window"]["overlap"])

    @property
    def labels(self) -> list[str]:
        return list(self.info["labels"])


def save_model(path: str | os.PathLike, estimator: Any, info: dict) -> TrainedModel:
    """Write a model folder atomically (a failed write leaves no half model).

    Parameters
    ----------
    path : folder to create or replace
    estimator : fitted gaitml estimator
    info : dict
        At least ``model_kind``, ``input_kind``, ``feature_set``,
        ``feature_names``, ``window`` (``length_s``, ``overlap``),
        ``sampling_rate_hz``, ``labels``; usually also ``training_config``,
        ``cv_scores``, ``n_train_windows``. Versions, the hash and the creation
        time are added here.
    """
    import joblib

    from gaitml.io import atomic_dir

    need = ("model_kind", "input_kind", "feature_set", "feature_names", "window", "sampling_rate_hz", "labels")
    missing = [k for k in need if k not in info]
    if missing:
        raise ModelError(f"model info lacks {', '.join(missing)}; pass them to save_model.")
    from gaitml.models._registry import TORCH_KINDS

    meta = {
        "format": "gaitml-model",
        "format_version": MODEL_FORMAT_VERSION,
        **info,
        "versions": library_versions(info["model_kind"] in TORCH_KINDS),
        "created_utc": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "security_note": "model.joblib is a pickle: load it only from a trusted source.",
    }
    target = Path(path)
    with atomic_dir(target) as tmp:
        joblib.dump(estimator, tmp / JOBLIB_NAME, compress=3)
        meta["sha256"] = sha256_file(tmp / JOBLIB_NAME)
        meta["settings_sha256"] = settings_sha256(meta)
        from gaitml.io._atomic import _json_default

        (tmp / JSON_NAME).write_text(json.dumps(meta, indent=2, default=_json_default) + "\n", encoding="utf-8")
    return TrainedModel(estimator=estimator, info=meta, path=target)


def _minor(v: str) -> str:
    return ".".join(str(v).split("+")[0].split(".")[:2])


def load_model(path: str | os.PathLike) -> TrainedModel:
    """Load a model folder after checking its hash, versions and feature set.

    Only load model folders from trusted sources: ``model.joblib`` is a pickle.

    Raises
    ------
    ModelError
        Missing folder or files, unreadable model.json, sha256 mismatch,
        different gaitml / scikit-learn / torch major.minor version, unknown
        model kind, or feature names that no longer match the feature set.
    """
    p = Path(path)
    if not p.is_dir():
        raise ModelError(f"model folder not found: {p}; train one with 'gaitml train CONFIG --out {p}'.")
    jpath, mpath = p / JSON_NAME, p / JOBLIB_NAME
    for f in (jpath, mpath):
        if not f.is_file():
            raise ModelError(f"{f.name} is missing from the model folder {p}; the artifact is incomplete, train it again.")
    try:
        info = json.loads(jpath.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"cannot read {jpath} ({exc}); the artifact is corrupt, train it again.") from exc
    if not isinstance(info, dict) or info.get("format") != "gaitml-model":
        raise ModelError(f"{jpath} is not a gaitml model description (no format = 'gaitml-model'); train the model again.")
    if info.get("format_version") != MODEL_FORMAT_VERSION:
        raise ModelError(
            f"model format version {info.get('format_version')!r} in {jpath} is not {MODEL_FORMAT_VERSION}; train the model again with this gaitml."
        )
    missing = [k for k in REQUIRED_KEYS if k not in info]
    if not missing and isinstance(info["window"], dict):
        missing = [f"window.{k}" for k in ("length_s", "overlap") if k not in info["window"]]
    elif not missing:
        missing = ["window (an object with length_s and overlap)"]
    if missing:
        raise ModelError(
            f"{jpath} lacks the required entry {', '.join(missing)}; the file was edited or is incomplete: retrain the model or restore model.json."
        )
    for key in HASH_KEYS:
        if not isinstance(info.get(key), str):
            raise ModelError(
                f"{jpath} has no {key} entry, so the model cannot be verified; retrain the model (gaitml train) or restore model.json."
            )
    digest = sha256_file(mpath)
    if digest != info.get("sha256"):
        raise ModelError(
            f"sha256 of {mpath.name} ({digest[:12]}...) does not match model.json ({str(info.get('sha256'))[:12]}...): "
            "the file was changed or corrupted; refusing to load it, train the model again."
        )
    if settings_sha256(info) != info["settings_sha256"]:
        raise ModelError(
            f"model.json was edited after training (its settings no longer match settings_sha256) in {p}; "
            "settings such as window.length_s cannot be changed after training: retrain or restore it."
        )
    from gaitml.models._registry import MODEL_KINDS, TORCH_KINDS

    kind = info.get("model_kind")
    if kind not in MODEL_KINDS:
        raise ModelError(f"model kind {kind!r} in {jpath} is unknown to this gaitml; known: {', '.join(MODEL_KINDS)}.")
    if kind in TORCH_KINDS:
        from gaitml.models._torch import require_torch

        require_torch(f"loading model kind {kind!r}")
    saved = info.get("versions") or {}
    current = library_versions(kind in TORCH_KINDS)
    for lib in ("gaitml", "scikit-learn", "torch"):
        if lib not in current:
            continue
        if lib not in saved:
            raise ModelError(
                f"model.json records no {lib} version although model kind {kind!r} needs {lib}; the artifact is inconsistent: "
                "retrain the model (gaitml train) or restore model.json."
            )
        if _minor(saved[lib]) != _minor(current[lib]):
            raise ModelError(
                f"the model was saved with {lib} {saved.get(lib, 'unknown')} but this is {lib} {current[lib]}; "
                f"retrain the model (gaitml train) or install {lib}=={saved[lib]}."
            )
    _check_feature_set(info, jpath)
    import joblib

    try:
        est = joblib.load(mpath)
    except Exception as exc:  # unpickling errors come in many types
        raise ModelError(f"cannot load {mpath} ({type(exc).__name__}: {exc}); the artifact is corrupt, train it again.") from exc
    n_in = getattr(est, "n_features_in_", None)
    if info.get("input_kind") == "features" and n_in is not None and n_in != len(info["feature_names"]):
        raise ModelError(
            f"the estimator takes {n_in} features but model.json lists {len(info['feature_names'])}; the artifact is inconsistent, train it again."
        )
    return TrainedModel(estimator=est, info=info, path=p)


def _check_feature_set(info: dict, jpath: Path) -> None:
    if info.get("input_kind") not in ("features", "raw"):
        raise ModelError(f"input_kind {info.get('input_kind')!r} in {jpath} must be 'features' or 'raw'; train the model again.")
    fset = info.get("feature_set")
    if info["input_kind"] == "raw":
        return
    from gaitml.features import FEATURE_SETS, feature_names

    if fset not in FEATURE_SETS:
        raise ModelError(f"feature set {fset!r} in {jpath} is unknown to this gaitml; known: {', '.join(FEATURE_SETS)}. Retrain the model.")
    now = list(feature_names(fset))
    saved = list(info.get("feature_names") or [])
    if now != saved:
        diff = next(
            (f"position {i}: saved {a!r}, now {b!r}" for i, (a, b) in enumerate(zip(saved, now, strict=False)) if a != b),
            f"saved {len(saved)} names, now {len(now)}",
        )
        raise ModelError(f"the model's feature names do not match feature set {fset!r} of this gaitml ({diff}); retrain the model.")
