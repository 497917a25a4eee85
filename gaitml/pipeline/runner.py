"""Run experiment configs: load data, window, cross-validate, sweep, train, write run folders.

:func:`evaluate_config` is what ``gaitml evaluate`` calls; :func:`train_config`
is ``gaitml train``. Both validate everything that needs the data
(:func:`prepare_data`: label present, groups, enough groups for the scheme)
before any feature is computed or model trained.
"""

from __future__ import annotations

import datetime as _dt
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from gaitml.errors import ConfigError, InputError
from gaitml.pipeline.config import ExperimentConfig, sweep_grid

__all__ = [
    "PreparedData",
    "prepare_data",
    "build_dataset",
    "evaluate_config",
    "train_config",
    "attach_training_domain",
    "fit_training_domain",
    "default_run_dir",
]

_DATA_CACHE: dict[str, Any] = {}
_DS_CACHE: dict[str, Any] = {}


class PreparedData:
    """Recordings at the experiment rate with labels set, their groups, and notes for the report."""

    def __init__(self, recordings, groups, notes, keep_labels=None):
        self.recordings = recordings
        self.groups = groups
        self.notes = notes
        #: labels to keep when ``data.labels`` is empty (all but 'unlabelled' of interval-labelled data), or None
        self.keep_labels = keep_labels


def _data_key(cfg: ExperimentConfig) -> str:
    d = dict(cfg["data"])
    return json.dumps({"data": d, "seed": cfg.seed, "base": str(cfg.base_dir)}, sort_keys=True, default=str)


def _meta_columns(recs) -> list[str]:
    keys = set()
    for r in recs:
        keys |= {k for k, v in r.meta.items() if isinstance(v, str | int | float) and not isinstance(v, bool)}
    return sorted(keys)


def _simulated_recordings(cfg: ExperimentConfig):
    """The ``[data.simulated]`` recordings of ``cfg`` and their notes."""
    from gaitml.simulate import simulate_dataset

    d = cfg["data"]
    fs = float(d["resample_hz"])
    notes: list[str] = []
    s = d["simulated"]
    recs = simulate_dataset(
        n_subjects=s["subjects"],
        n_sessions=s["sessions"],
        pose=s["pose"],
        duration_s=s["duration_s"],
        modes=tuple(s["modes"]),
        sampling_rate_hz=fs,
        seed=cfg.seed,
        positions=tuple(s.get("positions") or ()) or None,
    )
    notes.append(
        f"simulated: {s['subjects']} subjects x {s['sessions']} session(s), phone pose {s['pose']}, duration_s = {s['duration_s']}, modes {', '.join(s['modes'])}, {fs:g} Hz, seed {cfg.seed}"
    )
    if s.get("positions"):
        notes.append(f"carrying positions: {', '.join(s['positions'])} (one recording per subject and position)")
    return list(recs), notes


def _label_moving(recs, label: str, min_speed_ms: float):
    """Per-sample labels of the recordings with a motion capture (tyrex) from the walker's speed.

    A sample takes the recording's meta ``label`` value where the walker's body moves
    faster than ``min_speed_ms`` (:func:`gaitml.evaluation.trajectory.moving_samples`),
    ``still`` where it does not, and ``unlabelled`` outside the capture (left out of the
    windows like the samples outside an intervals file). Recordings without a motion
    capture are left out (and counted in the note).
    """
    from gaitml.evaluation.trajectory import moving_samples
    from gaitml.io.tyrex import read_tyrex_truth
    from gaitml.labels import UNLABELLED

    out, n_without = [], 0
    for r in recs:
        if not r.meta.get("truth"):
            n_without += 1
            continue
        if label not in r.meta:
            raise ConfigError(
                f"data.label = {label!r} is not a meta column of {r.name!r}; with data.labelling.moving_speed_ms > 0 the label must be "
                "a recording-level column such as 'mode'."
            )
        try:
            truth = read_tyrex_truth(r.meta["source"], truth_path=r.meta["truth"])
            m = moving_samples(r.t_s + float(r.meta.get("t0_original_s", 0.0)), truth.t_s, truth.pos_m[:, :2], min_speed_ms=min_speed_ms)
        except InputError as exc:
            raise ConfigError(f"data.labelling.moving_speed_ms: the motion capture of {r.name!r}: {str(exc).rstrip('.')}.") from None
        labels = np.where(m == 1, str(r.meta[label]), np.where(m == 0, "still", UNLABELLED)).astype(object)
        out.append(r.replace(labels=labels, meta={**r.meta, "labelled_from": "motion capture speed"}, check_units=False))
    note = (
        f"labels from the motion capture: the recording's {label!r} where the walker moves faster than {min_speed_ms:g} m/s "
        f"(true path low-passed at 0.5 Hz), 'still' elsewhere; {len(out)} recordings"
    )
    if n_without:
        note += f", {n_without} without a motion capture left out"
    return out, note


#: Consecutive true steps further apart than this (s) end a stretch of walking (:func:`step_walking_labels`).
WALK_MAX_STEP_GAP_S = 2.0
#: A stretch of walking extends this far (s) before its first and after its last true step.
WALK_STEP_PAD_S = 0.5


def step_walking_labels(rec, label: str = "walk", *, max_gap_s: float = WALK_MAX_STEP_GAP_S, pad_s: float = WALK_STEP_PAD_S) -> np.ndarray:
    """Per-sample labels of a recording with true step times (``reference['steps_t_s']``, e.g. the Oxford foot switches).

    ``label`` on the samples inside a stretch of steps (consecutive steps at most
    ``max_gap_s`` apart, extended by ``pad_s`` before its first and after its last
    step), ``unlabelled`` elsewhere (standing at the start and end of a recording,
    pauses), so that only walking gives training windows.
    """
    from gaitml.labels import UNLABELLED

    steps = np.sort(np.asarray(rec.reference.get("steps_t_s", ()), dtype=float))
    out = np.full(rec.n_samples, UNLABELLED, dtype=object)
    if len(steps) < 2:
        return out
    breaks = np.flatnonzero(np.diff(steps) > max_gap_s)
    for a, b in zip(np.r_[steps[0], steps[breaks + 1]], np.r_[steps[breaks], steps[-1]], strict=True):
        if b > a:
            out[(rec.t_s >= a - pad_s) & (rec.t_s <= b + pad_s)] = label
    return out


