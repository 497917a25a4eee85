"""Load time and per-window prediction latency of a model folder (issue 15: data-only vs pickle).

Run the same script against the old pickle format (the main branch before issue 15, or any
checkout whose models/demo holds model.joblib) and the new data-only format, back to back:

    PYTHONPATH=/path/to/old/checkout python benchmarks/model_format.py /path/to/old/checkout/models/demo
    PYTHONPATH=$PWD python benchmarks/model_format.py models/demo

Prints one JSON line: cold load (first load in the process, imports included), warm load
(median of 30), per-window predict latency (median of 2000 one-row calls) and the batch
cost per window (all windows of a simulated route in one call).
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np


def main(folder: str) -> dict:
    import gaitml
    from gaitml.models import load_model, model_inputs
    from gaitml.models._predict import _windows_for
    from gaitml.simulate import simulate_route

    t0 = time.perf_counter()
    model = load_model(folder)
    cold = time.perf_counter() - t0
    warm = []
    for _ in range(30):
        t0 = time.perf_counter()
        load_model(folder)
        warm.append(time.perf_counter() - t0)
    rec = simulate_route("rectangle", seed=3)
    X = model_inputs(model, rec, _windows_for(rec, model.length_s, model.overlap))
    est = model.estimator
    rows = [X[i : i + 1] for i in range(len(X))]
    for r in rows[:50]:
        est.predict(r)
    one = []
    for k in range(2000):
        r = rows[k % len(rows)]
        t0 = time.perf_counter()
        est.predict(r)
        one.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    for _ in range(20):
        est.predict(X)
    batch = (time.perf_counter() - t0) / 20 / len(X)
    return {
        "gaitml": gaitml.__file__,
        "folder": folder,
        "files": sorted(p.name for p in __import__("pathlib").Path(folder).iterdir()),
        "load_cold_ms": round(cold * 1e3, 2),
        "load_warm_median_ms": round(float(np.median(warm)) * 1e3, 2),
        "predict_one_window_median_us": round(float(np.median(one)) * 1e6, 1),
        "predict_batch_per_window_us": round(batch * 1e6, 2),
        "n_windows_batch": len(X),
    }


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1])))
