"""Ground truth for scoring a PDR trajectory: sparse landmarks or a dense reference path.

:func:`read_truth` reads, into one table ``t_s, x_m, y_m, floor``:

- the ``POSI`` lines of a GetSensorData log (``POSI;Timestamp;Counter;Latitude;
  Longitude;floor;building``, the landmarks the walker clicked);
- a CSV ``t,x_m,y_m[,floor]`` (metres; ``x,y`` are read as metres too,
  ``x_mm,y_mm`` as millimetres) or ``t,lat,lon[,floor]`` (degrees; also
  ``latitude,longitude`` / ``lat_deg,lon_deg``), with ``t`` (or ``t_s``, ``time``)
  in s, or ``t_ms`` in ms; the simulator's ``<id>.trajectory.csv`` is such a file.

Times are on the input recording's own clock (the clock of the recording file's
timestamps: for a GetSensorData log the app clock of its POSI lines); the
scorer moves them to the recording's time base (first sample = 0 s) by the
recording's ``meta['t0_original_s']``.

Latitude/longitude are projected to local east/north metres on the plane
tangent to the WGS84 ellipsoid at the first position (a local equirectangular
projection): ``x = N(lat0) cos(lat0) (lon - lon0)``, ``y = M(lat0) (lat - lat0)``
with ``M`` and ``N`` the meridian and prime-vertical radii of curvature at
``lat0`` (angles in rad). Its relative error over a site is about
``tan(lat0) * (lat - lat0)`` in x (2e-4 over 1 km at 45 deg) and of second
order in y: centimetres for a building.

A truth whose median interval is shorter than :data:`DENSE_INTERVAL_S` is called
``dense`` (a reference path, e.g. motion capture or the simulator's), otherwise
``landmarks``; both are scored the same way (:mod:`gaitml.evaluation.truth`).
Floors: consecutive points on the same floor form one 2-D segment; a floor
change starts a new one (the ``segment`` column).

References
----------
WGS84: NIMA TR8350.2 (3rd ed., 2000), sec. 3 (a = 6378137 m, f = 1/298.257223563)
and sec. 4 (radii of curvature). GetSensorData's POSI line: the app's log header
(LOPSI, CAR-CSIC) and the IPIN competition smartphone-track annexes.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.io._export import sniff_csv
from gaitml.io.getsensordata import is_getsensordata, read_getsensordata_landmarks

__all__ = [
    "DENSE_INTERVAL_S",
    "TRUTH_SOURCES",
    "Truth",
    "dense_truth",
    "project_latlon",
    "read_truth",
    "recording_truth",
    "truth_source",
    "truth_from_table",
    "truth_of_recording",
    "tyrex_track",
    "tyrex_truth",
    "unproject_xy",
]

#: A truth sampled at least this often (median interval, s) is a dense reference path.
DENSE_INTERVAL_S = 1.0
#: WGS84 semi-major axis (m) and flattening (NIMA TR8350.2 sec. 3).
WGS84_A_M = 6378137.0
WGS84_F = 1.0 / 298.257223563

_T = {"t": 1.0, "t_s": 1.0, "time": 1.0, "time_s": 1.0, "timestamp": 1.0, "t_ms": 1e-3}
_XY = {("x_m", "y_m"): 1.0, ("x", "y"): 1.0, ("x_mm", "y_mm"): 1e-3}
_LL = (("lat", "lon"), ("latitude", "longitude"), ("lat_deg", "lon_deg"))


@dataclass
class Truth:
    """Timed true positions on the recording's time base: ``table`` has ``t_s, x_m, y_m, floor, segment``."""

    table: pd.DataFrame
    kind: str
    source: str
    notes: list = field(default_factory=list)
    origin_latlon: tuple | None = None


