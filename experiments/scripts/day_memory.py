"""Peak memory and time of `steps`, `features`, `predict`, `pdr` on a generated 24 h recording at 100 Hz (issue 28).

The recording alternates 10 min of walking (a 1.8 Hz bounce with sway and rotation) and 10 min of
standing, with sensor noise: 8.64 million samples, a 0.54 GB gaitml-csv. Each command runs in a
child process (``python -m gaitml.cli``) with the checkout ``--root`` first on the path; its peak
resident memory is the child's ``ru_maxrss``.

    python -m experiments.scripts.day_memory --file /tmp/day.csv --make            # write the file once
    python -m experiments.scripts.day_memory --file /tmp/day.csv --root .           # this checkout
    python -m experiments.scripts.day_memory --file /tmp/day.csv --root ../main     # another one
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

FS_HZ = 100.0
HOURS = 24


def make_day(path: Path, *, hours: float = HOURS, fs: float = FS_HZ, block: int = 864_000) -> None:
    """Write the generated day (see the module docstring) as a gaitml-csv, block by block."""
    n = int(hours * 3600 * fs)
    rng = np.random.default_rng(0)
    with open(path, "w") as fh:
        fh.write("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n")
        for s in range(0, n, block):
            t = np.arange(s, min(n, s + block)) / fs
            walk = np.floor(t / 600) % 2 == 0
            a = np.column_stack(
                [0.6 * np.sin(np.pi * 1.8 * t), 0.3 * np.cos(2 * np.pi * 1.8 * t), 9.81 + 3.0 * np.sin(2 * np.pi * 1.8 * t)]
            )
            a[~walk] = [0.0, 0.0, 9.81]
            a += rng.normal(0, 0.05, a.shape)
            g = np.column_stack([0.8 * np.sin(np.pi * 1.8 * t), 0.4 * np.cos(2 * np.pi * 1.8 * t), 0.05 * np.sin(t / 50)])
            g[~walk] = 0.0
            g += rng.normal(0, 0.005, g.shape)
            pd.DataFrame(np.column_stack([t, a, g])).to_csv(fh, header=False, index=False, float_format="%.5f")


def measure(root: Path, data: Path, out: Path) -> list[dict]:
    """Run the four commands on ``data`` with ``root``'s gaitml; one row per command."""
    env = {**os.environ, "PYTHONPATH": str(root), "PYTHONDONTWRITEBYTECODE": "1"}
    runs = {
        "steps": ["steps", str(data), "--out", str(out / "steps.csv")],
        "features": ["features", str(data), "--out", str(out / "features.csv")],
        "predict": ["predict", str(root / "models" / "demo"), str(data), "--out", str(out / "pred.csv")],
        "pdr": ["pdr", str(data), "--out", str(out / "traj.csv")],
    }
    rows = []
    for name, argv in runs.items():
        # a fresh child per command: ru_maxrss of RUSAGE_CHILDREN is the largest child so far, so run each in its own helper
        code = (
            "import resource, subprocess, sys, time; t0 = time.time(); "
            "p = subprocess.run(sys.argv[1:], capture_output=True); "
            "print(p.returncode, round(time.time() - t0, 1), round(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024))"
        )
        res = subprocess.run(
            [sys.executable, "-c", code, sys.executable, "-m", "gaitml.cli", *argv], capture_output=True, text=True, env=env, cwd=root
        )
        rc, wall, peak = res.stdout.split()
        rows.append({"command": name, "exit": int(rc), "wall_s": float(wall), "peak_mb": int(peak)})
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--file", type=Path, required=True, help="the generated day (gaitml-csv)")
    ap.add_argument("--make", action="store_true", help="write the file and stop")
    ap.add_argument("--root", type=Path, default=Path("."), help="the checkout whose gaitml runs")
    args = ap.parse_args(argv)
    if args.make:
        make_day(args.file)
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        rows = measure(args.root.resolve(), args.file.resolve(), Path(tmp))
    print(pd.DataFrame(rows).to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