def _walk_recordings(cfg: ExperimentConfig, fs: float):
    """The ``[data.walks]`` recordings of ``cfg``: walking inside stretches of true steps, at ``fs``, repeated ``weight`` times."""
    from gaitml.io import read_dataset
    from gaitml.models import resample_recording

    w = cfg["data"]["walks"]
    folder = (cfg.base_dir / w["path"]).resolve()
    try:
        recs = read_dataset(folder)
    except InputError as exc:
        raise ConfigError(f"data.walks.path = {w['path']!r}: {exc}") from exc
    out = []
    for r in recs:
        if "steps_t_s" not in r.reference:
            raise ConfigError(
                f"data.walks.path = {w['path']!r}: {r.name!r} has no true step times; [data.walks] takes recordings with them "
                "(e.g. the Oxford step counter)."
            )
        r = resample_recording(r, fs)
        lab = step_walking_labels(r)
        pos = r.meta.get("position")
        meta = {**r.meta, "labelled_from": "true steps"}
        if pos:
            meta["motion"] = f"{r.meta.get('format', 'walks')} {pos}"
        out.append(r.replace(labels=lab, meta=meta, check_units=False))
    n_walk = sum(int(np.sum(r.labels == "walk")) for r in out)
    n_all = sum(r.n_samples for r in out)
    note = (
        f"added walking from {folder}: {len(out)} recordings, {n_walk / max(n_all, 1):.3f} of their samples inside stretches of "
        f"true steps (labelled walk; the rest left out), each counted {w['weight']} time(s)"
    )
    return out * int(w["weight"]), note


def _load_recordings(cfg: ExperimentConfig):
    d = cfg["data"]
    fs = float(d["resample_hz"])
    notes: list[str] = []
    if d["source"] == "simulated":
        return _with_rate_copies(cfg, *_simulated_recordings(cfg))
    from gaitml.models import resample_recording

    recs, read_notes = _read_folder(cfg)
    notes += read_notes
    where = d["where"]
    if where:
        cols = _meta_columns(recs)
        for k in where:
            if k not in cols:
                raise ConfigError(f"data.where key {k!r} is not a meta/manifest column of the data; columns: {', '.join(cols)}.")
        kept = [r for r in recs if all(str(r.meta.get(k)).lower() == str(v).lower() for k, v in where.items())]
        notes.append(f"data.where {where}: kept {len(kept)} of {len(recs)} recordings")
        if not kept:
            values = {k: sorted({str(r.meta.get(k)) for r in recs}) for k in where}
            raise ConfigError(f"data.where = {where} matches no recording; values present: {values}.")
        recs = kept
    if d["labelling"]["moving_speed_ms"] > 0:
        recs, note = _label_moving(recs, d["label"], float(d["labelling"]["moving_speed_ms"]))
        notes.append(note)
        if not recs:
            raise ConfigError(
                "data.labelling.moving_speed_ms > 0 but no recording has a motion capture; set it to 0 or use tyrex recordings."
            )
    # a stretch shorter than one window gives no window (e.g. a 9-sample piece between two sensor gaps of a tyrex
    # recording, read as segments): left out and counted rather than failing the resampling filter
    win_s = float(cfg["windows"]["length_s"])
    short = [r for r in recs if r.duration_s < win_s]
    if short:
        recs = [r for r in recs if r.duration_s >= win_s]
        notes.append(f"{len(short)} recording(s) shorter than one {win_s:g} s window left out: {', '.join(r.name for r in short)}")
    rates = sorted({round(r.sampling_rate_hz, 3) for r in recs})
    out = [resample_recording(r, fs) for r in recs]
    if any(abs(r - fs) > 1e-6 for r in rates):
        notes.append(f"resampled from {rates} Hz to {fs:g} Hz (low-pass at {0.45 * fs:g} Hz when down-sampling, then linear interpolation)")
    aug = d["augment"]
    if aug["tempo"]:
        out, note = _with_tempo_copies(
            out, list(aug["tempo"]), list(aug["tempo_labels"]), list(aug["tempo_positions"]), bool(aug["tempo_in_domain"])
        )
        notes.append(note)
    if aug["swing_turns"] > 0 or aug["flips"]:
        from gaitml.pipeline.augment import augmented_set

        turns, positions = int(aug["swing_turns"]), list(aug["positions"])
        flips, flip_positions = list(aug["flips"]), list(aug["flip_positions"])
        share = bool(aug["share_time"])
        if turns > 0:
            present = sorted({str(r.meta.get("position", "")) for r in out if r.gyr is not None})
            unmatched = [p for p in positions if p not in present]
            if unmatched:
                raise ConfigError(
                    f"data.augment.positions has {unmatched}, which matches no recording with a gyroscope; positions present (with a "
                    f"gyroscope): {present}. Fix the list or set data.augment.swing_turns = 0."
                )
        if flips:
            present = sorted({str(r.meta.get("position", "")) for r in out})
            unmatched = [p for p in flip_positions if p not in present]
            # the default list names every pocket of the tyrex layout: a data set needs only one of them
            from gaitml.pipeline.augment import POCKET_POSITIONS

            if unmatched and (flip_positions != list(POCKET_POSITIONS) or len(unmatched) == len(flip_positions)):
                raise ConfigError(
                    f"data.augment.flip_positions has {unmatched}, which matches no recording; positions present: {present}. "
                    "Fix the list or set data.augment.flips = []."
                )
        try:
            out, extra = augmented_set(out, turns, positions, seed=cfg.seed, share_time=share, flips=flips, flip_positions=flip_positions)
        except InputError as exc:
            raise ConfigError(f"data.augment.share_time: {exc}") from exc
        turned = [r for r in extra if "swing axis" in r.meta["augmented"] and "flipped" not in r.meta["augmented"]]
        n_turned = len(turned)
        parts = []
        if turns > 0:
            # a tempo copy in a swing position is turned too: counted apart from the real recordings
            n_tempo = sum(1 for r in turned if r.meta.get("augment_tempo")) // turns
            of_tempo = f" and their {n_tempo} tempo copies" if n_tempo else ""
            parts.append(
                f"{n_turned} copies of the {n_turned // turns - n_tempo} real recording(s){of_tempo} in {positions}, the phone turned about "
                f"its swing axis ({turns} angles per recording over the full turn)"
            )
        if flips:
            parts.append(f"{len(extra) - n_turned} copies flipped 180 deg about the phone's {'/'.join(flips)} axis in {flip_positions}")
        notes.append(
            "augmented: "
            + "; ".join(parts)
            + ("; the original and its copies share the recording's time (one grip per stretch)" if share else "")
        )
    if d["walks"]["path"]:
        walks, note = _walk_recordings(cfg, fs)
        out += walks
        notes.append(note)
    if d["add_simulated"]:
        sim, sim_notes = _simulated_recordings(cfg)
        out += sim
        notes += [f"added to the folder: {n}" for n in sim_notes]
    return _with_rate_copies(cfg, out, notes)