def project_latlon(lat_deg, lon_deg, *, lat0_deg: float | None = None, lon0_deg: float | None = None) -> np.ndarray:
    """Local east/north metres (n, 2) of WGS84 latitude/longitude about (lat0, lon0) (module doc).

    The origin defaults to the first position.
    """
    lat = np.radians(np.asarray(lat_deg, dtype=float))
    lon = np.radians(np.asarray(lon_deg, dtype=float))
    if lat.shape != lon.shape or lat.ndim != 1 or len(lat) == 0:
        raise InputError(f"latitude and longitude must be 1-D of the same length, got {lat.shape} and {lon.shape}.")
    if not (np.isfinite(lat).all() and np.isfinite(lon).all()):
        raise InputError("a latitude or longitude is missing or not a number; fix the truth file.")
    if (np.abs(lat) > np.pi / 2).any() or (np.abs(lon) > 2 * np.pi).any():
        raise InputError("a latitude is beyond +-90 deg or a longitude beyond +-360 deg; are the columns swapped or not in degrees?")
    lat0 = lat[0] if lat0_deg is None else np.radians(lat0_deg)
    lon0 = lon[0] if lon0_deg is None else np.radians(lon0_deg)
    e2 = WGS84_F * (2 - WGS84_F)
    s2 = np.sin(lat0) ** 2
    n_radius = WGS84_A_M / np.sqrt(1 - e2 * s2)
    m_radius = WGS84_A_M * (1 - e2) / (1 - e2 * s2) ** 1.5
    dlon = (lon - lon0 + np.pi) % (2 * np.pi) - np.pi
    return np.column_stack([n_radius * np.cos(lat0) * dlon, m_radius * (lat - lat0)])


