"""Experiment configs: TOML (``tomllib``) validated into dataclasses (DESIGN sec. 3).

Every key is checked against a schema before any work starts: unknown keys,
wrong types and values outside the allowed set raise :class:`ConfigError`
naming the key, the bad value and what is allowed. Paths are relative to the
config file. Checks that need the data (label present, enough groups) are done
by :func:`gaitml.pipeline.runner.prepare_data`, still before any training.

Every committed config (``experiments/*.toml``) follows this one schema. The
names a key may take (features, model kinds, cross-validation schemes, step
detectors) come from the package's registries, so a new entry there is valid
here without an edit.

Keys (defaults in brackets) of ``task = "classification"``::

    name = "..."                     # required; run folder runs/<name>/<timestamp>/
    seed = 0
    description = ""
    task = "classification"          # | "steps" (below)
    [data]
    source = "simulated"             # "simulated" | "folder"
    path = "../data/set"             # "folder": any data set the readers understand
    label = "label"                  # per-sample label, or a meta/manifest column (one label per recording);
                                     # simulated: "label" (the mode) or "position" (needs data.simulated.positions)
    group = "subject"                # meta/manifest column: cross-validation groups
    labels = []                      # keep only these labels (others dropped and reported)
    resample_hz = 50.0               # every recording is resampled to this rate
    where = {}                       # keep recordings whose meta matches, e.g. { surface = "Hard" }
    add_simulated = false            # "folder": also simulate [data.simulated] and add those recordings
                                     # (real and simulated windows in one training set; groups from data.group)
    manifest = ""                    # "folder": the manifest in data.path (default: manifest.csv when present;
                                     # a name given here must exist). Columns: gaitml.pipeline.folder_source
    [data.labelling]                 # "folder": recordings with an intervals file are labelled by gaitml.labels
    snap = "steps"                   # "steps" | "strides" | "none": boundaries snap to detected steps / strides
    detector = ""                    # the step (or, for strides, zero-velocity) detector; default adaptive
                                     # (gaitml.consts.DEFAULT_STEP_DETECTOR) / pseudo-std
    max_snap_s = 0.5
    rule = "change"                  # "change": a boundary moves only to evidence of the mode change
                                     # (gaitml.labels); "nearest": to the nearest step
    moving_speed_ms = 0.0            # "folder": > 0 labels every recording with a motion capture (tyrex)
                                     # per sample: its data.label value where the walker's body (the true path
                                     # low-passed at 0.5 Hz) moves faster than this, "still" elsewhere,
                                     # "unlabelled" outside the capture (gaitml.evaluation.trajectory.moving_samples)
    [data.walks]                     # "folder": also read real walking with true step times (e.g. the Oxford
    path = ""                        # step counter) from this folder, relative to the config: the samples inside
                                     # stretches of true steps become data.label "walk", the rest is left out
                                     # (gaitml.pipeline.runner.step_walking_labels); its data.group from the meta
    weight = 1                       # each such recording counts this many times in training
    [data.augment]                   # "folder": rotated copies of the real recordings (gaitml.pipeline.augment)
    swing_turns = 0                  # copies per recording in data.augment.positions: the phone turned about its
                                     # swing axis (the grip in a swinging hand), angles spread over the full turn
    positions = ["swinging-hand"]    # meta "position" values whose recordings get the copies
    share_time = false               # true: the original and its copies share the recording's time (a grip per
                                     # 3 s stretch), so the position keeps its number of windows
    flips = []                       # pocket flips: copies turned 180 deg about the named phone axes ("x", "y",
                                     # "z": top up/down, screen toward/away from the thigh), exact rigid turns
    flip_positions = ["front-pocket", "back-pocket", "pocket"]   # meta "position" values given the flips
    rates = []                       # sampling rates (Hz, below data.resample_hz): every training recording, real
                                     # and simulated, also trains as a copy taken down to each rate and back up
                                     # (the resampling of predict); the model's domain then reaches down to the
                                     # lowest (any source; gaitml.pipeline.augment.rate_copies)
    tempo = []                       # tempo factors (e.g. [0.87, 1.15]): every real recording with a label of
                                     # tempo_labels also trains replayed at each tempo (time x 1/s, angular rate
                                     # x s, linear acceleration x s^2, gravity kept; gaitml.pipeline.augment.
                                     # tempo_copies); the copies enter the domain record too, are turned and
                                     # flipped like their recording and get rate copies ("folder")
    tempo_labels = ["run"]           # the per-sample labels whose recordings get tempo copies
    tempo_positions = []             # meta "position" values whose recordings get tempo copies (e.g. ["pocket"]);
                                     # [] = every position
    tempo_in_domain = true           # false: the tempo copies train the classifier only and stay out of the
                                     # domain record, like the other copies
    [data.simulated]
    subjects = 8
    sessions = 1                     # recordings per subject (later sessions vary a little: another day)
    pose = "flat"                    # "flat" | "tilted" | "mixed" (drawn per subject)
    duration_s = 120.0
    modes = ["walk", "run", "side_left", "side_right", "backward"]
    positions = []                   # carrying positions (gaitml.simulate.POSITIONS, e.g. ["hand-flat", "front-pocket"]):
                                     # one recording per subject and position; [] = hand-held in `pose`
    [windows]
    length_s = 1.5
    overlap = 0.5
    min_label_fraction = 0.5
    by = "time"                      # "time" | "steps" (a window per detected step) | "strides" (per stride)
    detector = ""                    # steps: a step detector (default "single-peak"); strides: a ZUPT detector
                                     # (default "pseudo-std"); time windows ignore it (gaitml.features.step_windows)
    [features]
    set = "all52"                    # "all52" | "paper34" | "all52+gyro"
    frame = "phone"                  # "phone" (paper 003) | "gravity" (per-window gravity-aligned, orientation-free)
    acc_range_ms2 = 0                # read every accelerometer through +-this per axis (m/s^2), in training and
                                     # prediction: the training phones' narrowest range, e.g. 19.6 (2 g); 0 = none
    [model]
    kind = "linear-ovo-svm"          # | "mlp" | "cnn1d"
    params = {}                      # constructor parameters of the kind, e.g. { C = 1.0 }
    [cv]
    scheme = "leave-one-group-out"   # | "train-one-test-rest" | "group-kfold"
    n_splits = 5
    n_jobs = 1
    [postprocess]
    adjacent_correction = true
    [train]
    model_dir = ""                   # where `gaitml train` writes the model (default models/<name>)
    cross_validate = true            # record CV scores in model.json
    domain_dynamics = true           # all52+gyro models: record the orientation-dynamics part of the
                                     # training domain (gaitml.models.domain); false: features and gravity only
    domain_acc_range_ms2 = 0         # the domain record alone (feature distance, gravity, dynamics) reads every
                                     # accelerometer through +-this per axis, in training and prediction; the
                                     # classifier reads it as it comes; 0 = none (exclusive with acc_range_ms2)
    [card]                           # printed in the model card (MODEL.md) beside what training records
    licence = ""                     # the training data's licence(s)
    notes = []                       # lines for the card, e.g. where each mode's windows come from
    [sweep]
    "windows.length_s" = [0.5, 1.0]  # grid: every combination of the listed values

``task = "steps"``: every listed step detector on the shared real step
recordings (:mod:`gaitml.pipeline.steps_real`), keys::

    name, seed, description, task = "steps"
    [data]
    path = "../../shared/data"       # required: the folder holding the data sets below
    sets = ["ifsm-flat-phone", "oxford-step-counter"]
    [steps]
    detectors = [...]                # step detector names (default: every registered one)
    tolerance_s = 0.25               # one-to-one matching tolerance of precision / recall / F1
    [evaluation]
    holdout = "user"                 # "user" | "position" | "none", or a list such as ["user", "position"]:
                                     # leave-one-user-out / leave-one-position-out on the Oxford recordings
    tune = true                      # a detector declaring a param_grid also runs as "<name> (tuned)", its
                                     # setting chosen on the training folds only (hard floor)
"""