def _with_tempo_copies(recs: list, factors: list[float], labels: list[str], positions: list[str] | None = None, in_domain: bool = True):
    """``recs`` plus the tempo copies of those holding a label of ``labels`` (:func:`gaitml.pipeline.augment.tempo_copies`), and a note.

    ``positions`` (``data.augment.tempo_positions``; empty or None: every position): only the
    recordings carried in those positions (meta ``position``); a listed position that no labelled
    recording with a gyroscope is carried in is refused. ``in_domain``
    (``data.augment.tempo_in_domain``): the copies enter the domain record. The copies come after
    every recording, so that the turns' and flips' random draws of the recordings themselves are
    those of a config without tempo copies.
    """
    from gaitml.pipeline.augment import tempo_copies

    def holds(r):
        return r.labels is not None and bool(set(labels).intersection(np.unique(np.asarray(r.labels, dtype=object).astype(str))))

    chosen = [r for r in recs if holds(r)]
    with_gyr = [r for r in chosen if r.gyr is not None]
    if not with_gyr:
        present = sorted({str(x) for r in recs if r.labels is not None for x in np.unique(np.asarray(r.labels, dtype=object).astype(str))})
        raise ConfigError(
            f"data.augment.tempo_labels = {labels} matches no recording with a gyroscope (tempo copies need it for the phone's "
            f"gravity along its turns); labels present: {', '.join(present)}. Fix the labels or set data.augment.tempo = []."
        )
    where = ""
    if positions:
        present = sorted({str(r.meta.get("position", "")) for r in with_gyr})
        unmatched = [p for p in positions if p not in present]
        if unmatched:
            raise ConfigError(
                f"data.augment.tempo_positions has {unmatched}, which matches no recording labelled {'/'.join(labels)} with a "
                f"gyroscope; their positions: {', '.join(present)}. Fix the list or remove data.augment.tempo_positions."
            )
        chosen = [r for r in chosen if str(r.meta.get("position", "")) in positions]
        with_gyr = [r for r in with_gyr if str(r.meta.get("position", "")) in positions]
        where = f" in {'/'.join(positions)}"
    try:
        extra = tempo_copies(with_gyr, factors, labels, positions=positions or None, in_domain=in_domain)
    except InputError as exc:
        raise ConfigError(f"data.augment.tempo: {exc}") from exc
    skipped = len(chosen) - len(with_gyr)
    note = (
        f"augmented: {len(extra)} tempo copies of the {len(with_gyr)} recording(s) labelled {'/'.join(labels)}{where}, replayed at "
        f"{', '.join(f'{f:g}x' for f in factors)} (time / s, angular rate x s, linear acceleration x s^2; "
        + ("in the domain record)" if in_domain else "the classifier only, not in the domain record)")
        + (f"; {skipped} without a gyroscope got none" if skipped else "")
    )
    return [*recs, *extra], note


def _with_rate_copies(cfg: ExperimentConfig, recs: list, notes: list[str]):
    """``recs`` plus their copies at ``data.augment.rates`` (:func:`gaitml.pipeline.augment.rate_copies`), and a note.

    Every training recording gets them, real and simulated, rotated grips included: the model
    must read every mode in every position at the low rate (the simulator's side steps and
    backward walking as much as the real walks), and every class keeps its weight.
    """
    rates = list(cfg["data"]["augment"]["rates"])
    if not rates:
        return recs, notes
    from gaitml.pipeline.augment import rate_copies

    try:
        extra = rate_copies(recs, rates)
    except InputError as exc:
        raise ConfigError(f"data.augment.rates: {exc}") from exc
    note = (
        f"augmented: {len(extra)} copies of the {len(recs)} training recordings (real and simulated, grips included) taken down to "
        f"{', '.join(f'{r:g}' for r in rates)} Hz and back up to {float(cfg['data']['resample_hz']):g} Hz (predict's resampling)"
    )
    return [*recs, *extra], [*notes, note]


def _interval_labelling(d: dict) -> dict:
    """``[data.labelling]`` keys of the intervals-file labeller (``moving_speed_ms`` is the motion capture's, :func:`_label_moving`)."""
    return {k: v for k, v in d["labelling"].items() if k != "moving_speed_ms"}


def _read_folder(cfg: ExperimentConfig):
    """The recordings of a ``data.source = "folder"`` config.

    A folder with a manifest (``data.manifest``, or ``manifest.csv`` when present)
    is read by :func:`gaitml.pipeline.folder_source.read_manifest_folder`: any
    recording format, labels from intervals files. Without one, the folder's own
    layout (a gaitml-csv set, an Oxford set, a folder of recordings) is read by
    :func:`gaitml.io.read_dataset`.
    """
    from gaitml.io import read_dataset
    from gaitml.pipeline.folder_source import MANIFEST_NAME, read_manifest_folder

    d = cfg["data"]
    folder = cfg.data_path
    manifest = folder / (d["manifest"] or MANIFEST_NAME) if folder.is_dir() else None
    if d["manifest"] and (manifest is None or not manifest.is_file()):
        raise ConfigError(
            f"data.manifest = {d['manifest']!r} is not a file in {folder}; write the manifest (columns file, subject[, intervals, "
            "position, format]) or fix the name."
        )
    if manifest is not None and manifest.is_file():
        recs, notes = read_manifest_folder(folder, manifest, label=d["label"], labelling=_interval_labelling(d))
        return recs, [f"folder {folder}: {len(recs)} recordings read", *notes]
    try:
        recs = read_dataset(folder)
    except InputError as exc:
        raise ConfigError(f"data.path = {d['path']!r}: {exc}") from exc
    return recs, [f"folder {folder}: {len(recs)} recordings read"]


