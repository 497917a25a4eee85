"""Reader for the tyrex attitude benchmark (Michel et al., PerCom 2017): phones carried by people, with motion capture.

The data set (``tyrex-attitude/``, CeCILL v2.1) has one folder per recording,
``android/<Person>_Nexus5_<Dist|NoDist>_<Motion>/`` or
``ios/<Person>_<iPhone4S|iPhone5>_<Dist|NoDist>_<Motion>/``, and the phone's
motion capture in ``qualisys/<same name>.csv.gz``. What each platform logs:

- Android (Nexus 5): ``accelerometer.txt(.gz)`` and ``gyroscope-calibrated.txt(.gz)``,
  space-separated ``t x y z`` without a header; ``t`` in s since the recording
  started, acceleration in m/s^2 with gravity (+9.8 along the axis pointing up),
  angular rate in rad/s; about 199 Hz each. ``record.properties`` names the device.
- iOS (iPhone 4S, iPhone 5): ``accelerometer.txt(.gz)`` and ``gyroscope.txt(.gz)``;
  ``t`` in s since the phone booted, made s since the recording's start by
  subtracting ``BootTime`` of ``description.txt``; acceleration in g with the
  opposite sign of Android's (iOS reports -1 g along the axis pointing up), so it
  is multiplied by -9.80665 (what the source's own loader does); rad/s; about
  90-100 Hz, each sensor on its own clock ticks.

The two sensors of a recording never share sample times: they are merged by
:func:`gaitml.io._merge.merge_clocks` (every accelerometer sample kept, the gyroscope
linearly interpolated onto its times and held at its edge samples where it did not run,
reported in ``meta['clock_merge']`` and, past a few samples, one warning line),
then made uniform by :meth:`gaitml.recording.Recording.from_timestamps` (at the
accelerometer's median rate unless ``sampling_rate_hz`` is given).

Gaps are reported, never bridged beyond one stride. A sensor that stops logging
for longer than :func:`gaitml.recording.max_bridge_s` (1 s here) leaves a gap in
the merged stream even when the other sensor runs on (accelerometer samples in
a gyroscope gap are not used: their gyroscope would be invented). Two recordings
have such gaps (``Guillaume_Nexus5_NoDist_AR``: no gyroscope at 67-91 s and
102-114 s; ``Thibaud_iPhone4S_Dist_Texting``: nothing at 110-115 s).
:func:`read_tyrex` refuses them with the gap and the fix, as every reader of
the package refuses a gap too long to bridge; ``segments=True`` (and
:func:`gaitml.io.read_segments`, ``gaitml split``) reads each stretch between
the gaps as its own recording. Every gap found is listed in
``meta['sensor_gaps']``.

``meta`` holds ``subject`` (the person), ``person``, ``phone`` (``Nexus5``,
``iPhone4S``, ``iPhone5``), ``device`` (same), ``platform`` (android | ios),
``motion`` (the folder's suffix as in the source), ``position`` (see
:data:`TYREX_POSITIONS`), ``mode`` (``walk`` or ``run``), ``disturbance``
(``Dist`` | ``NoDist``: magnetic disturbances near the path, irrelevant without a
magnetometer) and ``truth`` (the motion-capture file, or ``''``).

The motion-capture truth is read by :func:`read_tyrex_truth` (see
:class:`TyrexTruth`), on the phone's clock: ``timeAlignment.txt``'s dt, refined by
default against the phone's own gyroscope (:func:`refine_tyrex_alignment`; the
file's dt is 10-30 ms off on most recordings, experiments/reports/tyrex-alignment.md).
The phone's clock is the recording's start, not its first sample: a recording's
times are ``meta['t0_original_s'] + t_s`` (:meth:`TyrexTruth.recording_times`).

References
----------
T. Michel, P. Genevès, H. Fourati, N. Layaïda, "On attitude estimation with
smartphones", IEEE PerCom 2017 (the data set: tyrex-team/benchmarks-attitude-smartphones).
"""

from __future__ import annotations

import dataclasses
import os
import re
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.io._common import head_lines, require_file
from gaitml.io._merge import check_times, merge_clocks
from gaitml.recording import Recording, max_bridge_s

__all__ = [
    "TYREX_MOTIONS",
    "TYREX_POSITIONS",
    "TYREX_MODES",
    "TyrexTruth",
    "is_tyrex_folder",
    "list_tyrex_folders",
    "parse_tyrex_name",
    "read_tyrex",
    "read_tyrex_truth",
    "refine_tyrex_alignment",
    "tyrex_phone_logs",
    "alignment_note",
    "TYREX_ALIGN_MODES",
    "tyrex_truth_path",
    "is_tyrex_truth_file",
    "tyrex_sensor_gaps",
    "body_rates",
    "estimate_mount_rotation",
]

#: The motions of the data set (folder suffixes, as spelt in the source).
TYREX_MOTIONS = ("Texting", "AR", "Phoning", "Swinging", "FrontPocket", "BackPocket", "RunningHand", "RunningPocket")
#: Carrying position of each motion, in the simulator's names where one matches
#: (:data:`gaitml.simulate.POSITIONS`). The README does not say how the phone was
#: held while running nor which pocket: ``hand`` and ``pocket``.
TYREX_POSITIONS = {
    "Texting": "hand-texting",
    "AR": "hand-ar",
    "Phoning": "hand-phoning",
    "Swinging": "swinging-hand",
    "FrontPocket": "front-pocket",
    "BackPocket": "back-pocket",
    "RunningHand": "hand",
    "RunningPocket": "pocket",
}
#: gaitml motion mode of each motion (:data:`gaitml.consts.MOTION_MODES`).
TYREX_MODES = {m: ("run" if m.startswith("Running") else "walk") for m in TYREX_MOTIONS}
_MOTION_BY_LOWER = {m.lower(): m for m in TYREX_MOTIONS}
_NAME = re.compile(
    r"^(?P<person>[A-Za-z]+)_(?P<phone>Nexus5|iPhone4S|iPhone5)_(?P<dist>Dist|NoDist)_(?P<motion>[A-Za-z]+?)(?P<take>_old)?$"
)
_ACC_FILES = ("accelerometer.txt.gz", "accelerometer.txt")
_GYR_FILES = {"android": ("gyroscope-calibrated.txt.gz", "gyroscope-calibrated.txt"), "ios": ("gyroscope.txt.gz", "gyroscope.txt")}
#: The source's loader: iOS acceleration (g, opposite sign) times -9.80665 is m/s^2 in Android's convention.
IOS_ACC_SCALE = -GRAVITY_MS2


