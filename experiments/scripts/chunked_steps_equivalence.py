"""Chunked ``adaptive`` steps against the whole-file run's, on every tyrex recording the reader accepts.

One line per recording and margin: name, margin (s), whole-file steps, chunked steps (``long_steps``, 20 s chunks),
and the number of step samples (``peak``) in one run and not the other (a step moved by one sample counts twice).
Nothing is fitted: an equivalence check. Run it against two code states (``PYTHONPATH``) to compare them.

    PYTHONPATH=$PWD GAITML_SHARED_DATA=/work/shared/data python experiments/scripts/chunked_steps_equivalence.py
"""

from __future__ import annotations

import glob
import os
import warnings


def main() -> None:
    import gaitml
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording
    from gaitml.steps import get_detector

    warnings.simplefilter("ignore")
    print(gaitml.__file__)
    d = os.environ.get("GAITML_SHARED_DATA", "/work/shared/data") + "/tyrex-attitude"
    for p in sorted(glob.glob(f"{d}/android/*")) + sorted(glob.glob(f"{d}/ios/*")):
        try:
            rec = read_recording(p)
        except Exception:  # noqa: BLE001 - a file the reader refuses is skipped (chunked_cadence_grid lists them)
            continue
        w = get_detector("adaptive").detect(rec).steps_["peak"].to_numpy()
        for m in (10.0, 30.0):
            c = long_steps(p, "adaptive", chunk_s=20.0, margin_s=m, progress=False)["peak"].to_numpy()
            print(os.path.basename(p), m, len(w), len(c), len(set(w.tolist()) ^ set(c.tolist())), flush=True)


if __name__ == "__main__":
    main()