def prepare_data(cfg: ExperimentConfig, *, use_cache: bool = True) -> PreparedData:
    """Load the recordings of ``cfg`` and check label, labels and group against them.

    Raises
    ------
    ConfigError
        The label is neither a per-sample label nor a meta/manifest column; a
        ``data.labels`` entry does not occur; the group column is missing; too
        few groups for ``cv.scheme``.
    """
    from gaitml.evaluation.cv import check_groups

    key = _data_key(cfg)
    if use_cache and key in _DATA_CACHE:
        recs, notes = _DATA_CACHE[key]
    else:
        recs, notes = _load_recordings(cfg)
        if use_cache:
            _DATA_CACHE.clear()
            _DATA_CACHE[key] = (recs, notes)
    notes = list(notes)
    d = cfg["data"]
    label, group = d["label"], d["group"]
    cols = _meta_columns(recs)
    # per-sample labels: the 'label' column, or set from a motion capture (data.labelling.moving_speed_ms)
    per_sample = (label == "label" or d["labelling"]["moving_speed_ms"] > 0) and all(r.labels is not None for r in recs)
    labelled = []
    if per_sample:
        labelled = list(recs)
    elif all(label in r.meta for r in recs):
        labelled = [r.replace(labels=np.full(r.n_samples, str(r.meta[label]), dtype=object), check_units=False) for r in recs]
        notes.append(f"label: meta column {label!r} (one label per recording)")
    else:
        have = "per-sample 'label', " if all(r.labels is not None for r in recs) else ""
        raise ConfigError(
            f"data.label = {label!r} is not in the data: neither per-sample labels nor a meta/manifest column; available: {have}{', '.join(cols)} "
            "(label phone recordings with intervals files listed in the folder's manifest.csv: gaitml.pipeline.folder_source)."
        )
    present = sorted({str(x) for r in labelled for x in np.unique(r.labels)})
    for x in d["labels"]:
        if x not in present:
            raise ConfigError(f"data.labels has {x!r}, which is not a label of the data; labels present: {', '.join(present)}.")
    classes = sorted(set(d["labels"])) if d["labels"] else present
    keep_labels = None
    from gaitml.labels import UNLABELLED

    shared = any(r.meta.get("augmented_shares_time") or r.meta.get("augment_full_labels") is not None for r in recs)
    if shared and UNLABELLED in d["labels"]:
        raise ConfigError(
            f"data.labels lists {UNLABELLED!r}, but data.augment.share_time marks every grip {UNLABELLED!r} outside its own stretches; "
            f"remove {UNLABELLED!r} from data.labels or set share_time = false."
        )
    if not d["labels"] and UNLABELLED in present and (shared or any("labelled_from" in r.meta for r in recs)):
        # samples outside every interval of an intervals file, or a turned grip's stretches given to another grip
        # (data.augment.share_time): left out, not a class
        classes = [c for c in present if c != UNLABELLED]
        keep_labels = classes
        why = "another grip's stretches, data.augment.share_time" if shared else "outside every interval"
        notes.append(
            f"windows labelled {UNLABELLED!r} ({why}) are left out" + ("" if shared else "; list it in data.labels to keep it as a class")
        )
    if len(classes) < 2:
        raise ConfigError(
            f"data.label = {label!r} has {len(classes)} class in the data ({', '.join(classes) or 'none'}); "
            "a classifier needs at least 2: use data with two or more labels or another data.label."
        )
    missing = [r.name for r in recs if group not in r.meta]
    if missing:
        raise ConfigError(
            f"data.group = {group!r} is not a meta/manifest column of recording {missing[0]!r}; columns: {', '.join(cols)} "
            "(a folder of phone recordings needs a manifest.csv with file, subject, ...)."
        )
    groups = [str(r.meta[group]) for r in recs]
    c = cfg["cv"]
    check_groups(c["scheme"], groups, c["n_splits"], group_key=group)
    labelled = _through_acc_range(labelled, cfg["features"]["acc_range_ms2"], notes)
    return PreparedData(labelled, groups, notes, keep_labels)


def _through_acc_range(recs: list, range_ms2: float, notes: list[str]) -> list:
    """``recs`` read through the accelerometer range ``range_ms2`` (``features.acc_range_ms2``; 0: as they are).

    Every recording of the training set, real and simulated, augmented copies included
    (turned first, then read by the range, as the phone's sensor would), clipped per axis
    (:mod:`gaitml.features._range`): the classifier, cross-validation and the domain record
    all read the windows as :func:`gaitml.models.predict_recording` will. A note says how many
    samples were clipped.
    """
    from gaitml.features import acc_range_tally, check_acc_range, clip_acc

    r = check_acc_range(range_ms2)
    if r is None:
        return recs
    out, n_clip, n_all, n_recs = [], 0, 0, 0
    for rec in recs:
        t = acc_range_tally(rec.acc, r)
        n_all += t["n_samples"]
        if t["n_samples_clipped"]:
            n_clip += t["n_samples_clipped"]
            n_recs += 1
            rec = rec.replace(acc=clip_acc(rec.acc, r), check_units=False)
        out.append(rec)
    notes.append(
        f"accelerometer read through +-{r:g} m/s^2 per axis (features.acc_range_ms2): {n_clip} of {n_all} samples clipped "
        f"in {n_recs} of {len(recs)} recordings"
    )
    return out


def build_dataset(
    cfg: ExperimentConfig, data: PreparedData, *, need_raw: bool | None = None, need_features: bool | None = None, use_cache: bool = True
):
    """Window the prepared recordings with the config's window and feature settings."""
    from gaitml.models import model_class

    input_kind = model_class(cfg["model"]["kind"]).input_kind
    need_raw = input_kind == "raw" if need_raw is None else need_raw
    need_features = input_kind == "features" if need_features is None else need_features
    w = cfg["windows"]
    key = json.dumps([_data_key(cfg), w, cfg["features"], need_raw, need_features], sort_keys=True, default=str)
    if use_cache and key in _DS_CACHE:
        return _DS_CACHE[key]
    if w["by"] != "time":
        ds = _build_step_dataset(cfg, data, need_raw=need_raw, need_features=need_features)
    else:
        ds = _build_time_dataset(cfg, data, need_raw=need_raw, need_features=need_features)
    if use_cache:
        if len(_DS_CACHE) > 4:
            _DS_CACHE.clear()
        _DS_CACHE[key] = ds
    return ds