def _first(folder: Path, names) -> Path | None:
    for n in names:
        if (folder / n).is_file():
            return folder / n
    return None


def _platform(folder: Path) -> str | None:
    """'android' (record.properties + calibrated gyroscope), 'ios' (description.txt + gyroscope) or None."""
    if _first(folder, _ACC_FILES) is None:
        return None
    if (folder / "description.txt").is_file() and _first(folder, _GYR_FILES["ios"]) is not None:
        return "ios"
    if (folder / "record.properties").is_file() and _first(folder, _GYR_FILES["android"]) is not None:
        return "android"
    return None


def is_tyrex_folder(path: str | os.PathLike) -> bool:
    """Whether ``path`` is one tyrex recording folder (sensor logs of one platform); never raises."""
    try:
        p = Path(path)
        return p.is_dir() and _platform(p) is not None
    except OSError:
        return False


def parse_tyrex_name(name: str) -> dict[str, Any] | None:
    """Person, phone, disturbance, motion, position and mode from a folder name, or None.

    The motion is matched without regard to case (``Jakob_iPhone4S_NoDist_Backpocket``
    is a ``BackPocket`` recording). The extra take ``..._old`` gets ``take = 'old'``.
    """
    m = _NAME.match(name)
    if not m:
        return None
    motion = _MOTION_BY_LOWER.get(m["motion"].lower())
    if motion is None:
        return None
    return {
        "person": m["person"],
        "phone": m["phone"],
        "disturbance": m["dist"],
        "motion": motion,
        "position": TYREX_POSITIONS[motion],
        "mode": TYREX_MODES[motion],
        "take": "old" if m["take"] else "",
    }


def list_tyrex_folders(path: str | os.PathLike) -> list[Path]:
    """Tyrex recording folders under ``path``: itself, its children, or ``android/`` and ``ios/`` below it.

    Only folders whose name names a person, phone and motion are listed; the static
    calibration recordings (``calib_*``) are not walks and are left out.
    """
    p = Path(path)
    if not p.is_dir():
        return []
    if is_tyrex_folder(p):
        return [p]
    found: list[Path] = []
    for base in (p, p / "android", p / "ios"):
        if base.is_dir():
            found.extend(d for d in sorted(base.iterdir()) if parse_tyrex_name(d.name) and is_tyrex_folder(d))
    return found


def _read_log(path: Path, what: str) -> tuple[np.ndarray, np.ndarray]:
    """Read a ``t x y z`` log: times and (n, 3) values; one-line errors for bad content."""
    try:
        df = pd.read_csv(path, sep=r"\s+", header=None, comment="#", dtype=str)
    except pd.errors.EmptyDataError:
        raise InputError(f"{what} ({path}) is empty; the recording is incomplete: copy the folder again.") from None
    except (OSError, EOFError, UnicodeDecodeError, pd.errors.ParserError) as exc:
        raise InputError(f"cannot read {what} ({path}: {str(exc).splitlines()[0]}); the file may be truncated.") from None
    if df.shape[1] != 4:
        raise InputError(f"{what} ({path.name}) has {df.shape[1]} columns; a tyrex sensor log has 4 (t x y z, space-separated).")
    vals = df.apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
    bad = ~np.isfinite(vals).all(axis=1)
    if bad.any():
        row = int(np.flatnonzero(bad)[0]) + 1
        raise InputError(f"{what} ({path.name}): missing or non-numeric value at row {row}; the file may be truncated.")
    check_times(vals[:, 0], what)
    return vals[:, 0], vals[:, 1:4]


def _ini_value(path: Path, key: str) -> str | None:
    for line in path.read_text(errors="replace").splitlines():
        k, sep, v = line.partition("=")
        if sep and k.strip().lower() == key.lower():
            return v.strip()
    return None


def tyrex_sensor_gaps(t_s: np.ndarray, sensor: str, *, limit_s: float | None = None) -> list[dict[str, Any]]:
    """The intervals of ``t_s`` longer than the bridge limit, as ``{sensor, t_start_s, t_end_s, duration_s}``.

    ``limit_s`` defaults to :func:`gaitml.recording.max_bridge_s` of the median interval.
    """
    t = np.asarray(t_s, dtype=float)
    dt = np.diff(t)
    lim = max_bridge_s(float(np.median(dt))) if limit_s is None else float(limit_s)
    return [
        {"sensor": sensor, "t_start_s": round(float(t[i]), 6), "t_end_s": round(float(t[i + 1]), 6), "duration_s": round(float(dt[i]), 6)}
        for i in np.flatnonzero(dt > lim)
    ]


def tyrex_phone_logs(folder: str | os.PathLike) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The raw logs of a tyrex recording folder on the phone's clock (s since the recording's start), in SI units and
    Android's sign convention, unmerged and unresampled: ``t_acc, acc, t_gyr, gyr`` (what
    :func:`refine_tyrex_alignment` takes)."""
    d = require_file(folder)
    platform = _platform(d)
    if platform is None:
        raise InputError(f"{d} is not a tyrex recording folder: it needs the accelerometer and gyroscope logs (see gaitml.io.tyrex).")
    t_acc, acc, t_gyr, gyr, _boot = _phone_logs(d, platform)
    return t_acc, acc, t_gyr, gyr


def _phone_logs(d: Path, platform: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
    """The raw accelerometer and gyroscope logs of a recording folder on the phone's clock, in SI units and
    Android's sign convention: ``t_acc, acc, t_gyr, gyr, boot_s`` (``boot_s`` NaN on Android)."""
    t_acc, acc = _read_log(_first(d, _ACC_FILES), f"the accelerometer log of {d.name}")
    t_gyr, gyr = _read_log(_first(d, _GYR_FILES[platform]), f"the gyroscope log of {d.name}")
    boot_s = float("nan")
    if platform == "ios":
        boot = _ini_value(d / "description.txt", "BootTime")
        try:
            boot_s = float(boot) if boot is not None else float("nan")
        except ValueError:
            boot_s = float("nan")
        if not np.isfinite(boot_s):
            raise InputError(f"{d.name}/description.txt has no numeric BootTime; the iOS times cannot be put on the recording's clock.")
        t_acc = t_acc - boot_s
        t_gyr = t_gyr - boot_s
        acc = acc * IOS_ACC_SCALE
    return t_acc, acc, t_gyr, gyr, boot_s


