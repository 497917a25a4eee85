"""Write simulated walks as phone-app exports: the example folder of the README walkthrough.

``python -m experiments.scripts.phone_demo OUT_DIR [--subjects N] [--duration-s S] [--seed N]``

Each simulated subject (gaitml's simulator, five motion modes, 50 Hz) is written in
the layout of a phone app, following each app's documented format (as the readers'
tests in ``tests/io_apps`` do): subject 1 as an unpacked phyphox export
(``Accelerometer.csv`` + ``Gyroscope.csv``, time in s from the start, with gravity),
subject 2 as an Android Sensor Logger export (``TotalAcceleration.csv`` +
``Gyroscope.csv`` + ``Metadata.csv``, ``time`` in ns since the epoch,
``seconds_elapsed``, columns ``z, y, x``), subject 3 and more as a generic CSV read
with a column map (time in ms, acceleration in g). Next to each export an intervals
file holds what a person would write down: the true mode changes moved by up to
+-0.3 s (uniform noise), as CSV ``start_s,end_s,label`` (phyphox, CSV) or as an
Audacity label track (Sensor Logger). ``manifest.csv`` lists them
(``file, subject, intervals, position, format, columns, time_unit, acc_unit``).

No real recording is copied: every number comes from the simulator. The README's
``data/phone-demo`` was written with the defaults (3 subjects, 45 s with 6-9 s mode
segments so that every walk holds all five modes, seed 7; phyphox and Sensor Logger
exports as the zip archives the apps share).
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from gaitml.consts import GRAVITY_MS2

__all__ = ["write_phyphox", "write_sensor_logger", "write_columns_csv", "write_intervals", "write_phone_folder", "main"]

#: Column map of the generic CSV written by :func:`write_columns_csv` (manifest column ``columns``).
COLUMNS_MAP = "t=time_ms,acc_x=ax_g,acc_y=ay_g,acc_z=az_g,gyr_x=gx,gyr_y=gy,gyr_z=gz"
_T0_NS = 1_700_000_000_000_000_000


def _write(path: Path, header: list[str], cols: list[np.ndarray], fmt: str = "{:.5g}") -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [",".join(f'"{h}"' if " " in h else h for h in header)]
    for row in zip(*cols, strict=True):
        lines.append(",".join(str(v) if isinstance(v, int | np.integer) else fmt.format(v) for v in row))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def write_phyphox(rec, folder: Path) -> Path:
    """An unpacked phyphox export of ``rec``: ``Accelerometer.csv`` (with gravity) and ``Gyroscope.csv``."""
    t = rec.t_s - rec.t_s[0]
    a, g = rec.acc, rec.gyr
    _write(
        folder / "Accelerometer.csv",
        ["Time (s)", "Acceleration x (m/s^2)", "Acceleration y (m/s^2)", "Acceleration z (m/s^2)", "Absolute acceleration (m/s^2)"],
        [t, *a.T, np.linalg.norm(a, axis=1)],
    )
    _write(
        folder / "Gyroscope.csv",
        ["Time (s)", "Gyroscope x (rad/s)", "Gyroscope y (rad/s)", "Gyroscope z (rad/s)", "Absolute (rad/s)"],
        [t, *g.T, np.linalg.norm(g, axis=1)],
    )
    (folder / "meta").mkdir(parents=True, exist_ok=True)
    (folder / "meta" / "device.csv").write_text('"property","value"\n"deviceModel","SimulatedPhone"\n')
    (folder / "meta" / "time.csv").write_text('"event","experiment time","system time"\n"START",0.0,1700000000.0\n')
    return folder


def write_sensor_logger(rec, folder: Path) -> Path:
    """An unpacked Android Sensor Logger export of ``rec``: ``TotalAcceleration.csv``, ``Gyroscope.csv``, ``Metadata.csv``."""
    t = rec.t_s - rec.t_s[0]
    ns = _T0_NS + np.round(t * 1e9).astype(np.int64)
    for name, xyz in (("TotalAcceleration.csv", rec.acc), ("Gyroscope.csv", rec.gyr)):
        _write(folder / name, ["time", "seconds_elapsed", "z", "y", "x"], [ns, t, xyz[:, 2], xyz[:, 1], xyz[:, 0]])
    (folder / "Metadata.csv").write_text("version,device name,recording time,platform\n3,SimulatedPhone,2023-11-14_22-13-20,Android\n")
    return folder


def write_columns_csv(rec, path: Path) -> Path:
    """A generic CSV of ``rec`` (time in ms, acceleration in g, gyroscope in rad/s), read with :data:`COLUMNS_MAP`."""
    t_ms = (rec.t_s - rec.t_s[0]) * 1000.0
    a = rec.acc / GRAVITY_MS2
    _write(path, ["time_ms", "ax_g", "ay_g", "az_g", "gx", "gy", "gz"], [t_ms, *a.T, *rec.gyr.T])
    return path


def write_intervals(rec, path: Path, *, noise_s: float = 0.3, seed: int = 0, audacity: bool = False) -> Path:
    """Intervals of ``rec``'s true labels with every mode change moved by uniform noise in +-``noise_s``."""
    from gaitml.labels import intervals_from_labels, perturb_intervals

    iv = perturb_intervals(intervals_from_labels(rec.labels, rec.sampling_rate_hz), noise_s, np.random.default_rng(seed), rec.duration_s)
    path.parent.mkdir(parents=True, exist_ok=True)
    if audacity:
        path.write_text("".join(f"{r.start_s:.6f}\t{r.end_s:.6f}\t{r.label}\n" for r in iv.itertuples()), encoding="utf-8")
    else:
        path.write_text("start_s,end_s,label\n" + "".join(f"{r.start_s:.3f},{r.end_s:.3f},{r.label}\n" for r in iv.itertuples()))
    return path