def _build_time_dataset(cfg: ExperimentConfig, data: PreparedData, *, need_raw: bool, need_features: bool):
    """Fixed-length time windows (``windows.by = "time"``, paper 003 sec. 3.3)."""
    from gaitml.models import build_window_dataset

    w = cfg["windows"]
    return build_window_dataset(
        data.recordings,
        groups=data.groups,
        length_s=w["length_s"],
        overlap=w["overlap"],
        min_label_fraction=w["min_label_fraction"],
        feature_set=cfg["features"]["set"],
        keep_labels=cfg["data"]["labels"] or data.keep_labels,
        need_features=need_features,
        need_raw=need_raw,
        frame=cfg["features"]["frame"],
    )


def _build_step_dataset(cfg: ExperimentConfig, data: PreparedData, *, need_raw: bool, need_features: bool):
    """One window per detected step or stride (``windows.by = "steps" | "strides"``, :mod:`gaitml.features.step_windows`)."""
    from gaitml.models import build_step_window_dataset

    w = cfg["windows"]
    return build_step_window_dataset(
        data.recordings,
        groups=data.groups,
        by=w["by"],
        detector=w["detector"] or None,
        min_label_fraction=w["min_label_fraction"],
        feature_set=cfg["features"]["set"],
        keep_labels=cfg["data"]["labels"] or data.keep_labels,
        need_features=need_features,
        need_raw=need_raw,
    )


def _window_info(cfg: ExperimentConfig) -> dict:
    """The ``window`` block of model.json: time-window settings, plus ``by``/``detector`` for step windows.

    A time-window model keeps the block it always had (``length_s``, ``overlap``,
    ``min_label_fraction``), so its model.json is unchanged; loading a model without
    ``by`` reads it as time windows.
    """
    w = cfg["windows"]
    info = {k: w[k] for k in ("length_s", "overlap", "min_label_fraction")}
    if w["by"] != "time":
        from gaitml.features.step_windows import RAW_SPAN_SAMPLES, check_window_by

        info.update(by=w["by"], detector=check_window_by(w["by"], w["detector"]), raw_length_samples=RAW_SPAN_SAMPLES[w["by"]])
    return info


def default_run_dir(cfg: ExperimentConfig) -> Path:
    """``runs/<name>/<UTC timestamp>/`` below the current folder."""
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y%m%dT%H%M%SZ")
    return Path("runs") / cfg.name / stamp


def _point_label(point: dict) -> str:
    return ", ".join(f"{k}={v}" for k, v in point.items()) or "(base)"


def has_copies(data: PreparedData) -> bool:
    """Whether ``data`` holds augmented copies or originals sharing their time with copies (:mod:`gaitml.pipeline.augment`)."""
    return any(r.meta.get("augmented") or r.meta.get("augment_full_labels") is not None for r in data.recordings)


def dataset_without_copies(
    cfg: ExperimentConfig,
    data: PreparedData,
    *,
    need_raw: bool | None = None,
    need_features: bool | None = None,
    keep_in_domain: bool = False,
):
    """The window data set of ``data``'s recordings as they were (:func:`gaitml.pipeline.augment.without_copies`).

    Copies dropped, originals with all their labelled windows: what cross-validation scores.
    ``keep_in_domain``: the tempo copies kept too (meta ``augment_in_domain``), what the domain
    record is fitted on. Cached on ``data`` per window and feature setting.
    """
    from gaitml.pipeline.augment import without_copies

    key = json.dumps(
        [cfg["windows"], cfg["features"]["set"], cfg["features"]["frame"], need_raw, need_features, keep_in_domain],
        sort_keys=True,
        default=str,
    )
    cache = data.__dict__.setdefault("_plain_datasets", {})
    if key not in cache:
        recs, groups = without_copies(data.recordings, data.groups, keep_in_domain=keep_in_domain)
        plain = PreparedData(recs, groups, data.notes, keep_labels=data.keep_labels)
        cache.clear()
        cache[key] = build_dataset(cfg, plain, need_raw=need_raw, need_features=need_features, use_cache=False)
    return cache[key]


def _evaluate_point(cfg: ExperimentConfig, data: PreparedData, progress: bool, desc: str) -> dict:
    from gaitml.evaluation.cv import cross_validate

    t0 = time.perf_counter()
    ds = build_dataset(cfg, data)
    # augmented copies train every fold but are not scored: the left-out people are scored on their recordings as they were
    test_ds = dataset_without_copies(cfg, data) if has_copies(data) else None
    t_ds = time.perf_counter() - t0
    labels = cfg["data"]["labels"] or None
    if labels is None and cfg["data"]["source"] == "simulated":
        sim = cfg["data"]["simulated"]
        order = sim["positions"] if cfg["data"]["label"] == "position" else sim["modes"]
        labels = [m for m in order if m in set(ds.y)]
    c = cfg["cv"]
    t1 = time.perf_counter()
    res = cross_validate(
        ds,
        cfg["model"]["kind"],
        cfg["model"]["params"],
        scheme=c["scheme"],
        n_splits=c["n_splits"],
        n_jobs=c["n_jobs"],
        seed=cfg.seed,
        labels=labels,
        progress=progress,
        description=desc,
        test_dataset=test_ds,
    )
    return {
        "dataset": ds,
        "test_dataset": ds if test_ds is None else test_ds,
        "cv": res,
        "dataset_s": t_ds,
        "cv_s": time.perf_counter() - t1,
    }


def _headline(cfg: ExperimentConfig, res) -> dict:
    use_after = cfg["postprocess"]["adjacent_correction"]
    final = res.after if use_after else res.before
    return {
        "accuracy": final["accuracy"],
        "macro_f1": final["macro_f1"],
        "accuracy_before_correction": res.before["accuracy"],
        "macro_f1_before_correction": res.before["macro_f1"],
        "accuracy_after_correction": res.after["accuracy"],
        "macro_f1_after_correction": res.after["macro_f1"],
        "correction_applied": bool(use_after),
        "per_class": final["per_class"],
        "labels": final["labels"],
        "confusion": final["confusion"],
        "confusion_before_correction": res.before["confusion"],
    }


