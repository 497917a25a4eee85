"""Reader for GetSensorData logs (the LOPSI / CAR-CSIC Android logger of the IPIN competitions).

A log is one text file per walk: ``%`` comment lines (the app writes its format
description there), then one line per sensor event, fields separated by ``;``,
numbers with a decimal point (the app formats with ``Locale.US``). The field
order and units published with the app (its log header, the IPIN smartphone
track annexes) are, for the types gaitml uses:

- ``ACCE;AppTimestamp(s);SensorTimestamp(s);Acc_X(m/s^2);Acc_Y(m/s^2);Acc_Z(m/s^2);Accuracy(integer)``
  (specific force, gravity included, Android device frame);
- ``GYRO;AppTimestamp(s);SensorTimestamp(s);Gyr_X(rad/s);Gyr_Y(rad/s);Gyr_Z(rad/s);Accuracy(integer)``;
- ``POSI;Timestamp(s);Counter;Latitude(degrees);Longitude(degrees);floor ID;Building ID``: a
  ground-truth landmark the walker clicked, on the app clock (read by
  :func:`read_getsensordata_landmarks`, kept in ``reference['landmarks']``).

The other types (``MAGN``, ``PRES``, ``LIGH``, ``PROX``, ``HUMI``, ``TEMP``,
``AHRS``, ``GNSS``, ``WIFI``, ``BLUE``, ``BLE4``, ``SOUN``, ``RFID``, ``IMUX``,
``IMUL``, ``IMUI``, ...) are counted, with their time span and rate, in
``meta['other_sensors']`` and otherwise skipped (``gaitml info`` shows the note).
The trailing accuracy field is optional (some builds omit it, some end lines with
``;``).

Clocks. ``AppTimestamp`` is set by the app when it receives an event: one clock
for all sensors, seconds since the log started, but it includes the delivery
latency. ``SensorTimestamp`` is set by the sensor: consecutive differences are
the true sampling intervals, but its origin is the sensor's own (the app's
header says so). gaitml therefore times each sensor's samples by its
``SensorTimestamp`` moved onto the app clock by that sensor's median
``AppTimestamp - SensorTimestamp``. When the two sensors' offsets agree within
:data:`SAME_CLOCK_S` they share one clock (the usual Android case) and the
accelerometer's offset is used for both, so their relative timing is exactly
the sensors'. The gyroscope is then interpolated onto the accelerometer times by
:func:`gaitml.io._merge.merge_clocks` (every accelerometer sample kept, the gyroscope's
edge samples held where it did not run, said in a warning), as for the phone-app
readers, and :meth:`Recording.from_timestamps` makes the time base uniform.

Ordering rule. Lines of different types interleave in arrival order and need not
be sorted. Within one type, events are sorted by ``SensorTimestamp``; an event
that goes back by up to :data:`MAX_REORDER_S` is moved to its place and counted
(``meta['getsensordata']['reordered']``); an event repeating the previous
timestamp exactly is dropped and counted (``duplicates``); a jump back by more
than :data:`MAX_REORDER_S` is a restarted sensor clock and refused with its line
number.

Malformed lines (an unknown line shape, too few or too many fields, a
non-numeric value) are refused with their line number, except the very last line
of the file: the app is often stopped while writing it, so a malformed last line
is dropped and said in ``meta['warnings']``.

Memory. The file is read in blocks of lines; each block's accelerometer and
gyroscope lines are parsed into float arrays and the block is dropped, so the
peak memory is the arrays of those two sensors (48 bytes per event) plus one
block, never a table of every line.
"""

from __future__ import annotations

import gzip
import io
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.io._hold import dehold, note_hold
from gaitml.io._merge import merge_clocks
from gaitml.recording import Recording

__all__ = [
    "MAX_REORDER_S",
    "SAME_CLOCK_S",
    "is_getsensordata",
    "read_getsensordata",
    "read_getsensordata_landmarks",
    "scan_getsensordata",
    "write_getsensordata",
]

#: An event of one type may go back by at most this much and still be sorted into place (s).
MAX_REORDER_S = 1.0
#: Two sensors whose median AppTimestamp - SensorTimestamp differ by at most this share one clock (s).
SAME_CLOCK_S = 0.05
#: Lines parsed per block (bounds the memory of the text held at once).
BLOCK_BYTES = 8_000_000