from __future__ import annotations

import copy
import dataclasses
import itertools
import math
import os
import tomllib
from pathlib import Path
from typing import Any

from gaitml.consts import MOTION_MODES
from gaitml.errors import ConfigError, GaitmlError, InputError
from gaitml.pipeline.augment import FLIP_AXES, TEMPO_LIMITS
from gaitml.pipeline.augment import POCKET_POSITIONS as POCKET_POSITIONS_DEFAULT
from gaitml.pipeline.augment import SWING_POSITIONS as SWING_POSITIONS_DEFAULT
from gaitml.pipeline.augment import TEMPO_LABELS as TEMPO_LABELS_DEFAULT

__all__ = ["ExperimentConfig", "load_config", "parse_config", "sweep_grid", "SOURCES", "TASKS", "STEP_DATA_SETS", "STEP_HOLDOUTS"]

SOURCES = ("simulated", "folder")
#: What a config runs: cross-validated classification (the default) or the step-detector evaluation.
TASKS = ("classification", "steps")
#: Data sets of ``task = "steps"``, folders below ``data.path``.
STEP_DATA_SETS = ("ifsm-flat-phone", "oxford-step-counter")
#: Default matching tolerance of ``task = "steps"`` (s).
STEP_TOLERANCE_S = 0.25
#: Held-out evaluation schemes of ``task = "steps"``: leave one Oxford user / carrying position out.
STEP_HOLDOUTS = ("user", "position", "none")


# Allowed names, read from the registries when a config is checked.
def _feature_set_names() -> tuple[str, ...]:
    from gaitml.features import FEATURE_SETS

    return tuple(FEATURE_SETS)


def _model_kind_names() -> tuple[str, ...]:
    from gaitml.models import MODEL_KINDS

    return tuple(MODEL_KINDS)


def _cv_scheme_names() -> tuple[str, ...]:
    from gaitml.evaluation.cv import CV_SCHEMES

    return tuple(CV_SCHEMES)


def _feature_frame_names() -> tuple[str, ...]:
    from gaitml.features import FEATURE_FRAMES

    return tuple(FEATURE_FRAMES)


def _sim_pose_names() -> tuple[str, ...]:
    """The simulator's phone poses plus "mixed" (drawn per subject)."""
    from gaitml.simulate.subject import POSES

    return (*POSES, "mixed")


def _sim_position_names() -> tuple[str, ...]:
    """The simulator's carrying positions."""
    from gaitml.simulate.positions import POSITIONS

    return tuple(POSITIONS)