def evaluate_config(
    cfg: ExperimentConfig, *, out_dir: str | Path | None = None, progress: bool = True, write: bool = True, n_jobs: int | None = None
) -> dict:
    """Cross-validate a config (every sweep point) and write its run folder.

    Returns
    -------
    dict
        The ``gaitml evaluate --json`` object: ``accuracy``, ``macro_f1`` (after
        the correction when ``postprocess.adjacent_correction``), the values
        before/after the correction, ``per_class``, ``confusion``, ``folds``,
        window counts, ``run_dir``; with a sweep also ``sweep`` (one row per grid
        point) and ``best`` (the grid point with the highest accuracy, whose
        numbers are the headline).

    ``n_jobs`` overrides ``cv.n_jobs`` (the Dask backend uses -1). A ``task = "steps"``
    config runs :func:`gaitml.pipeline.steps_real.evaluate_steps_config` instead.
    """
    from gaitml.pipeline.report import write_run

    if cfg.task == "steps":
        from gaitml.pipeline.steps_real import evaluate_steps_config

        return evaluate_steps_config(cfg, out_dir=out_dir, progress=progress)

    if n_jobs is not None:
        cfg = cfg.with_values({"cv.n_jobs": n_jobs}) if not cfg.sweep else _with_sweep(cfg, {"cv.n_jobs": n_jobs})

    data = prepare_data(cfg)
    grid = sweep_grid(cfg)
    points = []
    for i, point in enumerate(grid):
        pcfg = cfg.with_values(point) if point else cfg
        desc = f"{cfg.name} {i + 1}/{len(grid)}" if len(grid) > 1 else cfg.name
        r = _evaluate_point(pcfg, data, progress, desc)
        r["point"] = point
        r["cfg"] = pcfg
        points.append(r)
    rows = []
    for r in points:
        ds, res = r["dataset"], r["cv"]
        s = res.summary()
        rows.append(
            {
                **{k: v for k, v in r["point"].items()},
                "accuracy_before": s["accuracy_before"],
                "accuracy_after": s["accuracy_after"],
                "macro_f1_before": s["macro_f1_before"],
                "macro_f1_after": s["macro_f1_after"],
                "fold_accuracy_mean_before": s["fold_accuracy_mean_before"],
                "fold_accuracy_std_before": s["fold_accuracy_std_before"],
                "fold_accuracy_mean_after": s["fold_accuracy_mean_after"],
                "n_windows": len(ds),
                "n_dropped": ds.n_dropped_fraction + ds.n_dropped_label,
                "n_features": len(ds.feature_names),
                "cv_s": round(r["cv_s"], 3),
            }
        )
    key = "accuracy_after" if cfg["postprocess"]["adjacent_correction"] else "accuracy_before"
    best_i = int(np.argmax([row[key] for row in rows]))
    best = points[best_i]
    res, ds = best["cv"], best["dataset"]
    result = {
        "name": cfg.name,
        **_headline(best["cfg"], res),
        "folds": res.folds.to_dict(orient="records"),
        "scheme": cfg["cv"]["scheme"],
        "model_kind": best["cfg"]["model"]["kind"],
        "feature_set": best["cfg"]["features"]["set"],
        "window_length_s": best["cfg"]["windows"]["length_s"],
        "window_by": best["cfg"]["windows"]["by"],
        "window_detector": _window_info(best["cfg"]).get("detector", ""),
        "n_windows": len(ds),
        "n_windows_total": ds.n_total,
        "n_dropped_label_fraction": ds.n_dropped_fraction,
        "n_dropped_other_labels": ds.n_dropped_label,
        "dropped_labels": ds.dropped_labels,
        "skipped_recordings": ds.skipped_recordings,
        "n_recordings": len(data.recordings),
        "n_groups": len(set(data.groups)),
        "notes": data.notes,
    }
    if cfg.sweep:
        result["sweep"] = rows
        result["best"] = best["point"]
    if write:
        run_dir = Path(out_dir) if out_dir is not None else default_run_dir(cfg)
        write_run(run_dir, cfg, result, points, rows)
        result["run_dir"] = str(run_dir)
    return result


def _with_sweep(cfg: ExperimentConfig, overrides: dict) -> ExperimentConfig:
    import dataclasses

    return dataclasses.replace(cfg.with_values(overrides), sweep=cfg.sweep)


def fit_training_domain(cfg: ExperimentConfig, data: PreparedData, ds, model):
    """The domain record of a trained model (:mod:`gaitml.models.domain`).

    Distances on the model's own features (feature models) or on ``all52`` /
    ``all52+gyro`` of the same windows (raw-input models), in the config's frame; the
    gravity direction of every window in the phone frame; positions from the
    recordings' meta ``position`` (``"unknown"`` where absent); held-out thresholds
    over the config's groups.

    Augmented copies of real recordings (:mod:`gaitml.pipeline.augment`) train the
    classifier but not the domain record, which is fitted on the recordings as they were
    (:func:`gaitml.pipeline.augment.without_copies`: copies dropped, originals with all their
    windows): it holds the grips the walkers really used (a copy turned about the swing axis
    points gravity where no walker held the phone, and other carrying positions, a bag, would
    pass the gravity test there), and its held-out quantile thresholds are not pulled towards
    the augmented position. The tempo copies of ``data.augment.tempo`` are the exception (meta
    ``augment_in_domain``) unless ``data.augment.tempo_in_domain = false``: a run replayed faster
    or slower is a motion in a grip the runners used, and the record keeps them, so that a runner
    faster than the training people is not flagged for their tempo; their own turned, flipped and
    rate copies stay out.

    The record also holds the lowest sampling rate the model was trained at
    (:func:`training_min_rate`, over every training recording, rate copies included): a recording
    made at a lower rate is out of domain whatever its features say
    (:func:`gaitml.models.rate_reason`).

    ``[train] domain_acc_range_ms2``: the record alone reads every training recording
    through that accelerometer range (:func:`gaitml.features.clip_acc`; features, gravity
    and dynamics of the clipped signal) and keeps it (``DomainModel.acc_range_ms2``), so
    :func:`gaitml.models.predict_recording` reads every recording's check the same way;
    the classifier keeps the recordings as they came.
    """
    dom = _fit_domain_of(cfg, data, ds, model)
    dom.min_rate_hz = training_min_rate(data.recordings, float(ds.sampling_rate_hz))
    return dom


