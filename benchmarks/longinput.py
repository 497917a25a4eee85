"""Peak memory and time of the CLI on a day-long recording.

Run ``python -m benchmarks.longinput --hours 24 --out bench-out/long`` (from the
repository root) to

1. write a ``hours``-long gaitml-csv at 100 Hz with gyro and labels (a
   simulated 10-minute mixed-mode walk, repeated with continuous time), and
2. run ``gaitml steps``, ``gaitml zupt``, ``gaitml features`` and
   ``gaitml predict`` on it as separate processes under ``/usr/bin/time -v``,
   recording each one's wall time and peak resident memory (max RSS).

The table is printed and written to ``long_input.md``/``.json`` in ``--out``.
Not part of ``gaitml bench`` (it takes minutes and ~0.8 GB of disk).
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
import pandas as pd

from gaitml.io import write_json, write_text

__all__ = ["make_long_recording", "measure"]


def make_long_recording(path: Path, hours: float, *, sampling_rate_hz: float = 100.0, seed: int = 0) -> int:
    """Write a long gaitml-csv by repeating a simulated 10-minute walk; returns the sample count."""
    from gaitml.simulate import simulate_dataset

    base = simulate_dataset(1, 600.0, sampling_rate_hz=sampling_rate_hz, seed=seed)[0]
    n_base = base.n_samples
    n_total = int(round(hours * 3600 * sampling_rate_hz))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    with open(tmp, "w") as fh:
        fh.write("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,label\n")
        k = 0
        while k < n_total:
            m = min(n_base, n_total - k)
            t = (k + np.arange(m)) / sampling_rate_hz
            df = pd.DataFrame(
                np.column_stack([t, base.acc[:m], base.gyr[:m]]),
                columns=["t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"],
            )
            df["label"] = base.labels[:m]
            df.to_csv(fh, header=False, index=False, float_format="%.6f")
            k += m
    tmp.replace(path)
    return n_total


def _run_timed(cmd: list[str]) -> dict:
    t0 = time.perf_counter()
    res = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", res.stderr)
    rss_mb = int(m.group(1)) / 1024 if m else float("nan")
    return {
        "command": " ".join(cmd[1:]),
        "exit": res.returncode,
        "seconds": round(wall, 1),
        "peak_rss_mb": round(rss_mb, 1),
        "stderr_tail": res.stderr.strip().splitlines()[-1:] if res.returncode else [],
    }


def measure(hours: float, out: Path, *, model_dir: str = "models/demo", keep: bool = False) -> list[dict]:
    """Generate the long file and measure every bounded-memory command on it."""
    out.mkdir(parents=True, exist_ok=True)
    data = out / f"long_{hours:g}h.csv"
    if not data.exists():
        print(f"writing {data} ...", file=sys.stderr)
        n = make_long_recording(data, hours)
    else:
        n = sum(1 for _ in open(data)) - 1
    gaitml = [sys.executable, "-m", "gaitml.cli"]
    cmds = [
        [*gaitml, "steps", str(data), "--detector", "single-peak", "--out", str(out / "steps.csv")],
        [*gaitml, "zupt", str(data), "--detector", "pseudo-std", "--out", str(out / "zupt.csv")],
        [*gaitml, "features", str(data), "--out", str(out / "features.csv")],
        [*gaitml, "predict", model_dir, str(data), "--out", str(out / "predict.csv")],
    ]
    rows = []
    for cmd in cmds:
        print("running: gaitml " + " ".join(cmd[3:]), file=sys.stderr)
        r = _run_timed(cmd)
        r["n_samples"] = n
        rows.append(r)
        print(json.dumps(r), file=sys.stderr)
    md = [f"# Long input: {hours:g} h at 100 Hz ({n:,} samples, {data.stat().st_size / 1e6:.0f} MB CSV)", ""]
    md.append("| command | exit | seconds | peak RSS (MB) |")
    md.append("|---|---:|---:|---:|")
    for r in rows:
        cmd = re.sub(r"\S*/", "", r["command"])
        md.append(f"| {cmd} | {r['exit']} | {r['seconds']} | {r['peak_rss_mb']} |")
    text = "\n".join(md) + "\n"
    write_text(out / "long_input.md", text)
    write_json(out / "long_input.json", rows)
    print(text)
    if not keep:
        data.unlink()
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.longinput", description=__doc__.splitlines()[0])
    p.add_argument("--hours", type=float, default=24.0)
    p.add_argument("--out", default="bench-out/long")
    p.add_argument("--model", default="models/demo")
    p.add_argument("--keep", action="store_true", help="keep the generated CSV")
    a = p.parse_args(argv)
    rows = measure(a.hours, Path(a.out), model_dir=a.model, keep=a.keep)
    return 0 if all(r["exit"] == 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