def read_tyrex(
    path: str | os.PathLike,
    *,
    sampling_rate_hz: float | None = None,
    segments: bool = False,
    meta: dict | None = None,
) -> Recording | list[Recording]:
    """Read one tyrex recording folder (Android or iOS) into a Recording in SI units.

    Parameters
    ----------
    path : folder
        ``android/<name>/`` or ``ios/<name>/`` (or any folder with the same files).
    sampling_rate_hz : float, optional
        Uniform rate to resample to (default: the accelerometer's median rate,
        about 199 Hz on the Nexus 5, 90-100 Hz on the iPhones).
    segments : bool
        Return the stretches between gaps too long to bridge as a list of
        recordings (``meta['segment']`` says where each lay) instead of refusing them.
    meta : dict, optional
        Extra metadata.

    Returns
    -------
    Recording or list of Recording
        acc (m/s^2, gravity included, Android's sign convention on both platforms),
        gyr (rad/s), at uniform times. ``meta['t0_original_s']`` is the first
        sample's time on the phone's clock (s since the recording's start): the
        time base of :func:`read_tyrex_truth`.

    Raises
    ------
    InputError
        Missing or unreadable logs, decreasing times, clocks that do not overlap,
        or (unless ``segments``) a gap longer than the bridge limit in either sensor,
        naming the gap and the fix.
    """
    d = require_file(path)
    if d.is_file():
        d = d.parent
    platform = _platform(d)
    if platform is None:
        raise InputError(
            f"{d} is not a tyrex recording folder: it needs accelerometer.txt(.gz) with gyroscope-calibrated.txt(.gz) "
            "and record.properties (Android), or with gyroscope.txt(.gz) and description.txt (iOS)."
        )
    t_acc, acc, t_gyr, gyr, boot_s = _phone_logs(d, platform)
    m: dict[str, Any] = {"source": str(d), "format": "tyrex", "id": d.name, "session": d.name, "subject": d.name, "platform": platform}
    parsed = parse_tyrex_name(d.name)
    if parsed is not None:
        m.update(parsed, subject=parsed["person"], device=parsed["phone"])
    if platform == "ios":
        m["converted"] = ["acc from g, sign reversed (iOS convention)", "time minus BootTime"]
        m["boot_time_s"] = boot_s
    else:
        props = d / "record.properties"
        start = _ini_value(props, "StartTime")
        model = _ini_value(props, "Model")
        if start is not None:
            try:
                m["start_unix_s"] = float(start)
            except ValueError:
                pass
        if model:
            m["device_model"] = model
    gaps = tyrex_sensor_gaps(t_acc, "accelerometer") + tyrex_sensor_gaps(t_gyr, "gyroscope")
    # accelerometer samples inside a gyroscope gap would get an invented gyroscope: leave them out
    # so that the merged stream has the gap too (and the usual gap rule applies)
    keep = np.ones(len(t_acc), dtype=bool)
    for g in gaps:
        if g["sensor"] == "gyroscope":
            keep &= ~((t_acc > g["t_start_s"]) & (t_acc < g["t_end_s"]))
    if not keep.all():
        m["acc_samples_in_gyr_gaps"] = int((~keep).sum())
    t, acc_m, gyr_m, info = merge_clocks(t_acc[keep], acc[keep], t_gyr, gyr, what=d.name)
    m["clock_merge"] = info
    if info["warning"]:  # the gyroscope started late or stopped early: its edge samples held there, said once
        m.setdefault("warnings", []).append(info["warning"])
    m["sensor_gaps"] = gaps
    m["n_acc_samples"] = int(len(t_acc))
    m["n_gyr_samples"] = int(len(t_gyr))
    truth = tyrex_truth_path(d)
    m["truth"] = str(truth) if truth is not None else ""
    m.update(meta or {})
    # the merged stream's gaps are where either sensor stopped: one limit for both
    limit = max_bridge_s(float(np.median(np.diff(t))))
    if segments:
        return Recording.segments_from_timestamps(t, acc_m, gyr=gyr_m, sampling_rate_hz=sampling_rate_hz, meta=m, max_gap_s=limit)
    long = [g for g in gaps if g["duration_s"] > limit]
    if long:
        g = long[0]
        raise InputError(
            f"{d.name}: the {g['sensor']} has no samples from {g['t_start_s']:.2f} to {g['t_end_s']:.2f} s ({g['duration_s']:.2f} s; "
            f"{len(long)} gap{'s' if len(long) > 1 else ''} longer than {limit:.3g} s in all), too long to bridge; read the stretches "
            f"between the gaps as separate recordings: `gaitml split {d} --out DIR` (in Python: gaitml.io.read_segments)."
        )
    return Recording.from_timestamps(t, acc_m, gyr=gyr_m, sampling_rate_hz=sampling_rate_hz, meta=m, max_gap_s=limit)


# --------------------------------------------------------------------------- truth


def tyrex_truth_path(folder: str | os.PathLike) -> Path | None:
    """The motion-capture file of a recording folder: ``../../qualisys/<name>.csv(.gz)``, case-insensitive; None if absent.

    The source spells one folder ``Jakob_iPhone4S_NoDist_Backpocket`` and its
    motion capture ``..._BackPocket``: names are compared without regard to case.
    """
    d = Path(folder)
    qdir = d.parent.parent / "qualisys"
    if not qdir.is_dir():
        return None
    want = d.name.lower()
    for f in sorted(qdir.iterdir()):
        if f.name.lower() in (f"{want}.csv.gz", f"{want}.csv"):
            return f
    return None


def is_tyrex_truth_file(path: str | os.PathLike) -> bool:
    """Whether a file is a tyrex motion-capture CSV (its header has the rotation columns ``rot0..rot8``)."""
    try:
        lines = [ln for ln in head_lines(Path(path), 3) if not ln.startswith("#")]
    except Exception:  # noqa: BLE001 - the reader reports unreadable files itself
        return False
    return bool(lines) and "rot0" in lines[0]