def _snap_modes() -> tuple[str, ...]:
    from gaitml.labels import SNAP_MODES

    return SNAP_MODES


def _nonneg(v):
    return None if v >= 0 else "must be >= 0"


def _check_labelling(values: dict) -> None:
    """``data.labelling.detector`` must be a step detector (snap steps/none) or a zero-velocity detector (snap strides)."""
    lab = values["data"]["labelling"]
    if not lab["detector"]:
        return
    if lab["snap"] == "strides":
        from gaitml.zupt import DETECTORS

        kind = "zero-velocity detector (data.labelling.snap = 'strides')"
    else:
        from gaitml.steps import DETECTORS

        kind = f"step detector (data.labelling.snap = {lab['snap']!r})"
    if lab["detector"] not in DETECTORS:
        raise ConfigError(f"data.labelling.detector = {lab['detector']!r} is not a {kind}; allowed: {', '.join(map(repr, DETECTORS))}.")


def _check_ranges(values: dict) -> None:
    """``features.acc_range_ms2`` (classifier and domain record) and ``train.domain_acc_range_ms2`` (domain record only) exclude each other."""
    if values.get("features", {}).get("acc_range_ms2") and values.get("train", {}).get("domain_acc_range_ms2"):
        raise ConfigError(
            "features.acc_range_ms2 already reads the domain record through the range; set train.domain_acc_range_ms2 = 0, "
            "or features.acc_range_ms2 = 0 to range the domain record alone."
        )


def _window_by_names() -> tuple[str, ...]:
    from gaitml.features.step_windows import WINDOW_BY

    return WINDOW_BY


def _check_windows(values: dict) -> None:
    """``windows.detector`` must come from the registry of ``windows.by`` (steps: step detectors, strides: ZUPT detectors)."""
    from gaitml.features.step_windows import check_window_by

    w = values["windows"]
    try:
        check_window_by(w["by"], w["detector"])
    except InputError as exc:
        raise ConfigError(f"windows.detector = {w['detector']!r}: {str(exc).rstrip('.')}.") from None
    if w["by"] != "time" and values.get("features", {}).get("frame", "phone") != "phone":
        raise ConfigError(
            f"windows.by = {w['by']!r} computes the features in the phone frame only, got features.frame = "
            f"{values['features']['frame']!r}; set features.frame = 'phone' or windows.by = 'time'."
        )


def _step_detector_names() -> tuple[str, ...]:
    from gaitml.steps import detector_names

    return tuple(detector_names())


@dataclasses.dataclass(frozen=True)
class _Leaf:
    types: tuple
    default: Any  # a value, or a callable returning it
    allowed: Any = None  # tuple of values, or a callable returning one (a registry)
    check: Any = None  # callable(value) -> error text or None
    item_type: type | None = None  # for lists
    item_allowed: Any = None  # for lists: allowed items, tuple or callable

    def allowed_values(self, items: bool = False) -> tuple | None:
        a = self.item_allowed if items else self.allowed
        return a() if callable(a) else a

    def default_value(self):
        return self.default() if callable(self.default) else copy.deepcopy(self.default)


def _no_repeats(v):
    return None if len(set(v)) == len(v) else "lists an item twice"


def _pos(v):
    return None if v > 0 else "must be > 0"


def _acc_range(v):
    from gaitml.consts import GRAVITY_MS2

    return (
        None
        if v == 0 or v >= GRAVITY_MS2
        else f"must be 0 (no range) or a range per axis >= {GRAVITY_MS2} m/s^2 (1 g), e.g. 19.6 for +-2 g"
    )


def _nonneg_int(v):
    return None if v >= 0 else "must be >= 0"


def _overlap(v):
    return None if 0 <= v < 1 else "must be in [0, 1)"


def _fraction(v):
    return None if 0 <= v <= 1 else "must be in [0, 1]"


def _n_jobs(v):
    return None if v >= 1 or v == -1 else "must be >= 1, or -1 for all cores"


def _subjects(v):
    from gaitml.simulate.subject import MAX_SUBJECTS

    return None if 1 <= v <= MAX_SUBJECTS else f"must be within 1-{MAX_SUBJECTS}"


def _sim_duration(v):
    from gaitml.simulate.dataset import MAX_DURATION_S

    return None if 2.0 <= v <= MAX_DURATION_S else f"must be within 2-{MAX_DURATION_S:g} s (24 h per recording)"


def _sessions(v):
    return None if 1 <= v <= 100 else "must be within 1-100"


def _holdout(v):
    items = [v] if isinstance(v, str) else v
    if not items:
        return "must name at least one scheme (or be 'none')"
    bad = [x for x in items if not isinstance(x, str) or x not in STEP_HOLDOUTS]
    if bad:
        return f"has {bad[0]!r}, which is not allowed; allowed: {', '.join(map(repr, STEP_HOLDOUTS))}"
    if "none" in items and len(items) > 1:
        return "mixes 'none' with held-out schemes; give 'none' alone"
    if len(set(items)) != len(items):
        return "lists a scheme twice"
    return None


def _augment_rates(v):
    bad = [x for x in v if isinstance(x, bool) or not isinstance(x, int | float)]
    if bad:
        return f"must list sampling rates in Hz (numbers); {bad[0]!r} is not one"
    bad = [x for x in v if not 1.0 <= x < 1e4]
    if bad:
        return f"has {bad[0]!r}, not a sampling rate: list rates in Hz above 1, e.g. [20.0]"
    if len({float(x) for x in v}) != len(v):
        return "lists a rate twice"
    return None


