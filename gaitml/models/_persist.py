"""Model artifacts: a folder of data-only files that loading never unpickles (DESIGN sec. 3).

Layout (``format_version`` 2)::

    MODEL_DIR/
      model.json   settings, versions, the estimator's class, parameters and fitted
                   scalars, ``files`` (sha256 of every data file), ``settings_sha256``
      arrays.npz   the fitted arrays (scaler mean and scale, weights, intercepts,
                   class pairs, classes) as a numpy .npz, read with allow_pickle=False
      weights.pt   torch kinds only: the network's state_dict, read with
                   torch.load(weights_only=True); the architecture comes from the
                   parameters in model.json
      MODEL.md     the model card (documentation generated from model.json; not read)

``model.json`` also records ``feature_frame`` (``"phone"`` or ``"gravity"``,
:mod:`gaitml.features._frame`; absent in older models = ``"phone"``) and, for models
trained since the domain record exists, ``domain`` (:mod:`gaitml.models.domain`):
its arrays are stored in ``arrays.npz`` under names starting ``domain__`` and are
read with the same ``allow_pickle=False``. A model trained with ``[features]
acc_range_ms2`` records ``acc_range_ms2``: the accelerometer range per axis (m/s^2)
every recording is read through before its features and its domain check
(:mod:`gaitml.features._range`); a model without the key reads the accelerometer
as it comes.

``model.json`` records what is needed to use the model correctly and to trust it:
the gaitml, scikit-learn, numpy and torch versions, the model kind, the feature
set with its feature names in order (or the raw channels), the window length and
overlap, the sampling rate, the label set, the training config, the
cross-validation scores, the sha256 of every data file and ``settings_sha256``,
the sha256 of the canonical JSON of every other entry of ``model.json`` (sorted
keys, compact separators; the two hash entries left out), so that an edit of the
settings (say ``window.length_s``) is detected as well.

:func:`load_model` refuses (``ModelError``) a missing or unreadable file, a hash
mismatch, a different gaitml/scikit-learn/torch major.minor version, an edited
``model.json``, a missing required entry, a feature set whose names no longer
match, and an old pickle model (``format_version`` 1, ``model.joblib``), naming
the one-line conversion ``gaitml model convert OLD_DIR NEW_DIR`` (see
:mod:`gaitml.models._legacy`, the only code that unpickles, for trusted models).

Security: loading reads numbers only. ``arrays.npz`` must be a zip of ``.npy``
arrays and is opened with ``allow_pickle=False``; ``weights.pt`` must be a torch
zip archive and is opened with ``weights_only=True`` (torch's restricted
unpickler, which accepts tensors and containers only). No file of the folder is
passed to ``pickle`` or ``joblib``. The hashes detect corruption and edits; they
are not a signature.
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

import numpy as np

from gaitml.errors import ModelError

__all__ = [
    "TrainedModel",
    "save_model",
    "load_model",
    "library_versions",
    "sha256_file",
    "settings_sha256",
    "MODEL_FORMAT_VERSION",
    "legacy_message",
]

MODEL_FORMAT_VERSION = 2
JSON_NAME = "model.json"
ARRAYS_NAME = "arrays.npz"
TORCH_NAME = "weights.pt"
CARD_NAME = "MODEL.md"
#: The pickle of format version 1 (never read by load_model).
LEGACY_NAME = "model.joblib"
#: The entries of model.json that hold hashes (left out of the settings hash).
HASH_KEYS = ("files", "settings_sha256")
#: Entries a model.json must have to be used (``window`` also needs ``length_s`` and ``overlap``).
REQUIRED_KEYS = (
    "model_kind",
    "input_kind",
    "feature_set",
    "feature_names",
    "window",
    "sampling_rate_hz",
    "labels",
    "versions",
    "estimator",
)
SECURITY_NOTE = (
    "data-only model: arrays.npz is read with numpy (allow_pickle=False) and weights.pt, if any, with torch.load(weights_only=True); "
    "loading runs no code from the folder. The sha256 entries detect changes; they are not a signature."
)
_ZIP_MAGIC = b"PK\x03\x04"


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


def legacy_message(path: str | os.PathLike) -> str:
    """The one-line refusal of an old pickle model, naming the conversion command."""
    p = Path(path)
    new = p.with_name(p.name + "-v2")
    return (
        f"{p} is an old pickle model (model.joblib), which gaitml no longer loads because unpickling can run code; "
        f"if you trust its source, convert it once with: gaitml model convert {p} {new}"
    )


@dataclasses.dataclass
class TrainedModel:
    """A fitted estimator with the settings it needs (``info`` is model.json)."""

    estimator: Any
    info: dict
    path: Path | None = None
    #: :class:`gaitml.models.domain.DomainModel`, or None for a model saved without a domain record.
    domain: Any = None

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
    def frame(self) -> str:
        """Feature frame the model was trained in (``'phone'`` for models that do not record one)."""
        return str(self.info.get("feature_frame", "phone"))

    @property
    def acc_range_ms2(self) -> float | None:
        """The accelerometer range (m/s^2 per axis) the model reads every phone through, or None (:mod:`gaitml.features._range`)."""
        v = self.info.get("acc_range_ms2")
        return None if v is None else float(v)

    def rate_reason(self, recorded_hz: float | None) -> str | None:
        """The rate check of a recording made at ``recorded_hz`` (:func:`gaitml.models.rate_reason`)."""
        from gaitml.models._predict import rate_reason

        return rate_reason(self, recorded_hz)

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

    @property
    def window_by(self) -> str:
        """``'time'``, ``'steps'`` or ``'strides'`` (models saved before step windows: ``'time'``)."""
        return str(self.info["window"].get("by", "time"))

    @property
    def window_detector(self) -> str:
        """The step / zero-velocity detector of a step-window model ('' for time windows)."""
        return str(self.info["window"].get("detector", "") or "")


def _plain_array(name: str, a) -> np.ndarray:
    """``a`` as an array numpy can save without pickle (object arrays of str become unicode)."""
    arr = np.asarray(a)
    if arr.dtype == object:
        try:
            arr = np.asarray(arr.tolist())
        except Exception:  # noqa: BLE001 - any failure means: not plain data
            pass
    if arr.dtype == object or arr.dtype.kind not in "biufU":
        raise ModelError(
            f"fitted array {name} has dtype {arr.dtype}, which cannot be saved without pickle; use str or numeric class labels."
        )
    return arr


def _json_params(est) -> dict:
    """Constructor parameters as JSON values (a RandomState instance is recorded as None)."""
    out = {}
    for k, v in est.get_params(deep=False).items():
        if isinstance(v, np.random.RandomState):
            v = None
        elif isinstance(v, tuple):
            v = list(v)
        elif isinstance(v, np.generic):
            v = v.item()
        out[k] = v
    json.dumps(out)  # fails loudly on anything else
    return out


def _params_from_json(kind: str, params: dict) -> dict:
    p = dict(params)
    for k in ("hidden", "channels"):
        if isinstance(p.get(k), list):
            p[k] = tuple(p[k])
    return p


def save_model(
    path: str | os.PathLike, estimator: Any, info: dict, *, created_utc: str | None = None, card: bool = True, domain: Any = None
) -> TrainedModel:
    """Write a data-only model folder atomically (a failed write leaves no half model).

    Parameters
    ----------
    path : folder to create or replace
    estimator : fitted gaitml estimator (a kind of :data:`gaitml.models.MODEL_KINDS`)
    info : dict
        At least ``model_kind``, ``input_kind``, ``feature_set``,
        ``feature_names``, ``window`` (``length_s``, ``overlap``),
        ``sampling_rate_hz``, ``labels``; usually also ``training_config``,
        ``training_data``, ``cv_scores``. Versions, the estimator's state, the
        hashes and the creation time are added here.
    created_utc : str, optional
        Creation time to record (``gaitml model convert`` keeps the training time).
    card : bool, default True
        Also write ``MODEL.md`` (:func:`gaitml.models.model_card`).
    domain : DomainModel, optional
        The training domain (:func:`gaitml.models.domain.fit_domain`): its description
        goes to ``model.json`` key ``domain``, its arrays to ``arrays.npz`` (``domain__*``).
    """
    from gaitml.io import atomic_dir
    from gaitml.io._atomic import _json_default
    from gaitml.models._registry import MODEL_KINDS, TORCH_KINDS

    need = ("model_kind", "input_kind", "feature_set", "feature_names", "window", "sampling_rate_hz", "labels")
    missing = [k for k in need if k not in info]
    if missing:
        raise ModelError(f"model info lacks {', '.join(missing)}; pass them to save_model.")
    kind = info["model_kind"]
    cls = MODEL_KINDS.get(kind)
    if cls is None or type(estimator) is not cls:
        raise ModelError(
            f"save_model takes a fitted {getattr(cls, '__name__', kind)} for model kind {kind!r}, got {type(estimator).__name__}."
        )
    is_torch = kind in TORCH_KINDS
    state = estimator._get_state()
    scalars, arrays = state[0], {k: _plain_array(k, v) for k, v in state[1].items()}
    # ---- domain record (gaitml.models.domain): a JSON entry plus plain arrays
    if domain is not None:
        from gaitml.models.domain import ARRAY_PREFIX

        if any(k.startswith(ARRAY_PREFIX) for k in arrays):
            raise ModelError(f"estimator arrays must not start with {ARRAY_PREFIX!r}; rename them.")
        arrays.update({k: _plain_array(k, v) for k, v in domain.to_arrays().items()})
        info = {**info, "domain": domain.to_json()}
    meta = {
        "format": "gaitml-model",
        "format_version": MODEL_FORMAT_VERSION,
        **{k: v for k, v in info.items() if k not in (*HASH_KEYS, "format", "format_version", "versions", "created_utc", "estimator")},
        "estimator": {"class": cls.__name__, "params": _json_params(estimator), "state": scalars},
        "versions": library_versions(is_torch),
        "created_utc": created_utc or _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "security_note": SECURITY_NOTE,
    }
    target = Path(path)
    with atomic_dir(target) as tmp:
        np.savez_compressed(tmp / ARRAYS_NAME, **arrays)
        files = {ARRAYS_NAME: sha256_file(tmp / ARRAYS_NAME)}
        if is_torch:
            import torch

            torch.save(state[2], tmp / TORCH_NAME)
            files[TORCH_NAME] = sha256_file(tmp / TORCH_NAME)
        meta["files"] = files
        meta["settings_sha256"] = settings_sha256(meta)
        (tmp / JSON_NAME).write_text(json.dumps(meta, indent=2, default=_json_default) + "\n", encoding="utf-8")
        if card:
            from gaitml.models._card import model_card

            (tmp / CARD_NAME).write_text(model_card(meta), encoding="utf-8")
    return TrainedModel(estimator=estimator, info=meta, path=target, domain=domain)


def _minor(v: str) -> str:
    return ".".join(str(v).split("+")[0].split(".")[:2])


def read_model_json(path: str | os.PathLike) -> tuple[Path, dict]:
    """Read and check a model folder's ``model.json`` and the sha256 of its data files (none is opened).

    Used by ``gaitml model card``; :func:`load_model` runs the same checks.
    """
    p, info = _read_info(path)
    _verify_files(p, info)
    return p, info


def _read_info(path: str | os.PathLike) -> tuple[Path, dict]:
    """Read ``model.json``: format, old pickle model refused (:func:`legacy_message`), required entries, settings hash."""
    p = Path(path)
    if not p.is_dir():
        raise ModelError(f"model folder not found: {p}; train one with 'gaitml train CONFIG --out {p}'.")
    jpath = p / JSON_NAME
    if not jpath.is_file():
        raise ModelError(f"{jpath.name} is missing from the model folder {p}; the artifact is incomplete, train it again.")
    try:
        info = json.loads(jpath.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"cannot read {jpath} ({exc}); the artifact is corrupt, train it again.") from exc
    if not isinstance(info, dict) or info.get("format") != "gaitml-model":
        raise ModelError(f"{jpath} is not a gaitml model description (no format = 'gaitml-model'); train the model again.")
    version = info.get("format_version")
    if version == 1 or (version != MODEL_FORMAT_VERSION and (p / LEGACY_NAME).exists()):
        raise ModelError(legacy_message(p))
    if version != MODEL_FORMAT_VERSION:
        raise ModelError(
            f"model format version {version!r} in {jpath} is not {MODEL_FORMAT_VERSION}; train the model again with this gaitml."
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
    if not isinstance(info.get("settings_sha256"), str) or not isinstance(info.get("files"), dict):
        key = "settings_sha256" if not isinstance(info.get("settings_sha256"), str) else "files"
        raise ModelError(
            f"{jpath} has no {key} entry, so the model cannot be verified; retrain the model (gaitml train) or restore model.json."
        )
    if settings_sha256(info) != info["settings_sha256"]:
        raise ModelError(
            f"model.json was edited after training (its settings no longer match settings_sha256) in {p}; "
            "settings such as window.length_s cannot be changed after training: retrain or restore it."
        )
    return p, info


def _verify_files(p: Path, info: dict) -> None:
    """The data files listed in ``files`` are exactly the kind's, present, with matching sha256."""
    from gaitml.models._registry import TORCH_KINDS

    expected = {ARRAYS_NAME} | ({TORCH_NAME} if info.get("model_kind") in TORCH_KINDS else set())
    if set(info["files"]) != expected or not all(isinstance(v, str) for v in info["files"].values()):
        raise ModelError(
            f"model.json in {p} lists the files {sorted(info['files'])} but model kind {info.get('model_kind')!r} has {sorted(expected)}; "
            "the artifact is inconsistent: retrain the model."
        )
    for name in sorted(expected):
        f = p / name
        if not f.is_file():
            raise ModelError(f"{name} is missing from the model folder {p}; the artifact is incomplete, train it again.")
        digest = sha256_file(f)
        if digest != info["files"][name]:
            raise ModelError(
                f"sha256 of {name} ({digest[:12]}...) does not match model.json ({info['files'][name][:12]}...): "
                "the file was changed or corrupted; refusing to load it, train the model again."
            )