def training_min_rate(recs, model_rate_hz: float) -> float:
    """The lowest sampling rate whose information the training recordings carry (Hz).

    A recording recorded at ``f`` Hz and brought to the model's rate carries the information of
    ``min(f, model rate)``: its own rate when it was up-sampled (``meta['resampled_from_hz']``,
    the rate copies of ``data.augment.rates`` included), the model's when it was recorded faster
    and down-sampled (the anti-alias filter keeps nothing above the model's rate). The minimum
    over ``recs``, each read as predict's rate check reads a recording
    (:func:`gaitml.recording.recorded_rate_hz`).
    """
    from gaitml.recording import recorded_rate_hz

    rates = [min(float(model_rate_hz), recorded_rate_hz(r.sampling_rate_hz, r.meta)) for r in recs]
    return min(rates) if rates else float(model_rate_hz)


def _fit_domain_of(cfg: ExperimentConfig, data: PreparedData, ds, model):
    """:func:`fit_training_domain` without the rate: the record fitted on the recordings as they were."""
    from gaitml.pipeline.augment import without_copies

    if has_copies(data):
        # the tempo copies (augment_in_domain) stay: a runner at another tempo is in the domain (gaitml.pipeline.augment)
        keep = any(r.meta.get("augment_in_domain") for r in data.recordings)
        recs, groups = without_copies(data.recordings, data.groups, keep_in_domain=keep)
        plain = PreparedData(recs, groups, data.notes, keep_labels=data.keep_labels)
        return _fit_domain_on(cfg, plain, dataset_without_copies(cfg, data, keep_in_domain=keep), model)
    return _fit_domain_on(cfg, data, ds, model)


def _fit_domain_on(cfg: ExperimentConfig, data: PreparedData, ds, model):
    """The domain record fitted on every window of ``ds`` (the windows of ``data``'s recordings)."""
    from gaitml.features import feature_names, features_from_arrays, resolve_subset
    from gaitml.features.step_windows import extract_step_features
    from gaitml.models.domain import DYNAMICS_NAMES, fit_domain, orientation_dynamics, span_gravity, window_gravity

    frame = cfg["features"]["frame"]
    rec_idx = ds.recording_index
    starts = ds.windows["start"].to_numpy(np.int64)
    ends = ds.windows["end"].to_numpy(np.int64)
    length = int(ends[0] - starts[0])
    by_steps = cfg["windows"]["by"] != "time"  # step windows differ in length: gravity and features per span
    if model.input_kind == "features":
        fset, X = resolve_subset(ds.feature_set), ds.inputs("features")
    else:
        fset = "all52+gyro" if any(c.startswith("gyr") for c in ds.raw_channels) else "all52"
        X = np.zeros((len(ds), len(feature_names(fset))))
    gravity = np.zeros((len(ds), 3))
    positions = np.empty(len(ds), dtype=object)
    # the orientation-dynamics part needs the gyroscope (gaitml.models.domain; without it the check is weak)
    with_dynamics = "gyro" in fset.split("+") and cfg["train"]["domain_dynamics"]
    dynamics = np.zeros((len(ds), len(DYNAMICS_NAMES))) if with_dynamics else None
    from gaitml.features import check_acc_range, clip_acc

    dom_range = check_acc_range(cfg["train"]["domain_acc_range_ms2"])
    if dom_range is not None and model.input_kind == "features":  # the model's features read the unclipped recordings
        X = np.zeros((len(ds), len(feature_names(fset))))
    for i in np.unique(rec_idx):
        rows = np.flatnonzero(rec_idx == i)
        rec = data.recordings[int(i)]
        if dom_range is not None:
            rec = rec.replace(acc=clip_acc(rec.acc, dom_range), check_units=False)
        if dynamics is not None:
            dynamics[rows] = orientation_dynamics(rec.acc, rec.gyr, starts[rows], ends[rows], rec.sampling_rate_hz)
        gravity[rows] = span_gravity(rec.acc, starts[rows], ends[rows]) if by_steps else window_gravity(rec.acc, starts[rows], length)
        positions[rows] = str(rec.meta.get("position") or "unknown")
        own = model.input_kind == "features" and dom_range is None  # the model's own feature matrix serves
        if not own and by_steps:
            X[rows] = extract_step_features(rec, ds.windows.iloc[rows], subset=fset).to_numpy(dtype=float)
        elif not own:
            gyr = rec.gyr if "gyro" in fset.split("+") else None
            X[rows] = features_from_arrays(rec.acc, gyr, rec.sampling_rate_hz, starts[rows], length, fset, frame)
    record = fit_domain(
        X,
        ds.y,
        ds.groups,
        gravity,
        feature_names=feature_names(fset),
        feature_set=fset,
        frame=frame,
        positions=positions,
        seed=cfg.seed,
        dynamics=dynamics,
        sequence=rec_idx,
    )
    if dom_range is not None:
        record.acc_range_ms2 = dom_range
    return record


def window_sources(data: PreparedData, ds) -> list[dict]:
    """Where the training windows come from: one entry per (real | simulated, position), windows per label.

    A recording is simulated when its meta ``source`` is ``gaitml.simulate``, a rotated copy of a real
    recording (meta ``augmented``, :mod:`gaitml.pipeline.augment`) is ``real, turned``, else real; its
    position is the meta ``motion`` (a tyrex recording's carrying motion, e.g. ``FrontPocket``)
    or else ``position`` (the simulator's carrying position). The model card prints the table
    (which modes were learnt from real recordings and which from the simulator).
    """
    counts: dict[tuple[str, str], dict[str, int]] = {}
    recs = data.recordings
    for idx, lab in zip(ds.windows["recording"].to_numpy(), ds.windows["label"].astype(str).to_numpy(), strict=True):
        meta = recs[int(idx)].meta
        turned = meta.get("augmented") and ("turned" in meta["augmented"] or "flipped" in meta["augmented"])
        kind = "simulated" if meta.get("source") == "gaitml.simulate" else ("real, turned" if turned else "real")
        if meta.get("augment_tempo"):
            kind += f", tempo {float(meta['augment_tempo']):g}x"
        if meta.get("augment_rate_hz"):
            kind += f", at {float(meta['augment_rate_hz']):g} Hz"
        where = str(meta.get("motion") or meta.get("position") or "unknown")
        row = counts.setdefault((kind, where), {})
        row[lab] = row.get(lab, 0) + 1
    return [{"kind": k, "position": w, "windows": dict(sorted(c.items()))} for (k, w), c in sorted(counts.items())]