@dataclasses.dataclass(frozen=True, eq=False)
class TyrexTruth:
    """The phone's motion capture on the phone's clock.

    Attributes
    ----------
    t_s : ndarray, shape (n,)
        Phone time (s since the recording's start: Android's log time, iOS's log
        time minus BootTime) of each motion-capture frame: ``t_mocap - dt_s``.
    pos_m : ndarray, shape (n, 3)
        Position of the rigid body in the room's frame (x, y horizontal, z up), m;
        NaN where the markers were lost.
    rot : ndarray, shape (n, 3, 3)
        Attitude of the rigid body, body to room: ``v_room = rot @ v_body``; NaN
        where the markers were lost. The source's loader builds the direction-cosine
        matrix as MATLAB ``reshape(rot, 3, 3)'`` (numpy ``reshape(3, 3)`` of
        ``rot0..rot8``) and passes it to ``dcm2quat``, whose DCM maps room vectors
        to body vectors; ``rot`` is its transpose. The direction was checked
        against the phone's gyroscope: with this ``rot`` the body's angular rate
        ``vee(rot_k^T rot_k+1) / dt`` matches the gyroscope through a rotation
        within a few degrees of identity (:func:`estimate_mount_rotation`); with the
        other direction no rotation matches it.
    residual_mm : ndarray, shape (n,)
        QTM's marker residual.
    dt_s : float
        The clock offset applied: motion-capture time = phone time + dt. With
        ``align='file'`` it is ``timeAlignment.txt``'s; with ``align='refine'`` the
        file's corrected by the residual lag :func:`refine_tyrex_alignment` found
        (the file's where none was accepted).
    frame_rate_hz : float
        Motion-capture rate (60 Hz).
    source : str
        The CSV read.
    dt_file_s : float
        ``timeAlignment.txt``'s dt (s), whatever ``align`` was.
    align : dict
        How dt was chosen: ``mode`` (``'file'`` | ``'refine'``), and with ``'refine'``
        the fields of :func:`refine_tyrex_alignment` (``accepted``, ``signal``,
        ``shift_s``, the correlations, ``reason``).
    """

    t_s: np.ndarray
    pos_m: np.ndarray
    rot: np.ndarray
    residual_mm: np.ndarray
    dt_s: float
    frame_rate_hz: float
    source: str
    dt_file_s: float = float("nan")
    align: dict = dataclasses.field(default_factory=dict)

    @property
    def align_note(self) -> str:
        """One line on the clock alignment, for notes and tables."""
        return alignment_note(self.dt_file_s if np.isfinite(self.dt_file_s) else self.dt_s, self.dt_s, self.align)

    @property
    def valid(self) -> np.ndarray:
        """Frames with a position and an attitude (markers seen)."""
        return np.isfinite(self.pos_m).all(axis=1) & np.isfinite(self.rot).all(axis=(1, 2))

    @property
    def quat_wxyz(self) -> np.ndarray:
        """Attitude as unit quaternions ``(w, x, y, z)`` (body to room), NaN where lost."""
        from scipy.spatial.transform import Rotation

        q = np.full((len(self.t_s), 4), np.nan)
        ok = self.valid
        if ok.any():
            xyzw = Rotation.from_matrix(_orthonormal(self.rot[ok])).as_quat()
            q[ok] = np.column_stack([xyzw[:, 3], xyzw[:, :3]])
        return q

    def recording_times(self, recording: Recording) -> np.ndarray:
        """Phone-clock time of every sample of a recording read by :func:`read_tyrex`."""
        t0 = float(recording.meta.get("t0_original_s", 0.0))
        return t0 + recording.t_s

    def position_at(self, t_phone_s) -> np.ndarray:
        """Positions (m) at phone times, linear between frames; NaN outside the capture or next to a lost frame."""
        t = np.asarray(t_phone_s, dtype=float)
        out = np.column_stack([np.interp(t, self.t_s, self.pos_m[:, j], left=np.nan, right=np.nan) for j in range(3)])
        return out

    def rotation_at(self, t_phone_s) -> np.ndarray:
        """Body-to-room rotation matrices at phone times (spherical interpolation); NaN where unknown."""
        from scipy.spatial.transform import Rotation, Slerp

        t = np.asarray(t_phone_s, dtype=float)
        out = np.full((len(t), 3, 3), np.nan)
        ok = self.valid
        if ok.sum() < 2:
            return out
        tk = self.t_s[ok]
        slerp = Slerp(tk, Rotation.from_matrix(_orthonormal(self.rot[ok])))
        inside = (t >= tk[0]) & (t <= tk[-1])
        # a query between two frames with a lost frame between them is not interpolated
        idx = np.searchsorted(self.t_s, t, side="right") - 1
        idx = np.clip(idx, 0, len(self.t_s) - 2)
        near_ok = (ok[idx] & ok[idx + 1]) | (np.isclose(t, self.t_s[idx]) & ok[idx])
        use = inside & near_ok
        if use.any():
            out[use] = slerp(t[use]).as_matrix()
        return out


def _orthonormal(r: np.ndarray) -> np.ndarray:
    """Nearest rotation matrices (SVD) of matrices stored to 5 decimals."""
    u, _, vt = np.linalg.svd(r)
    d = np.sign(np.linalg.det(u @ vt))
    u[..., :, -1] *= d[..., None]
    return u @ vt