def _augment_tempo(v):
    bad = [x for x in v if isinstance(x, bool) or not isinstance(x, int | float)]
    if bad:
        return f"must list tempo factors (numbers); {bad[0]!r} is not one"
    lo, hi = TEMPO_LIMITS
    bad = [x for x in v if not lo < x < hi or x == 1]
    if bad:
        return f"has {bad[0]!r}, not a tempo factor: list factors between {lo:g} and {hi:g} other than 1, e.g. [0.87, 1.15]"
    if len({float(x) for x in v}) != len(v):
        return "lists a factor twice"
    return None


def _min2(v):
    return None if v >= 2 else "must be >= 2"


_NUM = (int, float)
_COMMON: dict[str, Any] = {
    "name": _Leaf((str,), None, check=lambda v: None if v.strip() and "/" not in v else "must be a non-empty name without '/'"),
    "seed": _Leaf((int,), 0, check=_nonneg_int),
    "description": _Leaf((str,), ""),
    "task": _Leaf((str,), "classification", allowed=TASKS),
}
SCHEMA: dict[str, Any] = {
    **_COMMON,
    "data": {
        "source": _Leaf((str,), "simulated", allowed=SOURCES),
        "path": _Leaf((str,), ""),
        "label": _Leaf((str,), "label"),
        "group": _Leaf((str,), "subject"),
        "labels": _Leaf((list,), [], item_type=str),
        "resample_hz": _Leaf(_NUM, 50.0, check=_pos),
        "where": _Leaf((dict,), {}),
        # a folder of phone recordings listed in a manifest (gaitml.pipeline.folder_source)
        "manifest": _Leaf((str,), ""),
        "labelling": {
            "snap": _Leaf((str,), "steps", allowed=_snap_modes),
            "detector": _Leaf((str,), ""),
            "max_snap_s": _Leaf(_NUM, 0.5, check=_nonneg),
            # where a boundary moves: to evidence of the mode change, or to the nearest step
            "rule": _Leaf((str,), "change", allowed=("change", "nearest")),
            # label recordings with a motion capture by the walker's speed (0 = off)
            "moving_speed_ms": _Leaf(_NUM, 0.0, check=_nonneg),
        },
        # a folder source plus real walking with true step times (labelled walk inside stretches of steps)
        "walks": {
            "path": _Leaf((str,), ""),
            "weight": _Leaf((int,), 1, check=_pos),
        },
        # a folder source plus rotated copies of its recordings in swinging positions (gaitml.pipeline.augment)
        "augment": {
            "swing_turns": _Leaf((int,), 0, check=_nonneg),
            "positions": _Leaf((list,), list(SWING_POSITIONS_DEFAULT), item_type=str),
            "share_time": _Leaf((bool,), False),
            # 180 deg turns of the phone about its own axes (the ways a phone lies in a pocket)
            "flips": _Leaf((list,), [], item_type=str, item_allowed=FLIP_AXES, check=_no_repeats),
            "flip_positions": _Leaf((list,), list(POCKET_POSITIONS_DEFAULT), item_type=str),
            # sampling rates the recordings also train at, through predict's own resampling (any source)
            "rates": _Leaf((list,), [], check=_augment_rates),
            # running replayed faster and slower (time compressed, rates and accelerations scaled)
            "tempo": _Leaf((list,), [], check=_augment_tempo),
            "tempo_labels": _Leaf((list,), list(TEMPO_LABELS_DEFAULT), item_type=str, check=_no_repeats),
            "tempo_positions": _Leaf((list,), [], item_type=str, check=_no_repeats),
            "tempo_in_domain": _Leaf((bool,), True),
        },
        # a folder source plus the simulated subjects of [data.simulated]
        "add_simulated": _Leaf((bool,), False),
        "simulated": {
            "subjects": _Leaf((int,), 8, check=_subjects),
            "sessions": _Leaf((int,), 1, check=_sessions),
            "pose": _Leaf((str,), "flat", allowed=_sim_pose_names),
            "duration_s": _Leaf(_NUM, 120.0, check=_sim_duration),
            "modes": _Leaf((list,), list(MOTION_MODES), item_type=str),
            # carrying positions; [] = the hand-held phone in data.simulated.pose (one recording per subject)
            "positions": _Leaf((list,), [], item_type=str, item_allowed=_sim_position_names),
        },
    },
    "windows": {
        "length_s": _Leaf(_NUM, 1.5, check=_pos),
        "overlap": _Leaf(_NUM, 0.5, check=_overlap),
        "min_label_fraction": _Leaf(_NUM, 0.5, check=_fraction),
        # step-synchronous windows (gaitml.features.step_windows); detector checked in _check_windows
        "by": _Leaf((str,), "time", allowed=_window_by_names),
        "detector": _Leaf((str,), ""),
    },
    "features": {
        "set": _Leaf((str,), "all52", allowed=_feature_set_names),
        "frame": _Leaf((str,), "phone", allowed=_feature_frame_names),
        # the accelerometer range every recording is read through (gaitml.features._range); 0 = none
        "acc_range_ms2": _Leaf(_NUM, 0.0, check=_acc_range),
    },
    "model": {
        "kind": _Leaf((str,), "linear-ovo-svm", allowed=_model_kind_names),
        "params": _Leaf((dict,), {}),
    },
    "cv": {
        "scheme": _Leaf((str,), "leave-one-group-out", allowed=_cv_scheme_names),
        "n_splits": _Leaf((int,), 5, check=_min2),
        "n_jobs": _Leaf((int,), 1, check=_n_jobs),
    },
    "postprocess": {"adjacent_correction": _Leaf((bool,), True)},
    "train": {
        "model_dir": _Leaf((str,), ""),
        "cross_validate": _Leaf((bool,), True),
        "domain_dynamics": _Leaf((bool,), True),
        "domain_acc_range_ms2": _Leaf(_NUM, 0.0, check=_acc_range),
    },
    # what the model card (MODEL.md) states beside the recorded facts: the training data's licence and notes
    "card": {
        "licence": _Leaf((str,), ""),
        "notes": _Leaf((list,), [], item_type=str),
    },
}