def unproject_xy(xy, lat0_deg: float, lon0_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Latitude and longitude (deg) of local east/north metres: the inverse of :func:`project_latlon` about (lat0, lon0)."""
    a = np.asarray(xy, dtype=float)
    lat0 = np.radians(lat0_deg)
    e2 = WGS84_F * (2 - WGS84_F)
    s2 = np.sin(lat0) ** 2
    n_radius = WGS84_A_M / np.sqrt(1 - e2 * s2)
    m_radius = WGS84_A_M * (1 - e2) / (1 - e2 * s2) ** 1.5
    return lat0_deg + np.degrees(a[:, 1] / m_radius), lon0_deg + np.degrees(a[:, 0] / (n_radius * np.cos(lat0)))


def _segments(floor: np.ndarray) -> np.ndarray:
    f = np.where(np.isfinite(floor), floor, -1e9)
    return np.concatenate([[0], np.cumsum(f[1:] != f[:-1])]).astype(int)


def truth_from_table(t_s, xy, *, floor=None, source: str = "", notes: list | None = None) -> Truth:
    """Build a :class:`Truth` from times (s, recording time base) and east/north metres."""
    t = np.asarray(t_s, dtype=float)
    a = np.asarray(xy, dtype=float)
    if a.ndim != 2 or a.shape[1] != 2 or len(a) != len(t):
        raise InputError(f"truth positions must have shape (n, 2) with one time each, got {a.shape} for {len(t)} times.")
    if len(t) < 2:
        raise InputError(f"the truth {source} has {len(t)} positions; scoring needs a start and at least one later position.")
    if not (np.isfinite(t).all() and np.isfinite(a).all()):
        bad = int(np.flatnonzero(~(np.isfinite(t) & np.isfinite(a).all(axis=1)))[0])
        raise InputError(f"the truth {source} has a missing or non-numeric value at row {bad + 1}; fix or remove that row.")
    order = np.argsort(t, kind="stable")
    notes = list(notes or [])
    if (np.diff(t) < 0).any():
        notes.append("truth rows were not in time order: sorted by time")
        t, a = t[order], a[order]
        floor = None if floor is None else np.asarray(floor, dtype=float)[order]
    fl = np.full(len(t), np.nan) if floor is None else np.asarray(floor, dtype=float)
    seg = _segments(fl)
    table = pd.DataFrame({"t_s": t, "x_m": a[:, 0], "y_m": a[:, 1], "floor": fl, "segment": seg})
    kind = "dense" if float(np.median(np.diff(t))) < DENSE_INTERVAL_S else "landmarks"
    if seg[-1] > 0:
        changes = [f"{fl[i - 1]:g}->{fl[i]:g} at {t[i]:.1f} s" for i in np.flatnonzero(np.diff(seg)) + 1]
        notes.append(
            f"the walk changes floor {len(changes)} time(s) ({', '.join(changes[:5])}): {seg[-1] + 1} 2-D segments, scored per segment "
            "and together (PDR is 2-D: floors are taken as one horizontal plane)"
        )
    return Truth(table=table, kind=kind, source=source, notes=notes)


def _csv_truth(p: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, list, tuple | None]:
    with open(p, encoding="utf-8-sig", errors="replace") as fh:
        head = fh.readline()
    sep, dec = sniff_csv(head)
    try:
        df = pd.read_csv(p, sep=sep, decimal=dec, encoding="utf-8-sig", skipinitialspace=True)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the truth {p.name} as CSV ({str(exc).splitlines()[0]}); check the file.") from exc
    cols = {str(c).strip().lower(): c for c in df.columns}
    tcol = next((c for c in _T if c in cols), None)
    expected = "t,x_m,y_m[,floor] (m), t,x_mm,y_mm (mm) or t,lat,lon[,floor] (degrees)"
    if tcol is None:
        raise InputError(f"the truth {p.name} has no time column (t, t_s, time or t_ms) among {list(df.columns)[:8]}; expected {expected}.")
    t = pd.to_numeric(df[cols[tcol]], errors="coerce").to_numpy(float) * _T[tcol]
    notes: list = []
    origin = None
    xy = None
    for (cx, cy), scale in _XY.items():
        if cx in cols and cy in cols:
            xy = np.column_stack([pd.to_numeric(df[cols[c]], errors="coerce").to_numpy(float) for c in (cx, cy)]) * scale
            if scale != 1.0:
                notes.append(f"positions {cx},{cy} read as millimetres")
            break
    if xy is None:
        for cla, clo in _LL:
            if cla in cols and clo in cols:
                lat = pd.to_numeric(df[cols[cla]], errors="coerce").to_numpy(float)
                lon = pd.to_numeric(df[cols[clo]], errors="coerce").to_numpy(float)
                xy = project_latlon(lat, lon)
                origin = (float(lat[0]), float(lon[0]))
                notes.append(
                    f"latitude/longitude projected to local east/north metres about ({lat[0]:.7f}, {lon[0]:.7f}) (WGS84 tangent plane)"
                )
                break
    if xy is None:
        raise InputError(f"the truth {p.name} has no position columns among {list(df.columns)[:8]}; expected {expected}.")
    floor = pd.to_numeric(df[cols["floor"]], errors="coerce").to_numpy(float) if "floor" in cols else None
    return t, xy, floor, notes, origin


def read_truth(path: str | os.PathLike, *, t0_original_s: float = 0.0) -> Truth:
    """Read landmarks or a dense reference path (module doc) onto a recording's time base.

    Parameters
    ----------
    path : file
        A GetSensorData log (its POSI lines) or a truth CSV.
    t0_original_s : float
        The recording's first timestamp on its own clock (``meta['t0_original_s']``),
        subtracted from the truth's times.

    Raises
    ------
    InputError
        No time or position columns, fewer than two positions, POSI lines without
        coordinates (all 0, 0), bad values.
    """
    p = require_file(path)
    if p.is_dir():
        raise InputError(f"--truth {p} is a folder; pass a landmark or trajectory file.")
    if is_getsensordata(p):
        lm = read_getsensordata_landmarks(p)
        lat, lon = lm["lat_deg"].to_numpy(float), lm["lon_deg"].to_numpy(float)
        if np.all((lat == 0) & (lon == 0)):
            raise InputError(
                f"the POSI lines of {p.name} have no coordinates (all 0, 0: GetSensorData writes the click times and the positions "
                "are filled in later); pass a landmark CSV t,lat,lon[,floor] or t,x_m,y_m[,floor] with their positions."
            )
        xy = project_latlon(lat, lon)
        notes = [f"{len(lm)} POSI landmarks; latitude/longitude projected to local east/north metres about ({lat[0]:.7f}, {lon[0]:.7f})"]
        truth = truth_from_table(
            lm["t_s"].to_numpy(float) - t0_original_s, xy, floor=lm["floor"].to_numpy(float), source=p.name, notes=notes
        )
        truth.origin_latlon = (float(lat[0]), float(lon[0]))
        return truth
    t, xy, floor, notes, origin = _csv_truth(p)
    truth = truth_from_table(t - t0_original_s, xy, floor=floor, source=p.name, notes=notes)
    truth.origin_latlon = origin
    return truth


def truth_of_recording(rec) -> Truth:
    """The truth a recording carries itself (``--truth self``): its POSI landmarks, else its reference trajectory.

    Raises
    ------
    InputError
        The recording has neither.
    """
    lm = rec.reference.get("landmarks")
    if lm is not None and len(lm):
        lat, lon = lm["lat_deg"].to_numpy(float), lm["lon_deg"].to_numpy(float)
        if np.all((lat == 0) & (lon == 0)):
            raise InputError(
                f"the POSI landmarks of {rec.name} have no coordinates (all 0, 0); pass --truth with a landmark CSV "
                "t,lat,lon[,floor] or t,x_m,y_m[,floor] holding their positions."
            )
        notes = [f"{len(lm)} POSI landmarks; latitude/longitude projected to local east/north metres about ({lat[0]:.7f}, {lon[0]:.7f})"]
        truth = truth_from_table(
            lm["t_s"].to_numpy(float), project_latlon(lat, lon), floor=lm["floor"].to_numpy(float), source="POSI", notes=notes
        )
        truth.origin_latlon = (float(lat[0]), float(lon[0]))
        return truth
    traj = reference_trajectory_truth(rec)
    if traj is not None:
        return traj
    raise InputError(f"--truth self: {rec.name} carries no landmarks (POSI lines) and no reference trajectory; pass --truth FILE.")


def reference_trajectory_truth(rec) -> Truth | None:
    """The reference trajectory a recording carries (``rec.reference['trajectory']``, columns ``t_s`` or ``t`` on the
    file's clock, ``x_m``, ``y_m``) as a dense truth on the recording's time base; None when it carries none."""
    traj = rec.reference.get("trajectory")
    if traj is None or not len(traj):
        return None
    tcol = "t_s" if "t_s" in traj else "t"
    t = traj[tcol].to_numpy(float) - float(rec.meta.get("t0_original_s", 0.0))
    return truth_from_table(t, traj[["x_m", "y_m"]].to_numpy(float), source="reference trajectory")


def tyrex_track(rec, truth_path=None) -> tuple[np.ndarray, np.ndarray, Path, str]:
    """The motion capture of a tyrex recording (:func:`gaitml.io.tyrex.read_tyrex_truth`, its default alignment) on
    the recording's time base: times (s), the phone's horizontal positions (m, room frame, NaN where the markers were
    lost), the recording's folder and one line on the clock alignment (the file's dt, the refined one or why not:
    :attr:`gaitml.io.tyrex.TyrexTruth.align_note`)."""
    from gaitml.io.tyrex import read_tyrex_truth

    folder = Path(str(rec.meta.get("source", "")))
    folder = folder if folder.is_dir() else folder.parent
    tt = read_tyrex_truth(folder, truth_path=truth_path)
    return tt.t_s - float(rec.meta.get("t0_original_s", 0.0)), tt.pos_m[:, :2], folder, tt.align_note


def tyrex_truth(rec, truth_path=None, *, smooth=None, smooth_note: str = "") -> Truth:
    """The motion capture of a tyrex recording (:func:`gaitml.io.tyrex.read_tyrex_truth`) as a dense truth.

    The phone's positions (room frame, x and y horizontal) on the recording's time
    base. ``smooth`` (a function ``(t_s, xy) -> xy`` that fills lost frames, e.g.
    :func:`gaitml.evaluation.trajectory.body_track`, which ``gaitml pdr --truth self``
    passes to follow the walker rather than the phone's arm swing) is applied to the
    whole track, with ``smooth_note`` added to the notes; without it the frames where
    the markers were lost are left out.
    """
    t, xy, folder, align_note = tyrex_track(rec, truth_path)
    ok = np.isfinite(xy).all(axis=1)
    notes = [f"tyrex motion capture of {folder.name} on the phone clock ({align_note})"]
    if smooth is not None:
        xy = smooth(t, xy)
        notes.append(
            f"{smooth_note}; {int((~ok).sum())} lost frames filled linearly first"
            if smooth_note
            else f"{int((~ok).sum())} lost frames filled"
        )
    else:
        t, xy = t[ok], xy[ok]
        notes.append(f"{int((~ok).sum())} lost frames left out")
    return truth_from_table(t, xy, source=f"tyrex:{folder.name}", notes=notes)


#: Where a truth comes from (:func:`truth_source`): a tyrex recording's motion capture, the truth a recording carries
#: itself (landmarks, else its reference trajectory), a landmark or truth file.
TRUTH_SOURCES = ("tyrex", "self", "file")


def truth_source(rec, spec: str) -> tuple[str, str | None]:
    """Which truth ``spec`` (``'self'`` or a file) names for recording ``rec``: the one choice behind both views,
    :func:`recording_truth` (scoring) and :func:`dense_truth` (fitting).

    Returns
    -------
    (str, str or None)
        ``("tyrex", file or None)``: a tyrex recording with ``'self'`` (its own motion capture) or a tyrex motion-capture
        CSV (:func:`gaitml.io.tyrex.is_tyrex_truth_file`); ``("self", None)``: ``'self'``, or the recording's own file
        when it holds landmarks (the truth it carries, :func:`truth_of_recording`); ``("file", spec)``: a landmark or
        truth file (:func:`read_truth`).
    """
    from gaitml.io.tyrex import is_tyrex_truth_file

    spec = str(spec)
    if rec.meta.get("format") == "tyrex" and (spec == "self" or is_tyrex_truth_file(spec)):
        return "tyrex", None if spec == "self" else spec
    if spec == "self":
        return "self", None
    source = rec.meta.get("source")
    if source is not None and rec.reference.get("landmarks") is not None and Path(spec).resolve() == Path(str(source)).resolve():
        return "self", None
    return "file", spec


def recording_truth(rec, spec: str = "self", *, smooth=None, smooth_note: str = "") -> Truth:
    """The truth ``spec`` names for ``rec`` (:func:`truth_source`) on its time base, to score a trajectory against:
    landmarks or a dense path. A tyrex motion capture goes through :func:`tyrex_truth` with ``smooth`` and
    ``smooth_note`` (``gaitml pdr --truth`` passes :func:`gaitml.evaluation.trajectory.body_track`).

    Raises
    ------
    InputError
        As :func:`truth_of_recording`, :func:`read_truth` and :func:`gaitml.io.tyrex.read_tyrex_truth`.
    """
    kind, path = truth_source(rec, spec)
    if kind == "tyrex":
        return tyrex_truth(rec, path, smooth=smooth, smooth_note=smooth_note)
    if kind == "self":
        return truth_of_recording(rec)
    return read_truth(path, t0_original_s=float(rec.meta.get("t0_original_s", 0.0)))


def dense_truth(rec, spec: str = "self") -> tuple[np.ndarray, np.ndarray, str]:
    """The truth ``spec`` names for ``rec`` (:func:`truth_source`) as a dense path to fit against: times (s, on the
    recording's time base), positions (m, shape (n, 2); a tyrex motion capture keeps NaN where the markers were lost),
    and a name (``tyrex:<folder>``, or the :class:`Truth`'s ``source``).

    Raises
    ------
    InputError
        ``'self'`` on a recording without a motion capture or a reference trajectory; a truth of sparse landmarks (true
        step lengths need a dense path); and as :func:`recording_truth`. A recording that carries both landmarks and a
        reference trajectory is fitted against the trajectory (scored against the landmarks).
    """
    kind, path = truth_source(rec, spec)
    if kind == "tyrex":
        t, xy, folder, _note = tyrex_track(rec, path)
        return t, xy, f"tyrex:{folder.name}"
    tr = None
    if kind == "self":
        # the truth the recording carries: its reference trajectory, even where it carries landmarks too (the
        # scoring view's first choice), since fitting needs a dense path
        tr = reference_trajectory_truth(rec)
        if tr is None and str(spec) == "self":
            raise InputError(
                f"{rec.name} carries no truth trajectory (motion capture or a reference path); "
                "pass --truth FILE, a dense t,x_m,y_m CSV on the recording's clock."
            )
    if tr is None:
        tr = recording_truth(rec, spec)
    if tr.kind != "dense":
        raise InputError(
            f"the truth {tr.source} of {rec.name} is sparse landmarks (a point every {np.median(np.diff(tr.table['t_s'])):.1f} s); "
            "true step lengths need a dense path (motion capture or a reference trajectory at >= 1 Hz)."
        )
    return tr.table["t_s"].to_numpy(float), tr.table[["x_m", "y_m"]].to_numpy(float), tr.source