#: Ways :func:`read_tyrex_truth` puts the motion capture on the phone's clock: ``'refine'`` (``timeAlignment.txt``'s
#: dt corrected by the residual lag of the angular-rate magnitudes, :func:`refine_tyrex_alignment`) and ``'file'``
#: (``timeAlignment.txt``'s dt as it is, the behaviour before the refinement).
TYREX_ALIGN_MODES = ("refine", "file")
#: Half-width (s) of the lag searched around the file's dt: wide against the residual lags the data set shows (tens of
#: ms; experiments/reports/tyrex-alignment.md), and against a clock error of a recording's late first sample (the
#: Nexus 5 logs start up to about 0.6 s in), while staying inside the file's own search (the source slid |acc| over
#: +-5 s).
ALIGN_SEARCH_S = 1.5
#: Rate (Hz) of the common grid both magnitudes are interpolated to before correlating: one grid step (10 ms) is
#: finer than a capture frame (16.7 ms); the peak is refined between grid steps by a parabola.
ALIGN_GRID_HZ = 100.0
#: Low-pass cut-off (Hz, 4th-order Butterworth run forwards and backwards, so without a delay) applied to both
#: magnitudes: the capture's rates and accelerations are finite differences of 60 Hz frames, noisy above a few Hz,
#: while walking and running put their power below 8 Hz.
ALIGN_LOWPASS_HZ = 8.0
#: A lag is accepted only where the correlation at its peak reaches this (Pearson, on the common samples). The
#: magnitudes of one rigid body's motion measured twice correlate 0.94-0.99 at the right lag on this data set;
#: 0.8 leaves room for a noisier capture and refuses stretches without motion (noise against noise).
ALIGN_MIN_CORR = 0.8
#: ... and only where it beats every other local maximum of the correlation in the search window by this much: gait
#: is periodic, so the neighbouring strides give secondary peaks one stride apart; a peak that is not clearly the
#: highest is not trusted.
ALIGN_MIN_MARGIN = 0.05
#: Fewest seconds of samples where both signals are known for a lag to be measured.
ALIGN_MIN_OVERLAP_S = 10.0
#: Half-width (s) of the search for the lag of the first and last third of a recording (the clock-rate drift check),
#: around the whole recording's lag: a third holds a few strides only, so a narrower window keeps it off the
#: neighbouring strides.
ALIGN_THIRDS_SEARCH_S = 0.25
#: Samples of a grid point's neighbourhood (s) that must be known (no lost capture frame, no sensor gap) for it to
#: count: the finite differences and the filter spread a gap's edge this far.
ALIGN_EDGE_S = 0.1
_GRAVITY_UP = np.array([0.0, 0.0, GRAVITY_MS2])
_ALIGN_CACHE: dict[tuple, dict[str, Any]] = {}