STEPS_SCHEMA: dict[str, Any] = {
    **_COMMON,
    "data": {
        "path": _Leaf((str,), ""),
        "sets": _Leaf((list,), list(STEP_DATA_SETS), item_type=str, item_allowed=STEP_DATA_SETS),
    },
    "steps": {
        "detectors": _Leaf((list,), lambda: list(_step_detector_names()), item_type=str, item_allowed=_step_detector_names),
        "tolerance_s": _Leaf(_NUM, STEP_TOLERANCE_S, check=_pos),
    },
    "evaluation": {
        "holdout": _Leaf((str, list), "user", check=_holdout),
        "tune": _Leaf((bool,), True),
    },
}
#: task -> its schema
SCHEMAS = {"classification": SCHEMA, "steps": STEPS_SCHEMA}


def _type_ok(v, types) -> bool:
    if isinstance(v, bool) and bool not in types:
        return False
    return isinstance(v, types)


def _type_names(types) -> str:
    names = {int: "integer", float: "number", str: "string", bool: "boolean", list: "array", dict: "table"}
    return " or ".join(names.get(t, t.__name__) for t in types)


def _a(noun: str) -> str:
    """``noun`` with its indefinite article ("an integer", "a string")."""
    return f"an {noun}" if noun[:1].lower() in "aeiou" else f"a {noun}"


def _check_leaf(key: str, leaf: _Leaf, v):
    if not _type_ok(v, leaf.types):
        raise ConfigError(f"{key} = {v!r} has the wrong type ({type(v).__name__}); expected {_a(_type_names(leaf.types))}.")
    allowed = leaf.allowed_values()
    if allowed is not None and v not in allowed:
        raise ConfigError(f"{key} = {v!r} is not allowed; allowed: {', '.join(map(repr, allowed))}.")
    if leaf.item_type is not None:
        bad = [x for x in v if not isinstance(x, leaf.item_type)]
        if bad:
            raise ConfigError(f"{key} = {v!r} must list {_type_names((leaf.item_type,))}s; {bad[0]!r} is not one.")
        allowed = leaf.allowed_values(items=True)
        bad = [x for x in v if allowed is not None and x not in allowed]
        if bad:
            raise ConfigError(f"{key} has {bad[0]!r}, which is not allowed; allowed: {', '.join(map(repr, allowed))}.")
    if leaf.check is not None:
        msg = leaf.check(v)
        if msg:
            raise ConfigError(f"{key} = {v!r} {msg}.")
    if float in leaf.types and isinstance(v, int) and not isinstance(v, bool):
        v = float(v)
    return copy.deepcopy(v)


def _fill(raw: dict, schema: dict, prefix: str) -> dict:
    if not isinstance(raw, dict):
        raise ConfigError(f"{prefix.rstrip('.')} must be a table, got {raw!r}.")
    out: dict = {}
    for k in raw:
        if k not in schema:
            where = f"[{prefix.rstrip('.')}]" if prefix else "the top level"
            raise ConfigError(f"unknown key {prefix}{k} in {where}; allowed keys: {', '.join(schema)}.")
    for k, spec in schema.items():
        key = prefix + k
        if isinstance(spec, dict):
            out[k] = _fill(raw.get(k, {}), spec, key + ".")
        elif k in raw:
            out[k] = _check_leaf(key, spec, raw[k])
        else:
            if spec.default is None:
                raise ConfigError(f'the config has no {key}; add e.g. {key} = "my-experiment".')
            out[k] = spec.default_value()
    return out


def _leaf_at(path: str):
    node: Any = SCHEMA
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node if isinstance(node, _Leaf) else None


#: Keys written into :meth:`ExperimentConfig.resolved` only when they differ from their default.
_WRITTEN_WHEN_SET: dict[tuple[str, ...], Any] = {
    ("data", "add_simulated"): False,
    ("data", "labelling", "moving_speed_ms"): 0.0,
    ("data", "labelling", "rule"): "change",
    ("card", "licence"): "",
    ("card", "notes"): [],
    ("data", "walks", "path"): "",
    ("data", "walks", "weight"): 1,
    ("data", "augment", "swing_turns"): 0,
    ("data", "augment", "positions"): list(SWING_POSITIONS_DEFAULT),
    ("data", "augment", "share_time"): False,
    ("data", "augment", "flips"): [],
    ("data", "augment", "flip_positions"): list(POCKET_POSITIONS_DEFAULT),
    ("data", "augment", "rates"): [],
    ("data", "augment", "tempo"): [],
    ("data", "augment", "tempo_labels"): list(TEMPO_LABELS_DEFAULT),
    ("data", "augment", "tempo_positions"): [],
    ("data", "augment", "tempo_in_domain"): True,
    ("train", "domain_acc_range_ms2"): 0.0,
}