_TYPE = re.compile(r"^[A-Z][A-Z0-9]{3}$")
#: Published types (log header of GetSensorData 2.x and the IPIN annexes), with what they carry.
KNOWN_TYPES = {
    "ACCE": "accelerometer (m/s^2)",
    "GYRO": "gyroscope (rad/s)",
    "MAGN": "magnetometer (uT)",
    "PRES": "pressure (mbar)",
    "LIGH": "light (lux)",
    "PROX": "proximity",
    "HUMI": "humidity (%)",
    "TEMP": "temperature (C)",
    "AHRS": "orientation / rotation vector",
    "ORIE": "orientation (deg)",
    "GNSS": "GNSS fix (deg, m)",
    "WIFI": "Wi-Fi scan (dBm)",
    "BLUE": "Bluetooth (dBm)",
    "BLE4": "Bluetooth LE beacon (dBm)",
    "SOUN": "sound level",
    "RFID": "RFID reader",
    "IMUX": "external XSens IMU",
    "IMUL": "external LPMS-B IMU",
    "IMUI": "external MIMU22BT",
    "POSI": "ground-truth landmark",
}
_HEADER_MARK = "getsensordata"


def _open_text(p: Path):
    with open(p, "rb") as fh:
        magic = fh.read(2)
    if magic == b"\x1f\x8b":
        return io.TextIOWrapper(gzip.open(p, "rb"), encoding="utf-8", errors="replace")
    return open(p, encoding="utf-8", errors="replace")