def check_versions(info: dict) -> None:
    """Refuse a model saved with another gaitml / scikit-learn / torch major.minor version."""
    from gaitml.models._registry import MODEL_KINDS, TORCH_KINDS

    kind = info.get("model_kind")
    if kind not in MODEL_KINDS:
        raise ModelError(f"model kind {kind!r} in model.json is unknown to this gaitml; known: {', '.join(MODEL_KINDS)}.")
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


def max_array_elements(info: dict) -> int:
    """The most elements any array of a model can hold, from its model.json.

    With ``D`` inputs (feature names, or raw samples x channels) and ``L``
    labels, the largest arrays are the domain record's per-class precision
    matrices (``L x D x D``); nothing a model saves is larger than
    ``(L + 1) D^2`` plus a fixed allowance (:data:`_ARRAY_SLACK`).
    """
    window = info.get("window") or {}
    raw = len(info.get("raw_channels") or []) * int(window.get("length_samples") or 0)
    d = max(len(info.get("feature_names") or []), raw, 1)
    n_labels = len(info.get("labels") or [])
    return (n_labels + 1) * d * d + _ARRAY_SLACK


#: Elements any model array may hold beyond (L + 1) D^2 (small tables: gravity directions, pairs...).
_ARRAY_SLACK = 1_000_000