@dataclasses.dataclass(frozen=True)
class ExperimentConfig:
    """A validated experiment config (``values`` holds every key, defaults filled in).

    Attributes
    ----------
    values : dict
        The resolved config (nested dicts as in the TOML, without ``[sweep]``).
    sweep : dict
        Dotted key -> list of values (may be empty).
    base_dir : Path
        Folder of the config file: relative paths are resolved against it.
    source : Path or None
        The config file.
    """

    values: dict
    sweep: dict
    base_dir: Path
    source: Path | None = None

    # convenient views
    @property
    def name(self) -> str:
        return self.values["name"]

    @property
    def task(self) -> str:
        """What the config runs: ``'classification'`` or ``'steps'``."""
        return self.values["task"]

    @property
    def seed(self) -> int:
        return self.values["seed"]

    def __getitem__(self, section: str):
        return self.values[section]

    @property
    def data_path(self) -> Path | None:
        p = self.values["data"]["path"]
        return (self.base_dir / p).resolve() if p else None

    @property
    def model_dir(self) -> Path | None:
        p = self.values["train"]["model_dir"]
        return (self.base_dir / p).resolve() if p else None

    def resolved(self) -> dict:
        """The resolved config as a plain dict (for the run folder and model.json)."""
        d = copy.deepcopy(self.values)
        # keys that are off by default are written only when set, so that the resolved config (and
        # the training_config of a model in model.json) of a config that does not use them is unchanged
        for path, default in _WRITTEN_WHEN_SET.items():
            *parents, key = path
            sec = d
            for k in parents:
                sec = sec.get(k, {})
            if key in sec and sec[key] == default:
                del sec[key]
        if d.get("card") == {}:
            del d["card"]
        for sub in ("walks", "augment"):
            if d["data"].get(sub) == {}:
                del d["data"][sub]
        if self.data_path is not None:
            d["data"]["path_resolved"] = str(self.data_path)
        if self.sweep:
            d["sweep"] = copy.deepcopy(self.sweep)
        return d

    def with_values(self, overrides: dict[str, Any]) -> ExperimentConfig:
        """A copy with dotted keys set (validated again), without the sweep."""
        raw = copy.deepcopy(self.values)
        for path, v in overrides.items():
            node = raw
            parts = path.split(".")
            for p in parts[:-1]:
                node = node.setdefault(p, {})
            node[parts[-1]] = v
        # an override may turn the copies off (a sweep over data.augment.swing_turns): the other augment keys stay set
        return parse_config(raw, base_dir=self.base_dir, source=self.source, check_paths=False, check_unused=False)

    def with_data_path(self, path: str | os.PathLike) -> ExperimentConfig:
        """A copy reading its data from ``path`` (relative to the current folder), sweep kept.

        Raises
        ------
        ConfigError
            The config simulates its data, or ``path`` does not exist.
        """
        if self.task == "classification" and self["data"]["source"] != "folder":
            raise ConfigError(f"{self.name} simulates its data (data.source = 'simulated'); a data folder applies to folder configs only.")
        p = Path(path).resolve()
        if not p.exists():
            raise ConfigError(f"data folder {path} does not exist; pass an existing folder.")
        raw = copy.deepcopy(self.values)
        raw["data"]["path"] = str(p)
        if self.sweep:
            raw["sweep"] = copy.deepcopy(self.sweep)
        return parse_config(raw, base_dir=self.base_dir, source=self.source)


def sweep_grid(cfg: ExperimentConfig) -> list[dict[str, Any]]:
    """Every combination of the ``[sweep]`` values (one empty dict without a sweep)."""
    if not cfg.sweep:
        return [{}]
    keys = list(cfg.sweep)
    return [dict(zip(keys, combo, strict=True)) for combo in itertools.product(*(cfg.sweep[k] for k in keys))]


#: A sweep grid larger than this is refused: each point is a full cross-validation.
MAX_SWEEP_POINTS = 1000


def _check_sweep(raw_sweep, values: dict) -> dict:
    if not isinstance(raw_sweep, dict):
        raise ConfigError(f"[sweep] must be a table of dotted keys to lists, got {raw_sweep!r}.")
    out = {}
    for path, vals in raw_sweep.items():
        if path.startswith("model.params."):
            leaf = None
        else:
            leaf = _leaf_at(path)
            if leaf is None or path in ("name", "task"):
                raise ConfigError(
                    f"sweep key {path!r} is not a config key; use a dotted key such as 'windows.length_s', 'features.set' or 'model.params.C'."
                )
        if not isinstance(vals, list) or not vals:
            raise ConfigError(f"sweep.{path!r} = {vals!r} must be a non-empty array of values.")
        out[path] = [_check_leaf(f"sweep.{path!r}", leaf, v) if leaf else v for v in vals]
    n_points = math.prod(len(v) for v in out.values())
    if n_points > MAX_SWEEP_POINTS:
        sizes = " x ".join(str(len(v)) for v in out.values())
        raise ConfigError(
            f"[sweep] has {n_points} grid points ({sizes}), more than {MAX_SWEEP_POINTS}; sweep fewer values or split it into several configs."
        )
    return out