def read_tyrex_truth(
    folder: str | os.PathLike,
    *,
    truth_path: str | os.PathLike | None = None,
    align: str = "refine",
    recording: Recording | list[Recording] | None = None,
) -> TyrexTruth:
    """Read the motion capture of a tyrex recording, on the phone's clock.

    Parameters
    ----------
    folder : the recording folder (``android/<name>/`` or ``ios/<name>/``); its
        ``timeAlignment.txt`` gives dt (motion-capture time = phone time + dt).
    truth_path : the Qualisys CSV; default ``../../qualisys/<name>.csv.gz``
        (case-insensitive, see :func:`tyrex_truth_path`).
    align : ``'refine'`` (default) or ``'file'``
        ``'file'``: ``timeAlignment.txt``'s dt as it is. ``'refine'``: that dt
        corrected by the residual lag between the phone's |gyroscope| and the
        capture's |angular rate| (:func:`refine_tyrex_alignment`; without a
        gyroscope |acc| against the capture's specific force), accepted only where
        the correlation peak is clear, else the file's dt kept and said so in
        ``TyrexTruth.align``. How far the file's dt is off, per recording:
        experiments/reports/tyrex-alignment.md.
    recording : the phone's signals to align on (a :func:`read_tyrex` recording or
        its segments); default: the folder's own logs, read raw (the result is
        cached per folder and capture file).

    Returns
    -------
    TyrexTruth
        Positions in m (room frame, z up) and rotation matrices, NaN where the
        markers were lost (empty cells in the CSV); ``dt_s`` applied, ``dt_file_s``
        and ``align`` say how.

    Raises
    ------
    InputError
        No motion capture for the folder (the ``_old`` take has none), no or a
        non-numeric ``timeAlignment.txt``, a CSV without the documented columns, an
        unknown ``align``.
    """
    if align not in TYREX_ALIGN_MODES:
        raise InputError(f"align={align!r} is not a tyrex alignment; use one of {', '.join(repr(a) for a in TYREX_ALIGN_MODES)}.")
    d = require_file(folder)
    tp = Path(truth_path) if truth_path is not None else tyrex_truth_path(d)
    if tp is None or not tp.is_file():
        raise InputError(
            f"no motion capture for {d.name}: expected {d.parent.parent / 'qualisys' / (d.name + '.csv.gz')}; "
            "pass truth_path, or use a recording that has one (the '_old' take has none)."
        )
    ta = d / "timeAlignment.txt"
    if not ta.is_file():
        raise InputError(f"{d.name} has no timeAlignment.txt; without it the motion capture cannot be put on the phone's clock.")
    try:
        dt_s = float(ta.read_text().split()[0])
    except (ValueError, IndexError):
        raise InputError(f"{ta} does not hold one number (dt in s); copy it again from the source.") from None
    try:
        df = pd.read_csv(tp, comment="#")
        header = head_lines(tp, 1)[0] if tp.stat().st_size else ""
    except (OSError, EOFError, UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise InputError(f"cannot read the motion capture {tp} ({str(exc).splitlines()[0]}); the file may be truncated.") from None
    need = ["t_s", "x_mm", "y_mm", "z_mm", *(f"rot{i}" for i in range(9))]
    missing = [c for c in need if c not in df.columns]
    if missing:
        raise InputError(f"the motion capture {tp.name} lacks the columns {missing}; expected t_s,x_mm,y_mm,z_mm,rot0..rot8,residual_mm.")
    vals = df[need].apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
    t_mocap = vals[:, 0]
    check_times(t_mocap, f"the motion capture {tp.name}")
    rate = 60.0
    m = re.search(r"frame_rate_hz=([0-9.]+)", header)
    if m:
        rate = float(m.group(1))
    resid = pd.to_numeric(df["residual_mm"], errors="coerce").to_numpy(dtype=float) if "residual_mm" in df else np.full(len(df), np.nan)
    truth = TyrexTruth(
        t_s=t_mocap - dt_s,
        pos_m=vals[:, 1:4] / 1000.0,
        rot=np.transpose(vals[:, 4:13].reshape(-1, 3, 3), (0, 2, 1)),
        residual_mm=resid,
        dt_s=dt_s,
        frame_rate_hz=rate,
        source=str(tp),
        dt_file_s=dt_s,
        align={"mode": "file"},
    )
    if align == "file":
        return truth
    if recording is None:
        key = (str(d.resolve()), str(tp.resolve()), tp.stat().st_mtime_ns, ta.stat().st_mtime_ns, dt_s)
        info = _ALIGN_CACHE.get(key)
        if info is None:
            platform = _platform(d)
            if platform is None:
                raise InputError(
                    f"{d} holds no phone logs to refine the alignment on; pass recording=..., or align='file' to use timeAlignment.txt as it is."
                )
            t_acc, acc, t_gyr, gyr, _boot = _phone_logs(d, platform)
            info = refine_tyrex_alignment(truth, t_acc, acc, t_gyr, gyr)
            _ALIGN_CACHE[key] = info
    else:
        t_acc, acc, t_gyr, gyr = _recording_signals(recording)
        info = refine_tyrex_alignment(truth, t_acc, acc, t_gyr, gyr)
    info = {"mode": "refine", **info}
    shift = float(info["shift_s"]) if info["accepted"] else 0.0
    return dataclasses.replace(truth, t_s=truth.t_s + shift, dt_s=dt_s - shift, align=info)


def alignment_note(dt_file_s: float, dt_s: float, align: dict) -> str:
    """One line on how a capture was put on the phone's clock (the file's dt, the refined one, why)."""
    if align.get("mode", "file") == "file":
        return f"timeAlignment dt {dt_file_s:+.3f} s (align='file', not refined)"
    if align.get("accepted"):
        return (
            f"dt {dt_s:+.3f} s: timeAlignment {dt_file_s:+.3f} s refined by {dt_file_s - dt_s:+.3f} s "
            f"(|{align['signal']}| correlation {align['corr_file']:.2f} at the file's dt, {align['corr_peak']:.2f} refined)"
        )
    return f"timeAlignment dt {dt_file_s:+.3f} s kept: not refined ({align.get('reason', 'no clear correlation peak')})"


def _recording_signals(recording) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """A recording's (or its segments') signals on the phone's clock; a gap between segments left as a gap."""
    recs = list(recording) if isinstance(recording, list | tuple) else [recording]
    t = [float(r.meta.get("t0_original_s", 0.0)) + np.asarray(r.t_s, dtype=float) for r in recs]
    acc = [np.asarray(r.acc, dtype=float) for r in recs]
    has_gyr = all(r.gyr is not None for r in recs)
    t_all = np.concatenate(t)
    acc_all = np.concatenate(acc)
    gyr_all = np.concatenate([np.asarray(r.gyr, dtype=float) for r in recs]) if has_gyr else None
    return t_all, acc_all, (t_all if has_gyr else None), gyr_all


def _on_grid(grid: np.ndarray, t: np.ndarray, x: np.ndarray, max_step_s: float) -> tuple[np.ndarray, np.ndarray]:
    """``x(t)`` linearly interpolated at ``grid``, and where that is known: inside ``t`` and between two samples at
    most ``max_step_s`` apart."""
    t = np.asarray(t, dtype=float)
    y = np.interp(grid, t, x) if len(t) else np.zeros_like(grid)
    if len(t) < 2:
        return y, np.zeros(len(grid), dtype=bool)
    i = np.clip(np.searchsorted(t, grid, side="right") - 1, 0, len(t) - 2)
    ok = (grid >= t[0]) & (grid <= t[-1]) & ((t[i + 1] - t[i]) <= max_step_s)
    return y, ok


def _lowpass(x: np.ndarray, fs: float) -> np.ndarray:
    from scipy.signal import butter, filtfilt

    b, a = butter(4, ALIGN_LOWPASS_HZ / (fs / 2))
    return filtfilt(b, a, x) if len(x) > 27 else x


def _erode(ok: np.ndarray, n: int) -> np.ndarray:
    """``ok`` with every run of False widened by ``n`` samples on each side."""
    if n <= 0 or ok.all():
        return ok
    bad = (~ok).astype(float)
    return np.convolve(bad, np.ones(2 * n + 1), mode="same") == 0


def lag_correlation(a: np.ndarray, ok_a: np.ndarray, b: np.ndarray, ok_b: np.ndarray, lags: np.ndarray, min_n: int) -> np.ndarray:
    """Pearson correlation of ``a[i]`` with ``b[i + k]`` for each lag ``k`` (samples) over the ``i`` where both are
    known (``ok_a``, ``ok_b``); NaN where fewer than ``min_n`` samples are common or a side does not vary."""
    n = len(a)
    out = np.full(len(lags), np.nan)
    for j, k in enumerate(np.asarray(lags, dtype=int)):
        if abs(k) >= n:
            continue
        if k >= 0:
            x, y, m = a[: n - k], b[k:], ok_a[: n - k] & ok_b[k:]
        else:
            x, y, m = a[-k:], b[: n + k], ok_a[-k:] & ok_b[: n + k]
        if m.sum() < min_n:
            continue
        x = x[m] - x[m].mean()
        y = y[m] - y[m].mean()
        den = np.sqrt(float(x @ x) * float(y @ y))
        if den > 1e-12 * len(x):
            out[j] = float(x @ y) / den
    return out


def _peak(lags: np.ndarray, c: np.ndarray) -> tuple[float, float, float]:
    """The best lag (samples, refined between samples by a parabola through the peak and its neighbours), its
    correlation, and the highest other local maximum (NaN if none)."""
    j = int(np.nanargmax(c))
    frac = 0.0
    if 0 < j < len(c) - 1 and np.isfinite(c[j - 1]) and np.isfinite(c[j + 1]):
        den = c[j - 1] - 2 * c[j] + c[j + 1]
        if den < 0:
            frac = float(np.clip(0.5 * (c[j - 1] - c[j + 1]) / den, -0.5, 0.5))
    inner = np.arange(1, len(c) - 1)
    cc = np.where(np.isfinite(c), c, -np.inf)
    local = inner[(cc[inner] >= cc[inner - 1]) & (cc[inner] >= cc[inner + 1])]
    # the peak's own shoulders are not another maximum: only maxima separated from it by a dip count
    others = [k for k in local if k != j and np.min(cc[min(k, j) : max(k, j) + 1]) < cc[k] - 1e-9]
    second = float(max(cc[k] for k in others)) if others else float("nan")
    return float(lags[j] + frac), float(c[j]), second


def refine_tyrex_alignment(
    truth: TyrexTruth,
    t_acc: np.ndarray,
    acc: np.ndarray,
    t_gyr: np.ndarray | None,
    gyr: np.ndarray | None,
    *,
    signal: str = "auto",
    window_s: tuple[float, float] | None = None,
    search_s: float = ALIGN_SEARCH_S,
    centre_s: float = 0.0,
) -> dict[str, Any]:
    """The residual lag of a motion capture put on the phone's clock, from frame-invariant magnitudes.

    The phone and the capture's rigid body are one object, so the magnitude of the
    angular rate the gyroscope measures equals that of the capture's attitude
    (:func:`body_rates`), and the magnitude of the accelerometer's specific force
    equals ``|d2p/dt2 + g|`` of the capture's position, whatever the (unknown)
    mount rotation. Both magnitudes are interpolated on a common grid
    (:data:`ALIGN_GRID_HZ`), low-passed without delay (:data:`ALIGN_LOWPASS_HZ`),
    and correlated (Pearson, over the samples where both are known: lost capture
    frames and sensor gaps are left out, :data:`ALIGN_EDGE_S` around them) at every
    shift of the capture within ``centre_s`` +- ``search_s`` (default
    :data:`ALIGN_SEARCH_S`) of the time base ``truth.t_s`` already has. This is the
    source's own method (it slid |acc| against the capture's second derivative,
    data README "Time alignment") run again on the gyroscope, whose magnitude
    needs no differentiation of positions, around the source's result.

    Parameters
    ----------
    truth : the capture on the phone's clock to check (``align='file'``).
    t_acc, acc : phone-clock times (s) and the accelerometer (m/s^2, any axes).
    t_gyr, gyr : the gyroscope (rad/s), or None.
    signal : ``'auto'`` (the gyroscope, |acc| without one), ``'gyro'`` or ``'acc'``.
    window_s : only the phone times in ``[start, end)`` (e.g. a third of the recording).
    search_s, centre_s : the shifts searched (s).

    Returns
    -------
    dict
        ``accepted`` (bool), ``signal`` (``'gyro'`` | ``'acc'`` | None), ``shift_s``
        (to add to ``truth.t_s``; the capture's dt becomes ``dt - shift_s``; NaN
        where nothing was measured), ``corr_file`` (correlation at ``shift 0``, the
        time base given), ``corr_peak``, ``corr_second`` (the best other local
        maximum), ``overlap_s``, ``reason`` (why not accepted, else ``''``). Accepted
        where ``corr_peak >= ALIGN_MIN_CORR`` and it beats ``corr_second`` by
        :data:`ALIGN_MIN_MARGIN`.
    """
    if signal not in ("auto", "gyro", "acc"):
        raise InputError(f"signal={signal!r} is not an alignment signal; use 'auto', 'gyro' or 'acc'.")
    use = "gyro" if (signal == "gyro" or (signal == "auto" and gyr is not None and t_gyr is not None and len(t_gyr) > 1)) else "acc"
    out: dict[str, Any] = {
        "accepted": False,
        "signal": use,
        "shift_s": float("nan"),
        "corr_file": float("nan"),
        "corr_peak": float("nan"),
        "corr_second": float("nan"),
        "overlap_s": 0.0,
        "search_s": float(search_s),
        "reason": "",
    }
    if use == "gyro" and (gyr is None or t_gyr is None):
        out["reason"] = "no gyroscope"
        return out
    fs = ALIGN_GRID_HZ
    ok_frames = truth.valid
    if ok_frames.sum() < 3:
        out["reason"] = "the capture has fewer than 3 tracked frames"
        return out
    t_phone = np.asarray(t_gyr if use == "gyro" else t_acc, dtype=float)
    x_phone = np.linalg.norm(np.asarray(gyr if use == "gyro" else acc, dtype=float), axis=1)
    t_cap = truth.t_s
    lo = max(t_phone[0], t_cap[ok_frames][0] - centre_s - search_s)
    hi = min(t_phone[-1], t_cap[ok_frames][-1] - centre_s + search_s)
    if window_s is not None:
        lo, hi = max(lo, window_s[0]), min(hi, window_s[1])
    if hi - lo < ALIGN_MIN_OVERLAP_S:
        out["reason"] = f"the phone and the capture overlap for {max(hi - lo, 0.0):.1f} s (< {ALIGN_MIN_OVERLAP_S:g} s)"
        return out
    max_lag = int(np.ceil((abs(centre_s) + search_s) * fs))
    # the capture's grid reaches max_lag beyond the phone's so that every shift sees the same phone samples
    grid = lo + np.arange(int(np.floor((hi - lo) * fs)) + 1) / fs
    grid_c = lo - max_lag / fs + np.arange(len(grid) + 2 * max_lag) / fs
    frame_gap = 1.5 / truth.frame_rate_hz
    step_max = max(frame_gap, 0.05)
    a, ok_a = _on_grid(grid, t_phone, x_phone, step_max)
    a = _lowpass(a, fs)
    if use == "gyro":
        t_mid, omega = body_rates(truth)
        b, ok_b = _on_grid(grid_c, t_mid, np.linalg.norm(omega, axis=1), frame_gap * 2)
    else:
        tk = t_cap[ok_frames]
        pos = np.column_stack([np.interp(grid_c, tk, truth.pos_m[ok_frames, j]) for j in range(3)])
        _, ok_b = _on_grid(grid_c, tk, np.zeros(len(tk)), frame_gap * 2)
        pos = np.column_stack([_lowpass(pos[:, j], fs) for j in range(3)])
        f = np.gradient(np.gradient(pos, 1 / fs, axis=0), 1 / fs, axis=0) + _GRAVITY_UP
        b = np.linalg.norm(f, axis=1)
    b = _lowpass(b, fs)
    edge = int(round(ALIGN_EDGE_S * fs))
    ok_a, ok_b = _erode(ok_a, edge), _erode(ok_b, edge)
    # pad the phone side to the capture grid: a[i] is the phone at grid_c[i]
    pad = np.zeros(max_lag)
    a_full = np.concatenate([pad, a, pad])
    ok_a_full = np.concatenate([pad.astype(bool), ok_a, pad.astype(bool)])
    centre = int(round(centre_s * fs))
    lags = centre + np.arange(-int(round(search_s * fs)), int(round(search_s * fs)) + 1)
    min_n = int(ALIGN_MIN_OVERLAP_S * fs)
    n_common = int((ok_a & ok_b[max_lag : max_lag + len(grid)]).sum())
    out["overlap_s"] = n_common / fs
    c = lag_correlation(a_full, ok_a_full, b, ok_b, lags, min_n)
    c0 = lag_correlation(a_full, ok_a_full, b, ok_b, np.array([0]), min_n)[0]
    out["corr_file"] = float(c0)
    if not np.isfinite(c).any():
        out["reason"] = (
            f"fewer than {ALIGN_MIN_OVERLAP_S:g} s where both signals are known, or no motion"
            if n_common >= min_n
            else f"{n_common / fs:.1f} s where both signals are known (< {ALIGN_MIN_OVERLAP_S:g} s)"
        )
        return out
    k, cpk, second = _peak(lags, c)
    # the phone at grid t equals the capture at t + k / fs: the capture's events come k / fs late, its times move earlier
    out.update(shift_s=-k / fs, corr_peak=cpk, corr_second=second)
    if cpk < ALIGN_MIN_CORR:
        out["reason"] = f"the correlation peak {cpk:.2f} is below {ALIGN_MIN_CORR:g} (too little motion, or the signals disagree)"
    elif np.isfinite(second) and cpk - second < ALIGN_MIN_MARGIN:
        out["reason"] = f"the peak {cpk:.2f} is not clear: another lag reaches {second:.2f} (margin < {ALIGN_MIN_MARGIN:g})"
    elif abs(k - lags[0]) < 1 or abs(k - lags[-1]) < 1:
        out["reason"] = f"the peak lies at the edge of the +-{search_s:g} s search"
    else:
        out["accepted"] = True
    return out


def _kabsch(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation ``R`` minimising ``sum |a_i - R b_i|^2`` (Kabsch / Wahba's problem by SVD)."""
    u, _, vt = np.linalg.svd(b.T @ a)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    return vt.T @ np.diag([1.0, 1.0, d]) @ u.T


def body_rates(truth: TyrexTruth) -> tuple[np.ndarray, np.ndarray]:
    """Angular rate of the rigid body in its own axes (rad/s) between consecutive valid frames.

    ``omega_k = log(rot_k^T rot_k+1) / (t_k+1 - t_k)`` (the rotation vector of the
    relative rotation), at the midpoint times (phone clock).
    """
    from scipy.spatial.transform import Rotation

    ok = truth.valid
    pair = ok[:-1] & ok[1:]
    r = _orthonormal(np.where(ok[:, None, None], truth.rot, np.eye(3)))
    rel = np.einsum("nji,njk->nik", r[:-1][pair], r[1:][pair])
    dt = np.diff(truth.t_s)[pair]
    omega = Rotation.from_matrix(rel).as_rotvec() / dt[:, None]
    t_mid = 0.5 * (truth.t_s[:-1] + truth.t_s[1:])[pair]
    return t_mid, omega


def estimate_mount_rotation(recording: Recording, truth: TyrexTruth) -> tuple[np.ndarray, dict[str, float]]:
    """The constant rotation from the phone's sensor axes to the motion-capture body's axes.

    The rigid body's axes are those of a holder fixed to the phone, so
    ``v_body = R_mount @ v_phone`` for a constant ``R_mount``. It is estimated
    from the angular rate, which the gyroscope measures in the phone's axes and
    the motion capture gives in the body's axes (:func:`body_rates`): the
    gyroscope is averaged over one capture frame and interpolated at the frame
    midpoints, and ``R_mount`` solves Wahba's problem over all frames (Kabsch,
    SVD). Turns (about the vertical) and the phone's own swing and tilt excite
    all three axes, so the rotation is determined in every carrying position.
    Gravity gives an independent check: the accelerometer averaged over still
    spells (|gyr| < 0.1 rad/s over 0.5 s) is compared with
    ``R_mount^T rot^T (0, 0, 1)``.

    Returns
    -------
    R_mount : ndarray, shape (3, 3)
    info : dict
        ``angle_from_identity_deg``, ``rate_rms_residual_rads`` and
        ``rate_rms_rads`` (how much of the angular rate is left unexplained),
        ``gravity_angle_deg`` (median angle between the still accelerometer and
        the predicted up direction; NaN without still spells), ``n_frames``.
    """
    from scipy.spatial.transform import Rotation

    gyr = recording.require_gyr("the mount rotation")
    fs = recording.sampling_rate_hz
    tp = truth.recording_times(recording)
    t_mid, omega_b = body_rates(truth)
    k = max(1, int(round(fs / truth.frame_rate_hz)))
    box = np.ones(k) / k
    g = np.column_stack([np.convolve(gyr[:, j], box, mode="same") for j in range(3)])
    gp = np.column_stack([np.interp(t_mid, tp, g[:, j], left=np.nan, right=np.nan) for j in range(3)])
    m = np.isfinite(gp).all(axis=1)
    if m.sum() < 10:
        raise InputError("the recording and its motion capture overlap for fewer than 10 frames; check timeAlignment.txt.")
    r_mount = _kabsch(omega_b[m], gp[m])
    res = omega_b[m] - gp[m] @ r_mount.T
    info: dict[str, float] = {
        "angle_from_identity_deg": float(np.degrees(Rotation.from_matrix(r_mount).magnitude())),
        "rate_rms_residual_rads": float(np.sqrt(np.mean(np.sum(res**2, axis=1)))),
        "rate_rms_rads": float(np.sqrt(np.mean(np.sum(omega_b[m] ** 2, axis=1)))),
        "n_frames": int(m.sum()),
    }
    # gravity check on still spells
    n = max(1, int(round(0.5 * fs)))
    box = np.ones(n) / n
    gmag = np.convolve(np.linalg.norm(gyr, axis=1), box, mode="same")
    acc_s = np.column_stack([np.convolve(recording.acc[:, j], box, mode="same") for j in range(3)])
    still = gmag < 0.1
    angle = float("nan")
    if still.any():
        rot = truth.rotation_at(tp[still])
        ok = np.isfinite(rot).all(axis=(1, 2))
        if ok.any():
            up_body = rot[ok][:, 2, :]  # rot^T (0, 0, 1): the room's up in body axes
            up_phone = up_body @ r_mount  # R_mount^T up_body
            a = acc_s[still][ok]
            cos = np.sum(a * up_phone, axis=1) / np.linalg.norm(a, axis=1)
            angle = float(np.degrees(np.median(np.arccos(np.clip(cos, -1, 1)))))
    info["gravity_angle_deg"] = angle
    return r_mount, info