def check_npz_sizes(path: Path, max_elements: int) -> None:
    """Refuse an .npz member larger than its declared shape, or declaring more than ``max_elements``, before decompressing it.

    Reads the zip's central directory (each member's uncompressed size) and the
    ``.npy`` header of each member (its shape and dtype; a few hundred bytes):
    a member whose size is not its header plus ``prod(shape) x itemsize``, or
    whose shape is beyond what the model.json allows, is refused. ``np.load``
    would otherwise inflate a 5 MB archive into gigabytes of zeros.
    """
    import zipfile

    try:
        with zipfile.ZipFile(path) as zf:
            for zi in zf.infolist():
                with zf.open(zi) as fh:
                    version = np.lib.format.read_magic(fh)
                    read_header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
                    shape, _fortran, dtype = read_header(fh)
                    header_len = fh.tell()
                n = int(np.prod(shape, dtype=np.float64)) if len(shape) else 1
                if n > max_elements:
                    raise ModelError(
                        f"{path.name} member {zi.filename} declares an array of shape {tuple(shape)} ({n:.3g} values), more than the "
                        f"model.json allows ({max_elements:.3g}); the artifact is corrupt or was replaced: train the model again."
                    )
                if header_len + n * dtype.itemsize != zi.file_size:
                    raise ModelError(
                        f"{path.name} member {zi.filename} holds {zi.file_size} bytes but its header declares {tuple(shape)} {dtype} "
                        f"({header_len + n * dtype.itemsize} bytes); the artifact is corrupt or was replaced: train the model again."
                    )
    except ModelError:
        raise
    except (zipfile.BadZipFile, ValueError, OSError, EOFError) as exc:
        raise ModelError(f"cannot read {path} as plain arrays ({' '.join(str(exc).split())}); train the model again.") from exc