def _check_model(values: dict) -> None:
    from gaitml.models import make_model

    kind = values["model"]["kind"]
    try:
        est = make_model(kind, values["model"]["params"], seed=values["seed"])
        check = getattr(est, "_check_params", None)
        if check is not None:
            check()
    except ConfigError:
        raise
    except InputError as exc:
        raise ConfigError(f"model.params for {kind!r}: {str(exc).rstrip('.')}.") from exc
    except GaitmlError:
        raise
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"model.params = {values['model']['params']!r} is not valid for {kind!r}: {exc}.") from exc


def parse_config(
    raw: dict,
    *,
    base_dir: str | os.PathLike = ".",
    source: str | os.PathLike | None = None,
    check_paths: bool = True,
    check_unused: bool = True,
) -> ExperimentConfig:
    """Validate a config dict (as read from TOML) into an :class:`ExperimentConfig`.

    Raises
    ------
    ConfigError
        Unknown key, wrong type, a value outside the allowed set, a missing
        ``name``, a bad sweep, ``data.path`` missing for source 'folder' or not
        existing (when ``check_paths``), a model parameter the kind does not take,
        ``data.augment`` settings that cannot apply (``share_time`` or ``positions``
        without copies, when ``check_unused``; ``share_time`` with one label per
        recording).
    ModelError
        A torch model kind without torch installed.
    """
    raw = dict(raw)
    raw_sweep = raw.pop("sweep", {})
    task = _check_leaf("task", _COMMON["task"], raw.get("task", "classification"))
    values = _fill(raw, SCHEMAS[task], "")
    base = Path(base_dir)
    if task == "steps":
        if raw_sweep:
            raise ConfigError("[sweep] is for task 'classification'; a 'steps' config evaluates every listed detector: remove [sweep].")
        cfg = ExperimentConfig(values=values, sweep={}, base_dir=base, source=None if source is None else Path(source))
        if not values["data"]["path"]:
            raise ConfigError("task 'steps' needs data.path (the shared data folder, relative to the config file).")
        if check_paths and not cfg.data_path.is_dir():
            raise ConfigError(
                f"data.path = {values['data']['path']!r} is not a folder (resolved to {cfg.data_path}); fix the path "
                "(it is relative to the config file) or pass --data."
            )
        return cfg
    sweep = _check_sweep(raw_sweep, values)
    cfg = ExperimentConfig(values=values, sweep=sweep, base_dir=base, source=None if source is None else Path(source))
    d = values["data"]
    if d["source"] != "folder":
        for key, on in (
            ("data.add_simulated", d["add_simulated"]),
            ("data.labelling.moving_speed_ms", d["labelling"]["moving_speed_ms"] > 0),
            ("data.walks.path", bool(d["walks"]["path"])),
            ("data.augment.swing_turns", d["augment"]["swing_turns"] > 0),
            ("data.augment.share_time", d["augment"]["share_time"]),
            ("data.augment.positions", list(d["augment"]["positions"]) != list(SWING_POSITIONS_DEFAULT)),
            ("data.augment.flips", bool(d["augment"]["flips"])),
            ("data.augment.flip_positions", list(d["augment"]["flip_positions"]) != list(POCKET_POSITIONS_DEFAULT)),
            ("data.augment.tempo", bool(d["augment"]["tempo"])),
            ("data.augment.tempo_labels", list(d["augment"]["tempo_labels"]) != list(TEMPO_LABELS_DEFAULT)),
            ("data.augment.tempo_positions", bool(d["augment"]["tempo_positions"])),
            ("data.augment.tempo_in_domain", not d["augment"]["tempo_in_domain"]),
        ):
            if on:
                raise ConfigError(f"{key} applies to data.source = 'folder' (a real data set); remove it or read a folder.")
    d["augment"]["rates"] = [float(x) for x in d["augment"]["rates"]]
    high = [x for x in d["augment"]["rates"] if x >= float(d["resample_hz"])]
    if high:
        raise ConfigError(
            f"data.augment.rates has {high[0]:g} Hz, not below the model's rate data.resample_hz = {d['resample_hz']:g} Hz; "
            "list rates below it (a copy at the model's rate or above is the recording itself)."
        )
    if d["source"] == "folder":
        aug = d["augment"]
        if check_unused and aug["swing_turns"] == 0:
            for key, on in (
                ("data.augment.share_time", aug["share_time"] and not aug["flips"]),
                ("data.augment.positions", list(aug["positions"]) != list(SWING_POSITIONS_DEFAULT)),
            ):
                if on:
                    raise ConfigError(f"{key} is set but data.augment.swing_turns = 0 (no copies): set swing_turns > 0 or remove {key}.")
        if check_unused and not aug["tempo"]:
            for key, on in (
                ("data.augment.tempo_labels", list(aug["tempo_labels"]) != list(TEMPO_LABELS_DEFAULT)),
                ("data.augment.tempo_positions", bool(aug["tempo_positions"])),
                ("data.augment.tempo_in_domain", not aug["tempo_in_domain"]),
            ):
                if on:
                    raise ConfigError(f"{key} is set but data.augment.tempo is empty (no tempo copy): list factors or remove {key}.")
        if aug["tempo"] and not aug["tempo_labels"]:
            raise ConfigError("data.augment.tempo_labels is empty: name the labels whose recordings get tempo copies, e.g. ['run'].")
        aug["tempo"] = [float(x) for x in aug["tempo"]]
        if check_unused and not aug["flips"] and list(aug["flip_positions"]) != list(POCKET_POSITIONS_DEFAULT):
            raise ConfigError("data.augment.flip_positions is set but data.augment.flips is empty (no flip): name the axes or remove it.")
        copies = aug["swing_turns"] > 0 or bool(aug["flips"])
        if copies and aug["share_time"] and d["label"] != "label" and d["labelling"]["moving_speed_ms"] <= 0:
            raise ConfigError(
                f"data.augment.share_time needs per-sample labels, but data.label = {d['label']!r} is one label per recording; "
                "set share_time = false, or label per sample (data.label = 'label', or data.labelling.moving_speed_ms > 0)."
            )
        if not d["path"]:
            raise ConfigError("data.source = 'folder' needs data.path (a data set folder, relative to the config file).")
        if check_paths and not cfg.data_path.exists():
            raise ConfigError(
                f"data.path = {d['path']!r} does not exist (resolved to {cfg.data_path}); fix the path (it is relative to the config file)."
            )
        if check_paths and d["walks"]["path"] and not (cfg.base_dir / d["walks"]["path"]).is_dir():
            raise ConfigError(
                f"data.walks.path = {d['walks']['path']!r} is not a folder (resolved to {(cfg.base_dir / d['walks']['path']).resolve()}); "
                "fix the path (it is relative to the config file) or remove [data.walks]."
            )
        if check_paths and d["manifest"] and not (cfg.data_path / d["manifest"]).is_file():
            raise ConfigError(
                f"data.manifest = {d['manifest']!r} is not a file in {cfg.data_path}; write the manifest (columns file, subject[, intervals, "
                "position, format]) or fix the name."
            )
    else:
        bad = [m for m in d["simulated"]["modes"] if m not in MOTION_MODES]
        if bad:
            raise ConfigError(f"data.simulated.modes has {bad[0]!r}, not a simulated mode; allowed: {', '.join(MOTION_MODES)}.")
        if d["group"] not in ("subject", "session"):
            raise ConfigError(f"data.group = {d['group']!r} is not a column of simulated data; allowed: 'subject', 'session'.")
        positions = d["simulated"]["positions"]
        if d["label"] == "position" and not positions:
            raise ConfigError(
                "data.label = 'position' needs data.simulated.positions (the carrying positions to recognise); "
                "list at least two, e.g. positions = ['hand-flat', 'front-pocket']."
            )
        if d["label"] not in ("label", "position"):
            raise ConfigError(
                f"data.label = {d['label']!r} is not a column of simulated data; allowed: 'label' (the motion mode), "
                "'position' (with data.simulated.positions)."
            )
        # the classes: motion modes, or the carrying positions (one label per recording, from its meta 'position')
        by_position = d["label"] == "position"
        universe, key0, what = (
            (positions, "data.simulated.positions", "positions")
            if by_position
            else (d["simulated"]["modes"], "data.simulated.modes", "modes")
        )
        bad = [x for x in d["labels"] if x not in universe]
        if bad:
            raise ConfigError(f"data.labels has {bad[0]!r}, which is not in {key0} {universe}.")
        classes = sorted(set(d["labels"] or universe))
        if len(classes) < 2:
            key = "data.labels" if d["labels"] else key0
            raise ConfigError(
                f"{key} gives {len(classes)} class ({', '.join(classes) or 'none'}); a classifier needs at least 2: list at least two {what}."
            )
    _check_model(values)
    _check_windows(values)
    _check_labelling(values)
    _check_ranges(values)
    for point in sweep_grid(cfg):
        if point and any(k.startswith(("model.", "data.", "windows.by", "windows.detector", "features.frame")) for k in point):
            cfg.with_values(point)  # validates each grid point's model / data settings
    return cfg


def load_config(path: str | os.PathLike, *, check_paths: bool = True) -> ExperimentConfig:
    """Read and validate a TOML experiment config (paths relative to its folder).

    ``check_paths=False`` skips the check that ``data.path`` exists (for a config
    whose data folder is given later, e.g. by ``gaitml evaluate --data``).
    """
    p = Path(path)
    if p.is_dir():
        raise ConfigError(f"{p} is a directory, not a config file; pass a .toml file such as experiments/paper-svm.toml.")
    if not p.is_file():
        raise ConfigError(f"config file not found: {p}; pass a TOML file such as experiments/paper-svm.toml.")
    try:
        raw = tomllib.loads(p.read_text(encoding="utf-8-sig"))  # a BOM (Windows editors) is no syntax error
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{p.name} is not valid TOML: {exc}; fix the syntax.") from exc
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"cannot read config {p}: {exc}.") from exc
    return parse_config(raw, base_dir=p.resolve().parent, source=p.resolve(), check_paths=check_paths)