def attach_training_domain(cfg: ExperimentConfig, model_dir: str | Path, out_dir: str | Path | None = None):
    """Record the training domain of an existing model without refitting its classifier.

    For a model saved before gaitml recorded domains (or converted from a pickle): the
    training data of ``cfg`` (the config the model was trained with) is prepared and
    windowed again, the domain is fitted on it (:func:`fit_training_domain`) and the
    model is saved again with the same estimator, settings, scores and creation time
    plus ``feature_frame`` and ``domain``. The config must give the model's feature
    names, window and rate, else ConfigError.

    Returns
    -------
    TrainedModel (saved to ``out_dir``, default ``model_dir`` itself, atomically)
    """
    from gaitml.models import load_model, save_model

    model = load_model(model_dir)
    w = cfg["windows"]
    mine = (model.feature_set, model.length_s, model.overlap, model.sampling_rate_hz, model.frame, model.acc_range_ms2 or 0.0)
    theirs = (
        cfg["features"]["set"],
        float(w["length_s"]),
        float(w["overlap"]),
        float(cfg["data"]["resample_hz"]),
        cfg["features"]["frame"],
        float(cfg["features"]["acc_range_ms2"]),
    )
    if mine != theirs:
        raise ConfigError(
            f"config {cfg.name} (feature set, window, overlap, rate, frame, accelerometer range = {theirs}) is not the one model {model_dir} was trained with "
            f"({mine}); pass the model's own training config."
        )
    data = prepare_data(cfg)
    ds = build_dataset(cfg, data)
    if model.input_kind == "features" and list(ds.feature_names) != model.feature_names:
        raise ConfigError(f"the features of config {cfg.name} differ from the model's; pass the model's own training config.")
    domain = fit_training_domain(cfg, data, ds, model)
    domain.summary["recorded"] = f"after training, from config {cfg.name!r} (seed {cfg.seed}); the classifier was not refitted"
    info = {k: v for k, v in model.info.items() if k != "domain"}
    info["feature_frame"] = model.frame
    return save_model(
        out_dir if out_dir is not None else model_dir, model.estimator, info, created_utc=info.get("created_utc"), domain=domain
    )


def train_config(cfg: ExperimentConfig, *, out_dir: str | Path | None = None, progress: bool = True):
    """Train the config's model on all its windows and save the artifact.

    The model folder is ``out_dir``, else ``train.model_dir`` (relative to the
    config), else ``models/<name>``. With ``train.cross_validate`` the config's
    cross-validation runs first and its scores go into ``model.json``.

    Returns
    -------
    TrainedModel
    """
    from gaitml.features import feature_names
    from gaitml.models import make_model, save_model

    if cfg.task != "classification":
        raise ConfigError(f"gaitml train needs a classification config; {cfg.name} has task = {cfg.task!r}: run it with gaitml evaluate.")
    if cfg.sweep:
        raise ConfigError(
            f"gaitml train takes one setting but the config has a [sweep] over {', '.join(cfg.sweep)}; remove [sweep] or pick one value."
        )
    data = prepare_data(cfg)
    target = Path(out_dir) if out_dir is not None else (cfg.model_dir or Path("models") / cfg.name)
    cv_scores = None
    if cfg["train"]["cross_validate"]:
        r = _evaluate_point(cfg, data, progress, f"{cfg.name} cv")
        s = r["cv"].summary()
        cv_scores = {
            "scheme": cfg["cv"]["scheme"],
            **s,
            "per_class_before": r["cv"].before["per_class"],  # for the model card (MODEL.md)
            "per_class_after": r["cv"].after["per_class"],
            "folds": r["cv"].folds.to_dict(orient="records"),
        }
        if has_copies(data):
            cv_scores["copies_not_scored"] = True  # the model card says so
    ds = build_dataset(cfg, data)
    kind = cfg["model"]["kind"]
    model = make_model(kind, cfg["model"]["params"], seed=cfg.seed)
    t0 = time.perf_counter()
    model.fit(ds.inputs(model.input_kind), ds.y)
    fit_s = time.perf_counter() - t0
    fset = cfg["features"]["set"]
    info = {
        "name": cfg.name,
        "model_kind": kind,
        "model_params": cfg["model"]["params"],
        "input_kind": model.input_kind,
        "feature_set": fset,
        "feature_names": list(feature_names(fset)) if model.input_kind == "features" else [],
        "raw_channels": list(ds.raw_channels) if model.input_kind == "raw" else [],
        "window": _window_info(cfg),
        "sampling_rate_hz": ds.sampling_rate_hz,
        "labels": [str(x) for x in model.classes_],
        "postprocess": cfg["postprocess"],
        "training_config": cfg.resolved(),
        "training_data": {
            "n_windows": len(ds),
            "n_recordings": len(data.recordings),
            "groups": sorted(set(data.groups)),
            "notes": data.notes,
            "sources": window_sources(data, ds),
        },
        "fit_s": round(fit_s, 3),
        "cv_scores": cv_scores,
    }
    if cfg["data"]["source"] == "simulated":
        # the simulator's tilted hand pose at training time (the model card states it)
        from gaitml.simulate.subject import HAND_TILTED_PITCH_DEG

        info["training_data"]["hand_tilted_pitch_deg"] = [float(v) for v in HAND_TILTED_PITCH_DEG]
    if model.input_kind == "features" and list(ds.feature_names) != info["feature_names"]:
        raise InputError(f"the feature table columns differ from feature_names({fset!r}); this is a bug in the feature set definition.")
    info["feature_frame"] = cfg["features"]["frame"]
    if cfg["features"]["acc_range_ms2"]:  # a model without the key reads the accelerometer as it comes
        info["acc_range_ms2"] = float(cfg["features"]["acc_range_ms2"])
    domain = fit_training_domain(cfg, data, ds, model)
    return save_model(target, model, info, domain=domain)
