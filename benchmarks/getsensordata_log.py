"""Time and peak memory of reading a long GetSensorData log, against pandas reading the same lines.

Run ``python -m benchmarks.getsensordata_log --minutes 60 --out bench-out/gsd`` (from the
repository root) to

1. write a ``minutes``-long log in the published line format: a simulated 10-minute
   mixed-mode walk repeated with continuous time, ACCE and GYRO at 100 Hz on their own
   sensor clocks, MAGN at 50 Hz, PRES at 10 Hz, a WIFI scan every 2 s and a POSI
   landmark every 30 s, interleaved in app-time order as the app writes them;
2. in one process, time :func:`gaitml.io.getsensordata.read_getsensordata` against the
   reference: ``pandas.read_csv`` of every line (``sep=';'``, ``comment='%'``, one
   column per field) followed by the selection of the ACCE and GYRO rows (what a user
   would write), and check both give the same accelerometer values;
3. run ``gaitml info LOG --json`` and the pandas reference each as a separate process
   under ``/usr/bin/time -v`` for their peak resident memory.

Not part of ``gaitml bench`` (benchmarks/ has no readers suite; this takes about a
minute and ~80 MB of disk per hour of log).
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

__all__ = ["make_log", "measure"]

_PANDAS_REF = """
import sys, pandas as pd, numpy as np
df = pd.read_csv(sys.argv[1], sep=';', comment='%', header=None, names=range(12), engine='c', dtype={0: str}, low_memory=False)
acc = df[df[0] == 'ACCE'][[1, 2, 3, 4, 5]].to_numpy(float)
gyr = df[df[0] == 'GYRO'][[1, 2, 3, 4, 5]].to_numpy(float)
print(len(acc), len(gyr))
"""


def make_log(path: Path, minutes: float, *, seed: int = 0) -> dict:
    """Write the long log; returns line counts per type."""
    from gaitml.simulate import simulate_dataset

    fs = 100.0
    base = simulate_dataset(1, 600.0, sampling_rate_hz=fs, seed=seed)[0]
    n_total = int(round(minutes * 60 * fs))
    counts = {"ACCE": 0, "GYRO": 0, "MAGN": 0, "PRES": 0, "WIFI": 0, "POSI": 0}
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    rng = np.random.default_rng(seed)
    with open(tmp, "w") as fh:
        fh.write("% LogFile created by the 'GetSensorData' App for Android (benchmark log written by benchmarks.getsensordata_log)\n")
        k = 0
        while k < n_total:
            m = min(base.n_samples, n_total - k)
            t = (k + np.arange(m)) / fs
            ta = t + rng.uniform(0, 0.002, m)
            tg = t + 0.003 + rng.uniform(0, 0.002, m)
            rows = [
                (ti + 0.004, f"ACCE;{ti + 0.004:.3f};{ti + 5000:.3f};{a[0]:.5f};{a[1]:.5f};{a[2]:.5f};3")
                for ti, a in zip(ta, base.acc[:m], strict=True)
            ]
            rows += [
                (ti + 0.004, f"GYRO;{ti + 0.004:.3f};{ti + 5000:.3f};{g[0]:.5f};{g[1]:.5f};{g[2]:.5f};3")
                for ti, g in zip(tg, base.gyr[:m], strict=True)
            ]
            rows += [(ti + 0.006, f"MAGN;{ti + 0.006:.3f};{ti + 5000:.3f};21.50000;-4.25000;-38.12500;3") for ti in t[::2]]
            rows += [(ti + 0.007, f"PRES;{ti + 0.007:.3f};{ti + 5000:.3f};1013.2500;3") for ti in t[::10]]
            rows += [(ti + 0.008, f"WIFI;{ti + 0.008:.3f};{ti:.3f};eduroam;00:11:22:33:44:55;2412;-67") for ti in t[::200]]
            rows += [(ti + 0.009, f"POSI;{ti + 0.009:.3f};{int(ti // 30)};40.31330000;-3.48330000;0;0") for ti in t[::3000]]
            rows.sort(key=lambda r: r[0])
            for _, line in rows:
                fh.write(line)
                fh.write("\n")
                counts[line[:4]] += 1
            k += m
    tmp.replace(path)
    return counts


def _run_timed(cmd: list[str]) -> dict:
    t0 = time.perf_counter()
    res = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", res.stderr)
    return {"exit": res.returncode, "seconds": round(wall, 2), "peak_rss_mb": round(int(m.group(1)) / 1024, 1) if m else None}


def measure(minutes: float, out: Path) -> dict:
    """Write the log (unless present), then time both readers in one process and measure each one's memory."""
    import pandas as pd

    from gaitml.io.getsensordata import read_getsensordata

    out.mkdir(parents=True, exist_ok=True)
    log = out / f"gsd_{minutes:g}min.txt"
    counts = make_log(log, minutes) if not log.exists() else None
    t0 = time.perf_counter()
    rec = read_getsensordata(log)
    t_ours = time.perf_counter() - t0
    t0 = time.perf_counter()
    df = pd.read_csv(log, sep=";", comment="%", header=None, names=range(12), engine="c", dtype={0: str}, low_memory=False)
    ref_acc = df[df[0] == "ACCE"][[3, 4, 5]].to_numpy(float)
    t_ref = time.perf_counter() - t0
    n_events = rec.meta["getsensordata"]["ACCE"]["events"]
    assert n_events == len(ref_acc), (n_events, len(ref_acc))
    del df
    py = sys.executable
    mem_ours = _run_timed([py, "-m", "gaitml.cli", "info", str(log), "--json"])
    mem_ref = _run_timed([py, "-c", _PANDAS_REF, str(log)])
    result = {
        "minutes": minutes,
        "log_mb": round(log.stat().st_size / 1e6, 1),
        "lines": rec.meta["getsensordata"]["lines"],
        "line_counts": counts,
        "acce_events": n_events,
        "in_process_s": {
            "gaitml": round(t_ours, 2),
            "pandas_all_lines": round(t_ref, 2),
            "ratio_pandas_over_gaitml": round(t_ref / t_ours, 2),
        },
        "separate_process": {"gaitml info --json": mem_ours, "pandas read_csv of all lines": mem_ref},
    }
    (out / "getsensordata_log.json").write_text(json.dumps(result, indent=2))
    return result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--out", default="bench-out/gsd")
    args = ap.parse_args(argv)
    print(json.dumps(measure(args.minutes, Path(args.out)), indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
