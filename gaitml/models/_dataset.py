"""Windowed data sets that carry both the feature table and the raw windows.

Feature models (the linear OVO SVM, the MLP) read :attr:`WindowDataset.features`;
the 1-D CNN reads :attr:`WindowDataset.raw`. Both are built from the same window
table, so a cross-validation split means the same windows for every model kind.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np
import pandas as pd

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.recording import Recording, recorded_rate_hz

__all__ = ["WindowDataset", "build_window_dataset", "raw_windows", "raw_window_channels", "resample_recording"]

#: Raw channels fed to the CNN: acc x, y, z and the gravity-free magnitude |acc| - g
#: (the preprocessed magnitude of paper 003 sec. 2.1, without the N = 3 moving average).
#: Anti-alias cut-off of :func:`resample_recording` when it down-samples, as a fraction of the new rate: 0.45 keeps
#: the low-pass's transition band (4th-order Butterworth, zero phase) below the new Nyquist frequency (0.5).
ANTI_ALIAS_FRACTION = 0.45
RAW_ACC_CHANNELS = ("acc_x", "acc_y", "acc_z", "acc_mag")
RAW_GYR_CHANNELS = ("gyr_x", "gyr_y", "gyr_z", "gyr_mag")


def raw_window_channels(feature_set: str, has_gyr: bool) -> tuple[str, ...]:
    """Names of the raw channels for a feature set (gyro only for ``all52+gyro``)."""
    if "gyro" in feature_set:
        if not has_gyr:
            raise InputError(
                f"feature set {feature_set!r} needs a gyroscope but a recording has none; use 'all52' or recordings with gyr_x, gyr_y, gyr_z."
            )
        return RAW_ACC_CHANNELS + RAW_GYR_CHANNELS
    return RAW_ACC_CHANNELS


def raw_windows(
    recording: Recording, starts: np.ndarray, length_samples: int, channels: Sequence[str] = RAW_ACC_CHANNELS, frame: str = "phone"
) -> np.ndarray:
    """Copy the raw samples of every window: shape (n_windows, length_samples, n_channels).

    ``frame='gravity'`` expresses the x, y, z channels of each window in the window's
    gravity-aligned frame (:mod:`gaitml.features._frame`); magnitudes are unchanged.
    """
    from gaitml.features import check_frame, gravity_frame_rotations

    check_frame(frame)
    starts = np.asarray(starts, dtype=np.int64)
    if len(starts) == 0:
        return np.zeros((0, length_samples, len(channels)))
    idx = starts[:, None] + np.arange(length_samples)[None, :]
    rot = gravity_frame_rotations(recording.acc, starts, length_samples) if frame == "gravity" else None
    out = np.empty((len(starts), length_samples, len(channels)))
    for k, c in enumerate(channels):
        if c.startswith("acc_"):
            src = recording.acc
        else:
            src = recording.require_gyr(f"raw channel {c}")
        if c.endswith("_mag"):
            m = np.linalg.norm(src, axis=1)
            out[:, :, k] = (m - GRAVITY_MS2 if c == "acc_mag" else m)[idx]
        elif rot is None:
            out[:, :, k] = src[idx, "xyz".index(c[-1])]
        else:  # row of the window's rotation for this axis, applied to the window's samples
            out[:, :, k] = np.einsum("kc,klc->kl", rot[:, "xyz".index(c[-1])], src[idx])
    return out


def resample_recording(recording: Recording, sampling_rate_hz: float) -> Recording:
    """Return ``recording`` at ``sampling_rate_hz`` (unchanged when the rate already matches).

    Down-sampling first low-passes at :data:`ANTI_ALIAS_FRACTION` (0.45) x the new rate (4th-order Butterworth,
    zero phase) against aliasing; then every channel is linearly interpolated onto
    the new grid (labels: sample-and-hold), as :meth:`Recording.from_timestamps`
    does. ``meta['resampled_from_hz']`` records the rate the recording was made at: the lowest of
    ``recording``'s rate and the rates it was itself resampled from
    (:func:`gaitml.recording.recorded_rate_hz`), so a recording brought up twice (20 -> 50 -> 100 Hz)
    still reads as made at 20 Hz in the rate checks of a model and of a step detector.
    The recording's own clock is kept: ``meta['t0_original_s']`` (the first sample's time on it, which a truth on that
    clock, e.g. a tyrex motion capture, is aligned by) is the input's, not reset to 0.
    """
    fs0 = recording.sampling_rate_hz
    if abs(fs0 - sampling_rate_hz) <= 1e-9 * fs0:
        return recording
    from gaitml.signal import lowpass

    acc, gyr = recording.acc, recording.gyr
    if sampling_rate_hz < fs0:
        cut = ANTI_ALIAS_FRACTION * sampling_rate_hz
        acc = lowpass(acc, cut, fs0)
        gyr = None if gyr is None else lowpass(gyr, cut, fs0)
    # times on the recording's own clock, so that from_timestamps records the same t0_original_s
    t0 = float(recording.meta.get("t0_original_s", 0.0))
    rec = Recording.from_timestamps(
        t0 + recording.t_s,
        acc,
        gyr=gyr,
        labels=recording.labels,
        sampling_rate_hz=sampling_rate_hz,
        meta={**recording.meta, "resampled_from_hz": recorded_rate_hz(fs0, recording.meta)},
        reference=recording.reference,
        anti_alias=False,  # low-passed above
    )
    return rec


@dataclasses.dataclass
class WindowDataset:
    """Windows of many recordings with labels, groups, features and raw samples.

    Attributes
    ----------
    windows : DataFrame
        One row per kept window: ``recording`` (index into ``recording_names``),
        ``group``, ``start``, ``end``, ``t_start_s``, ``t_end_s``, ``label``,
        ``label_fraction``. Rows are in recording order, then time order.
    features : DataFrame or None
        Feature table aligned with ``windows`` (columns ``<channel>__<stat>``).
    raw : ndarray or None, shape (n, length_samples, n_channels)
    recording_names : list of str
    sampling_rate_hz, length_s, overlap : float
    feature_set : str
    frame : str
        Feature frame ('phone' or 'gravity').
    n_total, n_dropped_fraction, n_dropped_label : int
        Windows before filtering; dropped for a weak majority (below
        ``min_label_fraction``); dropped because the label is not in the kept set.
    dropped_labels : dict
        Label -> number of windows dropped because it is not in the kept set.
    skipped_recordings : list of str
        Recordings shorter than one window (no windows; reported, not an error).
    """

    windows: pd.DataFrame
    features: pd.DataFrame | None
    raw: np.ndarray | None
    recording_names: list[str]
    sampling_rate_hz: float
    length_s: float
    overlap: float
    feature_set: str
    raw_channels: tuple[str, ...] = RAW_ACC_CHANNELS
    frame: str = "phone"
    n_total: int = 0
    n_dropped_fraction: int = 0
    n_dropped_label: int = 0
    dropped_labels: dict = dataclasses.field(default_factory=dict)
    skipped_recordings: list = dataclasses.field(default_factory=list)

    def __len__(self) -> int:
        return len(self.windows)

    @property
    def y(self) -> np.ndarray:
        """Window labels (str)."""
        return self.windows["label"].to_numpy().astype(str)

    @property
    def groups(self) -> np.ndarray:
        """Cross-validation group of every window (str)."""
        return self.windows["group"].to_numpy().astype(str)

    @property
    def recording_index(self) -> np.ndarray:
        """Index of the source recording of every window."""
        return self.windows["recording"].to_numpy()

    @property
    def feature_names(self) -> list[str]:
        return [] if self.features is None else list(self.features.columns)

    def inputs(self, input_kind: str, rows=None) -> np.ndarray:
        """The model input: feature matrix ('features') or raw windows ('raw')."""
        rows = slice(None) if rows is None else rows
        if input_kind == "raw":
            if self.raw is None:
                raise InputError("this data set was built without raw windows; build it with need_raw=True for a raw-input model.")
            return self.raw[rows]
        if self.features is None:
            raise InputError("this data set was built without features; build it with need_features=True.")
        return self.features.to_numpy(dtype=float)[rows]


def drop_unkept_labels(windows: pd.DataFrame, keep: set[str], dropped: dict[str, int]) -> tuple[pd.DataFrame, int]:
    """Windows whose label is in ``keep``; the others are counted per label into ``dropped``.

    Returns the kept windows (index reset) and the number dropped.
    """
    bad = ~windows["label"].astype(str).isin(keep)
    for lab, cnt in windows.loc[bad, "label"].astype(str).value_counts().items():
        dropped[lab] = dropped.get(lab, 0) + int(cnt)
    return windows.loc[~bad].reset_index(drop=True), int(bad.sum())


def check_dataset_inputs(recordings, groups, feature_set: str, need_raw: bool) -> tuple[float, tuple[str, ...]]:
    """Checks shared by the window-dataset builders; returns (common sampling rate, raw channels).

    One group per recording and one sampling rate for all; the raw channels are those
    the feature set and the recordings' sensors allow (:func:`raw_window_channels`).
    """
    if len(recordings) == 0:
        raise InputError("no recordings to window; check the data source.")
    if len(groups) != len(recordings):
        raise InputError(f"{len(groups)} groups for {len(recordings)} recordings; give one group per recording.")
    rates = {float(r.sampling_rate_hz) for r in recordings}
    if len(rates) != 1:
        raise InputError(f"recordings have different sampling rates {sorted(rates)}; resample them to one rate first (data.resample_hz).")
    has_gyr = all(r.has_gyr for r in recordings)
    return rates.pop(), (raw_window_channels(feature_set, has_gyr) if need_raw else RAW_ACC_CHANNELS)


def build_window_dataset(
    recordings: Sequence[Recording],
    *,
    groups: Sequence[str],
    length_s: float,
    overlap: float,
    min_label_fraction: float = 0.5,
    feature_set: str = "all52",
    keep_labels: Sequence[str] | None = None,
    need_features: bool = True,
    need_raw: bool = False,
    frame: str = "phone",
) -> WindowDataset:
    """Window every (labelled, same-rate) recording and compute features and/or raw windows.

    Parameters
    ----------
    recordings : list of Recording
        Each with per-sample ``labels`` (a recording-level label is given as a
        constant array) and the same ``sampling_rate_hz``.
    groups : list of str
        Cross-validation group of each recording.
    length_s, overlap, min_label_fraction : window settings (DESIGN sec. 2).
    feature_set : 'all52' | 'paper34' | 'all52+gyro'
    keep_labels : list of str, optional
        Keep only windows with these labels (the others are counted in
        ``dropped_labels``).
    need_features, need_raw : which model inputs to compute.
    frame : 'phone' | 'gravity'
        Feature frame (:func:`gaitml.features.extract_features`); also used for the raw windows.
    """
    from gaitml.features import extract_features, make_windows

    fs, channels = check_dataset_inputs(recordings, groups, feature_set, need_raw)
    tables, feats, raws, names = [], [], [], []
    n_total = n_frac = n_lab = 0
    dropped: dict[str, int] = {}
    skipped: list[str] = []
    keep = None if not keep_labels else {str(x) for x in keep_labels}
    for i, (rec, grp) in enumerate(zip(recordings, groups, strict=True)):
        if rec.labels is None:
            raise InputError(f"recording {rec.name!r} has no labels; give per-sample labels or a label column in the manifest/meta.")
        names.append(rec.name)
        if rec.n_samples < int(round(length_s * rec.sampling_rate_hz)):
            skipped.append(rec.name)  # shorter than one window: nothing to classify
            continue
        w = make_windows(rec, length_s, overlap, min_label_fraction=min_label_fraction)
        n_total += int(w.attrs.get("n_total", len(w)))
        n_frac += int(w.attrs.get("n_dropped", 0))
        w = w.reset_index(drop=True)
        if keep is not None:
            w, n_bad = drop_unkept_labels(w, keep, dropped)
            n_lab += n_bad
        if len(w) == 0:
            continue
        if need_features:
            f = extract_features(rec, w, subset=feature_set, frame=frame)
            feats.append(f.reset_index(drop=True))
        if need_raw:
            length = int(w["end"].iloc[0] - w["start"].iloc[0])
            raws.append(raw_windows(rec, w["start"].to_numpy(), length, channels, frame))
        w = w.assign(recording=i, group=str(grp))
        tables.append(w)
    if not tables:
        raise InputError(
            f"no windows left after windowing ({n_total} in all, {n_frac} below min_label_fraction, {n_lab} with other labels); "
            "use shorter windows, a lower min_label_fraction or other labels."
        )
    windows = pd.concat(tables, ignore_index=True)
    cols = ["recording", "group", "start", "end", "t_start_s", "t_end_s", "label", "label_fraction"]
    windows = windows[[c for c in cols if c in windows.columns]]
    windows["label"] = windows["label"].astype(str)
    features = pd.concat(feats, ignore_index=True) if need_features else None
    raw = np.concatenate(raws, axis=0) if need_raw else None
    return WindowDataset(
        windows=windows,
        features=features,
        raw=raw,
        recording_names=names,
        sampling_rate_hz=fs,
        length_s=float(length_s),
        overlap=float(overlap),
        feature_set=feature_set,
        raw_channels=tuple(channels),
        frame=frame,
        n_total=n_total,
        n_dropped_fraction=n_frac,
        n_dropped_label=n_lab,
        dropped_labels=dropped,
        skipped_recordings=skipped,
    )
