"""Chunked ``steps --json`` cadence against the whole-file run's, on real recordings (tyrex-attitude).

For every tyrex recording: the whole-file ``adaptive`` cadence windows, and those of
``long_steps(chunk_s=20, margin_s=M, keep_cadence=True)`` for M = 10 and 30 s: window counts, whether the
times are equal (1e-9 s), the largest |d cadence_hz|. Nothing here is fitted; it checks an equivalence.

    PYTHONPATH=$PWD GAITML_SHARED_DATA=/work/shared/data python experiments/scripts/chunked_cadence_grid.py [name-glob]
"""

from __future__ import annotations

import glob
import os
import sys
import warnings

import numpy as np
import pandas as pd


def main() -> None:
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording
    from gaitml.steps import get_detector
    from gaitml.steps.adaptive import cadence_hop_samples

    d = os.environ.get("GAITML_SHARED_DATA", "/work/shared/data")
    pat = sys.argv[1] if len(sys.argv) > 1 else "*"
    paths = sorted(glob.glob(f"{d}/tyrex-attitude/android/{pat}")) + sorted(glob.glob(f"{d}/tyrex-attitude/ios/{pat}"))
    print("| recording | rate Hz | hop samples | whole windows | margin s | chunked windows | same times | max abs d cadence_hz |")
    print("|---|---|---|---|---|---|---|---|")
    for p in paths:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                rec = read_recording(p)
            except Exception as exc:  # noqa: BLE001 - a refused file is listed, not counted
                print(f"| {os.path.basename(p)} | refused: {str(exc)[:60]} |")
                continue
            fs = rec.sampling_rate_hz
            whole = get_detector("adaptive").detect(rec).cadence_
            for margin in (10.0, 30.0):
                c = pd.DataFrame(
                    long_steps(p, "adaptive", chunk_s=20.0, margin_s=margin, progress=False, keep_cadence=True).attrs["cadence"]
                )
                same = len(c) == len(whole) and np.allclose(c["t_s"], whole["t_s"], rtol=0, atol=1e-9)
                dc = float(np.max(np.abs(c["cadence_hz"] - whole["cadence_hz"]))) if same else float("nan")
                print(
                    f"| {os.path.basename(p)} | {fs:.2f} | {cadence_hop_samples(fs)} | {len(whole)} | {margin:g} | {len(c)} | {same} | {dc:.1e} |",
                    flush=True,
                )


if __name__ == "__main__":
    main()
