"""Throughput of the PDR pieces: gyro attitude integration and the whole pipeline.

- ``attitude-prefix-scan``: pure quaternion integration of the gyro (paper 003 sec. 4.2)
  vectorised as a parallel prefix product, against the reference: scipy ``Rotation``
  composed sample by sample in a plain loop (run on a prefix and scaled linearly).
- ``attitude-gravity-loop``: the complementary (gravity-corrected) integration, a tight
  loop on plain floats, against the same per-sample ``Rotation`` loop.
- ``pipeline``: :func:`gaitml.pdr.run_pdr` (single-peak steps, true modes, HDE) on a
  simulated 262 m rectangle, in steps/s.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.spatial.transform import Rotation

from gaitml.pdr.attitude import integrate_gyro, integrate_gyro_gravity

__all__ = ["run"]


def _reference_rotation_loop(gyr: np.ndarray, fs: float, r0: Rotation) -> np.ndarray:
    """Plain reference: compose scipy rotations one sample at a time."""
    out = np.empty((len(gyr), 4))
    r = r0
    out[0] = r.as_quat()
    dt = 1.0 / fs
    for i in range(1, len(gyr)):
        r = r * Rotation.from_rotvec(0.5 * (gyr[i - 1] + gyr[i]) * dt)
        out[i] = r.as_quat()
    return out


def _time(fn, repeat: int = 3) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def run(quick: bool = False) -> list[dict]:
    fs = 50.0
    n = 50_000 if quick else 500_000
    n_ref = 5_000 if quick else 20_000
    rng = np.random.default_rng(0)
    gyr = rng.normal(0, 0.5, (n, 3))
    up = np.tile([0.0, 0.0, 1.0], (n, 1))
    r0 = Rotation.identity()
    rows = []
    t_ref = _time(lambda: _reference_rotation_loop(gyr[:n_ref], fs, r0), repeat=1) * n / n_ref
    t_scan = _time(lambda: integrate_gyro(gyr, fs, r0))
    rows.append(
        {
            "area": "pdr",
            "name": "attitude-prefix-scan",
            "n_items": n,
            "unit": "samples",
            "seconds": t_scan,
            "throughput_per_s": n / t_scan,
            "reference_seconds": t_ref,
            "ratio": t_ref / t_scan,
            "note": f"reference: per-sample scipy Rotation loop on {n_ref} samples, scaled",
        }
    )
    t_loop = _time(lambda: integrate_gyro_gravity(gyr, up, fs, r0, 0.5), repeat=1)
    rows.append(
        {
            "area": "pdr",
            "name": "attitude-gravity-loop",
            "n_items": n,
            "unit": "samples",
            "seconds": t_loop,
            "throughput_per_s": n / t_loop,
            "reference_seconds": t_ref,
            "ratio": t_ref / t_loop,
            "note": "complementary filter, tight float loop; same reference",
        }
    )
    from gaitml.pdr import run_pdr
    from gaitml.simulate import simulate_route

    rec = simulate_route("rectangle", seed=0)
    h0 = float(rec.reference["trajectory"]["heading_rad"].iloc[0])
    kw = {"modes": "true", "heading": "hde", "initial_heading_rad": h0, "detector": "single-peak", "gyro_bias": "off"}
    res = run_pdr(rec, **kw)
    t_pipe = _time(lambda: run_pdr(rec, **kw), repeat=1 if quick else 3)
    rows.append(
        {
            "area": "pdr",
            "name": "pipeline-rectangle",
            "n_items": res.n_steps,
            "unit": "steps",
            "seconds": t_pipe,
            "throughput_per_s": res.n_steps / t_pipe,
            "note": f"run_pdr single-peak + true modes + HDE, no gyro-bias removal (the rows before the new defaults) on a {rec.duration_s:.0f} s, {rec.n_samples}-sample simulated rectangle",
        }
    )
    return rows