def _zip(folder: Path) -> Path:
    """Replace an export folder by the zip archive the app would share (``NAME.zip``)."""
    import shutil

    archive = Path(shutil.make_archive(str(folder), "zip", root_dir=folder))
    shutil.rmtree(folder)
    return archive


def write_phone_folder(
    out: Path,
    *,
    subjects: int = 3,
    duration_s: float = 45.0,
    seed: int = 7,
    noise_s: float = 0.3,
    segment_s: tuple[float, float] = (6.0, 9.0),
    zip_exports: bool = True,
) -> Path:
    """Simulate ``subjects`` walkers and write them as app exports + intervals + ``manifest.csv`` in ``out``.

    ``segment_s``: the length range of the mode segments (short, so that a 45 s walk
    holds all five modes); ``zip_exports``: write the phyphox and Sensor Logger
    exports as the zip archives the apps share (else as unpacked folders).
    """
    from gaitml.simulate import simulate_dataset

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    recs = simulate_dataset(n_subjects=subjects, duration_s=duration_s, seed=seed, sampling_rate_hz=50.0, segment_s=segment_s)
    ext = ".zip" if zip_exports else ""
    names = ["alice", "bob", "carol", "dave", "erin", "frank", "grace", "heidi"]
    rows = []
    for i, rec in enumerate(recs):
        who = names[i] if i < len(names) else f"subject{i + 1}"
        row = {
            "file": "",
            "subject": who,
            "intervals": "",
            "position": "hand",
            "format": "",
            "columns": "",
            "time_unit": "",
            "acc_unit": "",
        }
        if i == 0:
            write_phyphox(rec, out / f"{who}-phyphox")
            if zip_exports:
                _zip(out / f"{who}-phyphox")
            row.update(file=f"{who}-phyphox{ext}", format="phyphox", intervals=f"{who}.intervals.csv")
            write_intervals(rec, out / row["intervals"], noise_s=noise_s, seed=seed + i)
        elif i == 1:
            write_sensor_logger(rec, out / f"{who}-sensorlogger")
            if zip_exports:
                _zip(out / f"{who}-sensorlogger")
            row.update(file=f"{who}-sensorlogger{ext}", format="sensor-logger", intervals=f"{who}.labels.txt")
            write_intervals(rec, out / row["intervals"], noise_s=noise_s, seed=seed + i, audacity=True)
        else:
            write_columns_csv(rec, out / f"{who}.csv")
            row.update(
                file=f"{who}.csv", format="columns-csv", columns=COLUMNS_MAP, time_unit="ms", acc_unit="g", intervals=f"{who}.intervals.csv"
            )
            write_intervals(rec, out / row["intervals"], noise_s=noise_s, seed=seed + i)
        rows.append(row)
    with open(out / "manifest.csv", "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.phone_demo", description=__doc__.splitlines()[0])
    ap.add_argument("out_dir")
    ap.add_argument("--subjects", type=int, default=3)
    ap.add_argument("--duration-s", type=float, default=45.0)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args(argv)
    out = write_phone_folder(Path(args.out_dir), subjects=args.subjects, duration_s=args.duration_s, seed=args.seed)
    print(f"wrote {args.subjects} phone recordings, intervals files and manifest.csv to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