def is_getsensordata(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a GetSensorData log, from its first lines; never raises.

    True when the header names the app, or when the first event lines are
    ``TYPE;number;...`` with a published type.
    """
    try:
        p = Path(path)
        if not p.is_file():
            return False
        with _open_text(p) as fh:
            head = fh.read(65536)
    except (OSError, EOFError, ValueError):
        return False
    head = head.removeprefix("\ufeff")
    if _HEADER_MARK in head[:4096].lower() and head.lstrip().startswith("%"):
        return True
    seen = 0
    for line in head.splitlines()[:200]:
        s = line.strip()
        if not s or s.startswith("%"):
            continue
        parts = s.split(";")
        if len(parts) < 3 or parts[0] not in KNOWN_TYPES:
            return False
        try:
            float(parts[1])
        except ValueError:
            return False
        seen += 1
        if seen >= 3:
            return True
    return seen > 0


@dataclass
class _Stream:
    """Parsed events of one motion type: arrays of blocks, concatenated at the end."""

    app: list = field(default_factory=list)
    sensor: list = field(default_factory=list)
    xyz: list = field(default_factory=list)
    line: list = field(default_factory=list)

    def arrays(self):
        if not self.app:
            return None
        return (np.concatenate(self.app), np.concatenate(self.sensor), np.vstack(self.xyz), np.concatenate(self.line))


@dataclass
class GsdScan:
    """What one pass over a log found: motion arrays, landmarks, counts of the other types."""

    acce: tuple | None
    gyro: tuple | None
    posi: pd.DataFrame
    other: dict
    n_lines: int
    n_comments: int
    warnings: list


def _bad(where: str, lineno: int, line: str, why: str) -> InputError:
    shown = line.strip()[:60]
    return InputError(
        f"{where}: line {lineno} is malformed ({why}: {shown!r}); fix or delete that line (GetSensorData lines are "
        "TYPE;AppTimestamp;SensorTimestamp;values...)."
    )


def _parse_motion(lines: list[str], linenos: list[int], kind: str, where: str, stream: _Stream) -> None:
    """Parse one block of ACCE/GYRO lines into ``stream`` (fast path in pandas' C parser, exact errors in Python)."""
    text = "".join(lines)
    n_sep = np.fromiter((line.count(";") for line in lines), dtype=np.int64, count=len(lines))
    try:
        if ((n_sep < 5) | (n_sep > 7)).any():
            raise ValueError("field count")
        df = pd.read_csv(
            io.StringIO(text),
            sep=";",
            header=None,
            usecols=[1, 2, 3, 4, 5],
            dtype=float,
            engine="c",
        )
        vals = df.to_numpy(dtype=float)
        ok = len(vals) == len(lines) and np.isfinite(vals).all()
    except (ValueError, pd.errors.ParserError):
        ok = False
    if not ok:
        vals = np.empty((len(lines), 5))
        for i, (line, n) in enumerate(zip(lines, linenos, strict=True)):
            parts = line.rstrip("\r\n").split(";")
            if parts and parts[-1].strip() == "":
                parts = parts[:-1]
            if not 6 <= len(parts) <= 7:
                raise _bad(where, n, line, f"{kind} needs 6 or 7 fields, found {len(parts)}")
            try:
                vals[i] = [float(x) for x in parts[1:6]]
            except ValueError:
                raise _bad(where, n, line, "a value is not a number") from None
            if len(parts) == 7 and parts[6].strip():
                try:
                    float(parts[6])
                except ValueError:
                    raise _bad(where, n, line, "the accuracy is not a number") from None
        bad = ~np.isfinite(vals).all(axis=1)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise _bad(where, linenos[i], lines[i], "a value is not finite")
    stream.app.append(vals[:, 0].copy())
    stream.sensor.append(vals[:, 1].copy())
    stream.xyz.append(vals[:, 2:5].copy())
    stream.line.append(np.asarray(linenos, dtype=np.int64))


def _posi(parts: list[str], n: int, line: str, where: str) -> tuple:
    if parts and parts[-1].strip() == "":
        parts = parts[:-1]
    if len(parts) < 6:
        raise _bad(where, n, line, f"POSI needs Timestamp;Counter;Latitude;Longitude;floor[;building], found {len(parts)} fields")
    try:
        t, counter, lat, lon, floor = (float(parts[1]), float(parts[2]), float(parts[3]), float(parts[4]), float(parts[5]))
        building = float(parts[6]) if len(parts) > 6 and parts[6].strip() else np.nan
    except ValueError:
        raise _bad(where, n, line, "a POSI value is not a number") from None
    return t, counter, lat, lon, floor, building, n


def scan_getsensordata(path: str | os.PathLike, *, block_bytes: int = BLOCK_BYTES) -> GsdScan:
    """Read a GetSensorData log once, block by block.

    Returns
    -------
    GsdScan
        ``acce``/``gyro``: ``(app_s, sensor_s, xyz, line_numbers)`` in file order or
        ``None``; ``posi``: landmarks (``t_app_s, counter, lat_deg, lon_deg, floor,
        building, line``); ``other``: per other type ``{'lines', 't_first_s',
        't_last_s'}`` on the app clock; counts of lines and comments; warnings.

    Raises
    ------
    InputError
        A malformed line other than the last (with its number), no event lines.
    """
    p = require_file(path)
    where = p.name
    streams = {"ACCE": _Stream(), "GYRO": _Stream()}
    other: dict[str, dict] = {}
    posi: list[tuple] = []
    warnings: list[str] = []
    n_lines = n_comments = 0
    pending: tuple[int, str, str] | None = None  # the last malformed line, refused unless it is the file's last
    with _open_text(p) as fh:
        lineno = last_data = 0
        while True:
            block = fh.readlines(block_bytes)
            if not block:
                break
            buf: dict[str, tuple[list, list]] = {"ACCE": ([], []), "GYRO": ([], [])}
            for line in block:
                lineno += 1
                s = line.strip()
                if not s:
                    continue
                if pending is not None:
                    raise _bad(where, pending[0], pending[1], pending[2])
                last_data = lineno
                if s[0] == "%":
                    n_comments += 1
                    continue
                n_lines += 1
                kind = s[:4]
                if kind in buf and s[4:5] == ";":
                    buf[kind][0].append(line)
                    buf[kind][1].append(lineno)
                    continue
                parts = s.split(";")
                if not _TYPE.match(parts[0]) or len(parts) < 2:
                    pending = (lineno, line, "not a TYPE;... event line")
                    continue
                if kind == "POSI":
                    try:
                        posi.append(_posi(parts, lineno, line, where))
                    except InputError:
                        pending = (lineno, line, "a bad POSI line")
                    continue
                try:
                    t_app = float(parts[1])
                except ValueError:
                    pending = (lineno, line, f"{kind}'s AppTimestamp is not a number")
                    continue
                o = other.setdefault(kind, {"lines": 0, "t_first_s": t_app, "t_last_s": t_app})
                o["lines"] += 1
                o["t_last_s"] = t_app
            for kind, (lines, nos) in buf.items():
                if lines:
                    try:
                        _parse_motion(lines, nos, kind, where, streams[kind])
                    except InputError:
                        if nos[-1] != last_data:
                            raise
                        # only the file's last line may be cut short: parse the rest, drop it
                        if len(lines) > 1:
                            _parse_motion(lines[:-1], nos[:-1], kind, where, streams[kind])
                        pending = (nos[-1], lines[-1], "cut short")
    if pending is not None:
        warnings.append(
            f"the last line ({pending[0]}) of {where} is malformed ({pending[2]}) and was dropped (the app stopped while writing it)"
        )
        n_lines -= 1
    if n_lines == 0:
        raise InputError(f"{where} has no event lines (only comments); record again with the sensors switched on.")
    cols = ["t_app_s", "counter", "lat_deg", "lon_deg", "floor", "building", "line"]
    posi_df = pd.DataFrame(posi, columns=cols) if posi else pd.DataFrame(columns=cols, dtype=float)
    return GsdScan(
        acce=streams["ACCE"].arrays(),
        gyro=streams["GYRO"].arrays(),
        posi=posi_df,
        other=other,
        n_lines=n_lines,
        n_comments=n_comments,
        warnings=warnings,
    )


def _ordered(stream: tuple, kind: str, where: str, max_reorder_s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    """Sort one sensor's events by SensorTimestamp (the ordering rule of the module doc)."""
    app, sensor, xyz, line = stream
    info = {"events": int(len(sensor)), "reordered": 0, "duplicates": 0}
    d = np.diff(sensor)
    back = np.flatnonzero(d < 0)
    if back.size:
        # how far each event lies behind the running maximum before it
        run_max = np.maximum.accumulate(sensor)
        lag = run_max - sensor
        worst = int(np.argmax(lag))
        if lag[worst] > max_reorder_s:
            raise InputError(
                f"{where}: the {kind} SensorTimestamp goes back by {lag[worst]:.3f} s at line {int(line[worst])} "
                f"(more than {max_reorder_s:g} s: a restarted sensor clock); cut the log there and read the parts separately."
            )
        order = np.argsort(sensor, kind="stable")
        info["reordered"] = int((lag > 0).sum())
        app, sensor, xyz, line = app[order], sensor[order], xyz[order], line[order]
    dup = np.concatenate([[False], np.diff(sensor) == 0])
    if dup.any():
        info["duplicates"] = int(dup.sum())
        keep = ~dup
        app, sensor, xyz = app[keep], sensor[keep], xyz[keep]
    if len(sensor) < 2:
        raise InputError(f"{where} has {len(sensor)} {kind} events; record for longer with this sensor switched on.")
    info["offset_s"] = float(np.median(app - sensor))
    info["rate_hz"] = round(1.0 / float(np.median(np.diff(sensor))), 3)
    return app, sensor, xyz, info


def read_getsensordata(
    path: str | os.PathLike,
    *,
    sampling_rate_hz: float | None = None,
    meta: dict | None = None,
    max_reorder_s: float = MAX_REORDER_S,
    same_clock_s: float = SAME_CLOCK_S,
) -> Recording:
    """Read a GetSensorData log as a recording (see the module doc for the rules).

    Parameters
    ----------
    path : file
        The log (``.txt``, possibly gzipped).
    sampling_rate_hz : float, optional
        Resample to this uniform rate (default: the accelerometer's median rate).
    meta : dict, optional
        Extra metadata.
    max_reorder_s : float
        Largest backward step of one sensor's SensorTimestamp that is sorted into place.
    same_clock_s : float
        Largest difference of the two sensors' app-clock offsets treated as one clock.

    Returns
    -------
    Recording
        acc (m/s^2), gyr (rad/s) when the log has GYRO lines; ``meta['getsensordata']``
        (events, rates, offsets, reordered and duplicate counts per sensor, the clock
        rule used), ``meta['other_sensors']``, ``meta['clock_merge']``;
        ``reference['landmarks']`` (POSI lines: ``t_s`` on the recording's time base,
        ``counter``, ``lat_deg``, ``lon_deg``, ``floor``, ``building``) when present.

    Raises
    ------
    InputError
        Malformed lines (with their number), no ACCE lines, a restarted sensor
        clock, clocks that do not overlap.
    """
    p = require_file(path)
    where = p.name
    scan = scan_getsensordata(p)
    if scan.acce is None:
        kinds = ", ".join(sorted(scan.other)) or "none"
        raise InputError(
            f"{where} has no ACCE (accelerometer) lines (types found: {kinds}); switch the accelerometer on in GetSensorData and record again."
        )
    _, s_acc, acc, ia = _ordered(scan.acce, "ACCE", where, max_reorder_s)
    gsd: dict = {"ACCE": ia}
    m: dict = {"source": str(p), "format": "getsensordata", "id": p.stem, "subject": p.stem, "session": p.stem}
    warnings = list(scan.warnings)
    m["warnings"] = warnings
    gyr = None
    s_acc, acc = note_hold(m, "acc", *dehold(s_acc, acc, "accelerometer (ACCE)"))
    t_acc = s_acc + ia["offset_s"]
    t = t_acc
    if scan.gyro is not None:
        _, s_gyr, gyr_raw, ig = _ordered(scan.gyro, "GYRO", where, max_reorder_s)
        gsd["GYRO"] = ig
        s_gyr, gyr_raw = note_hold(m, "gyr", *dehold(s_gyr, gyr_raw, "gyroscope (GYRO)"))
        if abs(ig["offset_s"] - ia["offset_s"]) <= same_clock_s:
            gsd["clock_rule"] = "ACCE and GYRO share one sensor clock; both moved onto the app clock by the ACCE offset"
            t_gyr = s_gyr + ia["offset_s"]
        else:
            gsd["clock_rule"] = "ACCE and GYRO on separate sensor clocks; each moved onto the app clock by its own offset"
            t_gyr = s_gyr + ig["offset_s"]
        t, acc, gyr, merge = merge_clocks(t_acc, acc, t_gyr, gyr_raw, what=where)
        m["clock_merge"] = merge
        if merge["warning"]:
            warnings.append(merge["warning"])
    else:
        gsd["clock_rule"] = "ACCE only, moved onto the app clock by its offset"
        warnings.append(f"{where} has no GYRO lines: accelerometer only (PDR heading and gyroscope detectors need a gyroscope)")
    for kind, info in list(gsd.items()):
        if isinstance(info, dict) and (info["reordered"] or info["duplicates"]):
            gsd.setdefault("notes", []).append(
                f"{kind}: {info['reordered']} events out of order sorted into place, {info['duplicates']} repeated timestamps dropped"
            )
    gsd["lines"] = scan.n_lines
    m["getsensordata"] = gsd
    if scan.other:
        m["other_sensors"] = {
            k: {
                "lines": v["lines"],
                "what": KNOWN_TYPES.get(k, "unknown type"),
                "rate_hz": round((v["lines"] - 1) / (v["t_last_s"] - v["t_first_s"]), 3) if v["t_last_s"] > v["t_first_s"] else None,
                "kept": False,
            }
            for k, v in sorted(scan.other.items())
        }
        m["other_sensors_note"] = "counted and skipped: gaitml uses ACCE and GYRO (and POSI landmarks)"
    ref: dict = {}
    if len(scan.posi):
        lm = _landmark_table(scan.posi)
        lm["t_s"] = lm["t_s"] - float(t[0])
        ref["landmarks"] = lm
        m["landmarks"] = int(len(lm))
    if not warnings:
        del m["warnings"]
    m.update(meta or {})
    return Recording.from_timestamps(t, acc, gyr=gyr, sampling_rate_hz=sampling_rate_hz, meta=m, reference=ref)


def _landmark_table(posi: pd.DataFrame) -> pd.DataFrame:
    lm = pd.DataFrame(
        {
            "t_s": posi["t_app_s"].to_numpy(float),
            "counter": posi["counter"].to_numpy(float),
            "lat_deg": posi["lat_deg"].to_numpy(float),
            "lon_deg": posi["lon_deg"].to_numpy(float),
            "floor": posi["floor"].to_numpy(float),
            "building": posi["building"].to_numpy(float),
        }
    )
    return lm.sort_values("t_s", kind="stable").reset_index(drop=True)


def read_getsensordata_landmarks(path: str | os.PathLike) -> pd.DataFrame:
    """The POSI landmarks of a GetSensorData log on the app clock (``t_s`` = POSI timestamp, s).

    To put them on a recording's time base subtract the recording's
    ``meta['t0_original_s']`` (what :func:`read_getsensordata` does for
    ``reference['landmarks']``).

    Raises
    ------
    InputError
        A malformed line, or no POSI lines.
    """
    p = require_file(path)
    scan = scan_getsensordata(p)
    if not len(scan.posi):
        raise InputError(
            f"{p.name} has no POSI (landmark) lines; mark positions with GetSensorData's button while recording, or pass a landmark CSV."
        )
    return _landmark_table(scan.posi)


def write_getsensordata(
    path: str | os.PathLike,
    t_acc_s,
    acc,
    *,
    t_gyr_s=None,
    gyr=None,
    landmarks: pd.DataFrame | None = None,
    sensor_origin_s: float = 1000.0,
    gyr_sensor_origin_s: float | None = None,
    latency_s: float = 0.004,
    extra_lines: list[str] | None = None,
) -> Path:
    """Write a GetSensorData log in the published format (for converting simulated walks and for tests).

    Events are written in time order of their app timestamps (interleaved as the
    app writes them), with the app's number formats (``%.3f`` times, ``%.5f``
    values). ``SensorTimestamp`` = time + ``sensor_origin_s`` (the gyroscope's own
    origin when ``gyr_sensor_origin_s`` is given); ``AppTimestamp`` = time +
    ``latency_s``. ``landmarks`` (``t_s``, ``lat_deg``, ``lon_deg``, ``floor``[,
    ``building``]) become POSI lines; ``extra_lines`` (full lines, e.g. ``MAGN;...``)
    are appended in place by their AppTimestamp field.
    """
    p = Path(path)
    ta = np.asarray(t_acc_s, dtype=float)
    a = np.asarray(acc, dtype=float)
    rows: list[tuple[float, str]] = []
    for ti, (x, y, z) in zip(ta, a, strict=True):
        rows.append((ti + latency_s, f"ACCE;{ti + latency_s:.3f};{ti + sensor_origin_s:.3f};{x:.5f};{y:.5f};{z:.5f};3"))
    if t_gyr_s is not None:
        g0 = sensor_origin_s if gyr_sensor_origin_s is None else gyr_sensor_origin_s
        for ti, (x, y, z) in zip(np.asarray(t_gyr_s, float), np.asarray(gyr, float), strict=True):
            rows.append((ti + latency_s, f"GYRO;{ti + latency_s:.3f};{ti + g0:.3f};{x:.5f};{y:.5f};{z:.5f};3"))
    if landmarks is not None:
        for k, r in enumerate(landmarks.itertuples(index=False)):
            b = int(getattr(r, "building", 0))
            rows.append((float(r.t_s), f"POSI;{r.t_s:.3f};{k + 1};{r.lat_deg:.8f};{r.lon_deg:.8f};{int(r.floor)};{b}"))
    for line in extra_lines or []:
        rows.append((float(line.split(";")[1]), line))
    rows.sort(key=lambda r: r[0])
    header = (
        "% LogFile created by the 'GetSensorData' App for Android (written by gaitml.io.getsensordata.write_getsensordata).\n"
        "% Accelerometer data: \t'ACCE;AppTimestamp(s);SensorTimestamp(s);Acc_X(m/s^2);Acc_Y(m/s^2);Acc_Z(m/s^2);Accuracy(integer)'\n"
        "% Gyroscope data:     \t'GYRO;AppTimestamp(s);SensorTimestamp(s);Gyr_X(rad/s);Gyr_Y(rad/s);Gyr_Z(rad/s);Accuracy(integer)'\n"
        "% POSI Reference:     \t'POSI;Timestamp(s);Counter;Latitude(degrees);Longitude(degrees);floor ID(0,1,2..4);Building ID(0,1,2..3)'\n"
    )
    p.parent.mkdir(parents=True, exist_ok=True)
    with open(p, "w", encoding="utf-8") as fh:
        fh.write(header)
        for _, line in rows:
            fh.write(line + "\n")
    return p
