"""Build small phone-app exports following each app's documented layout (no real recording is copied).

The signal is analytic so a test can check values after the merge and the resampling:
specific force ``acc(t)`` (m/s^2, gravity +z, a 2 Hz "step" bounce) and angular
rate ``gyr(t)`` (rad/s).
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

G = 9.80665


def acc_true(t: np.ndarray) -> np.ndarray:
    """Specific force in m/s^2 with gravity on +z (phone flat), a 2 Hz bounce and a slow sway."""
    t = np.asarray(t, dtype=float)
    return np.column_stack([0.8 * np.sin(2 * np.pi * 1.0 * t), 0.5 * np.cos(2 * np.pi * 0.5 * t), G + 2.0 * np.sin(2 * np.pi * 2.0 * t)])


def gyr_true(t: np.ndarray) -> np.ndarray:
    """Angular rate in rad/s."""
    t = np.asarray(t, dtype=float)
    return np.column_stack([0.3 * np.sin(2 * np.pi * 1.0 * t), 0.2 * np.cos(2 * np.pi * 2.0 * t), 0.1 + 0.05 * np.sin(2 * np.pi * 0.5 * t)])


def jittered_times(t0: float, t1: float, rate_hz: float, seed: int, jitter: float = 0.15) -> np.ndarray:
    """Increasing sample times from t0 to about t1 at ``rate_hz`` with +-jitter/rate uniform jitter."""
    rng = np.random.default_rng(seed)
    n = int((t1 - t0) * rate_hz) + 1
    t = t0 + np.arange(n) / rate_hz + rng.uniform(-jitter, jitter, n) / rate_hz
    t[0] = t0
    return t


def write_csv(path: Path, header: list[str], columns: list[np.ndarray], sep: str = ",", decimal: str = ".", fmt: str = "{:.9g}") -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [sep.join(f'"{h}"' if sep == "," and " " in h else h for h in header)]
    for row in zip(*columns, strict=True):
        lines.append(sep.join(str(v) if isinstance(v, (int, np.integer, str)) else fmt.format(v).replace(".", decimal) for v in row))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def zip_folder(folder: Path, out: Path, root: str | None = None) -> Path:
    with zipfile.ZipFile(out, "w") as z:
        for f in sorted(folder.rglob("*")):
            if f.is_file():
                arc = f.relative_to(folder).as_posix()
                z.write(f, f"{root}/{arc}" if root else arc)
    return out


# ----------------------------------------------------------------- phyphox
PHY_ACC = ["Time (s)", "Acceleration x (m/s^2)", "Acceleration y (m/s^2)", "Acceleration z (m/s^2)", "Absolute acceleration (m/s^2)"]
PHY_LIN = [
    "Time (s)",
    "Linear Acceleration x (m/s^2)",
    "Linear Acceleration y (m/s^2)",
    "Linear Acceleration z (m/s^2)",
    "Absolute acceleration (m/s^2)",
]
PHY_GYR = ["Time (s)", "Gyroscope x (rad/s)", "Gyroscope y (rad/s)", "Gyroscope z (rad/s)", "Absolute (rad/s)"]


def phyphox_export(
    folder: Path,
    *,
    duration_s: float = 20.0,
    acc_rate: float = 100.0,
    gyr_rate: float = 200.0,
    gyr_offset_s: float = 0.05,
    gyr_end_s: float | None = None,
    gyro: bool = True,
    linear_only: bool = False,
    sep: str = ",",
    decimal: str = ".",
) -> Path:
    """An unpacked phyphox export: Accelerometer.csv [+ Gyroscope.csv] + meta/."""
    ta = jittered_times(0.0, duration_s, acc_rate, seed=1)
    a = acc_true(ta)
    if linear_only:
        lin = a - np.array([0, 0, G])
        write_csv(folder / "Accelerometer.csv", PHY_LIN, [ta, *lin.T, np.linalg.norm(lin, axis=1)], sep, decimal)
    else:
        write_csv(folder / "Accelerometer.csv", PHY_ACC, [ta, *a.T, np.linalg.norm(a, axis=1)], sep, decimal)
    if gyro:
        tg = jittered_times(gyr_offset_s, duration_s - 0.1 if gyr_end_s is None else gyr_end_s, gyr_rate, seed=2)
        g = gyr_true(tg)
        write_csv(folder / "Gyroscope.csv", PHY_GYR, [tg, *g.T, np.linalg.norm(g, axis=1)], sep, decimal)
    (folder / "meta").mkdir(parents=True, exist_ok=True)
    (folder / "meta" / "device.csv").write_text('"property","value"\n"deviceModel","TestPhone"\n')
    (folder / "meta" / "time.csv").write_text('"event","experiment time","system time"\n"START",0.0,1700000000.0\n')
    return folder


# ----------------------------------------------------------- Sensor Logger
SL_HEADER = ["time", "seconds_elapsed", "z", "y", "x"]
T0_NS = 1_700_000_000_123_456_789


def _sl_table(path: Path, t: np.ndarray, xyz: np.ndarray) -> None:
    ns = T0_NS + np.round(t * 1e9).astype(np.int64)
    write_csv(path, SL_HEADER, [ns, t, xyz[:, 2], xyz[:, 1], xyz[:, 0]])


def sensor_logger_export(
    folder: Path,
    *,
    platform: str | None = "Android",
    duration_s: float = 20.0,
    total: bool = True,
    gravity: bool = True,
    uncalibrated: bool = False,
    gyro: bool = True,
    gyr_shift_s: float = 0.0,
) -> Path:
    """An unpacked Sensor Logger export in the platform's documented units and frame."""
    ta = jittered_times(0.01, duration_s, 100.0, seed=3)
    a = acc_true(ta)
    grav_true = np.tile([0.0, 0.0, G], (len(ta), 1))
    user = a - grav_true
    ios = platform == "iOS"
    s = -1.0 if ios else 1.0  # iOS frame: all axes of acceleration and gravity negated
    _sl_table(folder / "Accelerometer.csv", ta, s * user)
    if total and not ios:
        _sl_table(folder / "TotalAcceleration.csv", ta, a)
    if gravity:
        _sl_table(folder / "Gravity.csv", ta, s * grav_true)
    if uncalibrated:
        _sl_table(folder / "AccelerometerUncalibrated.csv", ta, s * a / G if ios else a)
    if gyro:
        tg = jittered_times(0.02, duration_s - 0.05, 100.0, seed=4) + gyr_shift_s
        _sl_table(folder / "Gyroscope.csv", tg, gyr_true(tg - gyr_shift_s))
    if platform is not None:
        (folder / "Metadata.csv").write_text(f"version,device name,recording time,platform\n3,TestPhone,2023-11-14_22-13-20,{platform}\n")
    (folder / "Annotation.csv").write_text("time,seconds_elapsed,text,millisecond_press_duration\n")
    return folder


def measured(rec, *keys: str) -> np.ndarray:
    """Samples of ``rec`` where every merged stream ran (not filled by the clock merge's hold rule), with one interval of margin."""
    t = rec.t_s
    keep = np.ones(len(t), dtype=bool)
    for key in keys or ("clock_merge", "gravity_merge"):
        for a, b in rec.meta.get(key, {}).get("gyr_filled_s", []):
            keep &= (t < a - 1.0 / rec.sampling_rate_hz) | (t > b + 1.0 / rec.sampling_rate_hz)
    return keep