def _read_npz(path: Path, max_elements: int | None = None) -> dict[str, np.ndarray]:
    """The arrays of an .npz, refusing anything that is not a zip of plain .npy arrays (sizes checked first)."""
    with open(path, "rb") as f:
        if f.read(4) != _ZIP_MAGIC:
            raise ModelError(f"{path} is not a numpy .npz archive; the artifact is corrupt or was replaced: train the model again.")
    if max_elements is not None:
        check_npz_sizes(path, max_elements)
    try:
        with np.load(path, allow_pickle=False) as z:
            return {k: z[k] for k in z.files}
    except (ValueError, OSError, KeyError) as exc:
        raise ModelError(f"cannot read {path} as plain arrays ({' '.join(str(exc).split())}); train the model again.") from exc


def _read_torch_state(path: Path) -> dict:
    """A torch state_dict, read with ``weights_only=True`` (tensors and containers only)."""
    import torch

    with open(path, "rb") as f:
        if f.read(4) != _ZIP_MAGIC:
            raise ModelError(f"{path} is not a torch weights archive; the artifact is corrupt or was replaced: train the model again.")
    try:
        state = torch.load(path, map_location="cpu", weights_only=True)
    except Exception as exc:  # torch raises UnpicklingError, RuntimeError... for refused content
        raise ModelError(
            f"cannot read {path} as weights only ({type(exc).__name__}); the file holds more than tensors: train the model again."
        ) from exc
    if not isinstance(state, dict) or not all(isinstance(k, str) and isinstance(v, torch.Tensor) for k, v in state.items()):
        raise ModelError(f"{path} is not a state_dict of named tensors; train the model again.")
    return state


def load_model(path: str | os.PathLike) -> TrainedModel:
    """Load a data-only model folder after checking its hashes, versions and feature set.

    Nothing is unpickled: the arrays come from ``arrays.npz`` (``allow_pickle=False``),
    torch weights from ``weights.pt`` (``torch.load(weights_only=True)``), the
    estimator is rebuilt from its class and parameters in ``model.json``.

    Raises
    ------
    ModelError
        Missing folder or files, unreadable model.json, sha256 mismatch, an edited
        model.json, different gaitml / scikit-learn / torch major.minor version,
        unknown model kind, feature names that no longer match the feature set,
        or an old pickle model (the message names ``gaitml model convert``).
    """
    from gaitml.models._registry import MODEL_KINDS, TORCH_KINDS

    p, info = _read_info(path)
    check_versions(info)
    _check_feature_set(info, p / JSON_NAME)
    _verify_files(p, info)
    kind = info["model_kind"]
    cls = MODEL_KINDS[kind]
    spec = info["estimator"]
    if not isinstance(spec, dict) or spec.get("class") != cls.__name__:
        raise ModelError(
            f"model.json in {p} describes estimator {spec.get('class') if isinstance(spec, dict) else spec!r}, not {cls.__name__}; retrain the model."
        )
    arrays = _read_npz(p / ARRAYS_NAME, max_array_elements(info))
    from gaitml.models.domain import ARRAY_PREFIX, domain_from_model_info

    domain_arrays = {k: v for k, v in arrays.items() if k.startswith(ARRAY_PREFIX)}
    arrays = {k: v for k, v in arrays.items() if not k.startswith(ARRAY_PREFIX)}
    domain = domain_from_model_info(info, domain_arrays)
    try:
        params = _params_from_json(kind, spec.get("params") or {})
        if kind in TORCH_KINDS:
            est = cls._from_state(params, spec.get("state") or {}, arrays, _read_torch_state(p / TORCH_NAME))
        else:
            est = cls._from_state(params, spec.get("state") or {}, arrays)
    except ModelError:
        raise
    except (KeyError, TypeError, ValueError, RuntimeError) as exc:
        raise ModelError(
            f"the arrays of {p} do not fit its model.json ({type(exc).__name__}: {' '.join(str(exc).split())[:200]}); train the model again."
        ) from exc
    n_in = getattr(est, "n_features_in_", None)
    if info.get("input_kind") == "features" and n_in is not None and n_in != len(info["feature_names"]):
        raise ModelError(
            f"the estimator takes {n_in} features but model.json lists {len(info['feature_names'])}; the artifact is inconsistent, train it again."
        )
    return TrainedModel(estimator=est, info=info, path=p, domain=domain)


def _check_feature_set(info: dict, jpath: Path) -> None:
    if info.get("input_kind") not in ("features", "raw"):
        raise ModelError(f"input_kind {info.get('input_kind')!r} in {jpath} must be 'features' or 'raw'; train the model again.")
    fset = info.get("feature_set")
    from gaitml.features import FEATURE_FRAMES

    if info.get("feature_frame", "phone") not in FEATURE_FRAMES:
        raise ModelError(
            f"feature_frame {info.get('feature_frame')!r} in {jpath} is unknown to this gaitml; known: {', '.join(FEATURE_FRAMES)}. Retrain the model."
        )
    if info.get("acc_range_ms2") is not None:
        from gaitml.errors import InputError
        from gaitml.features import check_acc_range

        try:
            if check_acc_range(info["acc_range_ms2"]) is None:
                raise InputError("0 is written as no key")
        except InputError:
            raise ModelError(
                f"acc_range_ms2 {info['acc_range_ms2']!r} in {jpath} is not an accelerometer range (a number >= 9.81 m/s^2); retrain the model."
            ) from None
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
