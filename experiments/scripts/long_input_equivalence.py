"""Long inputs read in chunks against the same files read whole: gyroscope bias, trajectory and gait-evidence account.

Nothing is fitted here (the chunked paths must reproduce the whole-file answers), so there is no held-out
split; the real tyrex recordings are listed per person to show the agreement does not depend on the walker.

    PYTHONPATH=. python -m experiments.scripts.long_input_equivalence [--data ../shared/data] [--out /tmp/fixchunk2]

Prints three tables (markdown) used in experiments/reports/long-input-equivalence.md:
1. the biased 90 s simulated file (60 s walk, 10 s still, 20 s walk, gyro bias (0.04, -0.03, 0.05) rad/s):
   largest chunked-vs-whole position difference and the two reported biases, chunks of 30 s;
2. gait-evidence counts on simulate_nongait('gestures', seed=100) and a 120 s simulated walk, chunked
   (several chunk / margin lengths) against whole;
3. tyrex iPhone 5 texting and swinging walks (raw gyroscope, bias of about 0.1 rad/s), one per person and
   motion: chunked (30 s chunks, 30 s margins, --gyro-bias auto, the default adaptive detector and
   single-peak) against whole.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

from gaitml.chunked_run import long_pdr, long_steps
from gaitml.consts import GRAVITY_MS2
from gaitml.io import read_recording, read_segments, write_gaitml_csv
from gaitml.pdr import run_pdr
from gaitml.recording import Recording
from gaitml.simulate import simulate_dataset
from gaitml.simulate.nongait import simulate_nongait
from gaitml.steps import get_detector
from gaitml.steps._gait_evidence import gait_check_recording

BIAS_RADS = (0.04, -0.03, 0.05)
PEOPLE = ("Guillaume", "Jakob", "Thibaud")


def biased_walk(out: Path) -> Path:
    fs = 50.0
    a = simulate_dataset(1, 60.0, sampling_rate_hz=fs, seed=3, modes=("walk",))[0]
    b = simulate_dataset(1, 20.0, sampling_rate_hz=fs, seed=4, modes=("walk",))[0]
    rng = np.random.default_rng(0)
    n = int(10 * fs)
    up = a.acc[-int(fs) :].mean(axis=0)
    acc = np.vstack([a.acc, up / np.linalg.norm(up) * GRAVITY_MS2 + rng.normal(0, 0.02, (n, 3)), b.acc])
    gyr = np.vstack([a.gyr, rng.normal(0, 0.003, (n, 3)), b.gyr]) + np.array(BIAS_RADS)
    p = out / "biased.csv"
    write_gaitml_csv(Recording.from_arrays(acc, fs, gyr=gyr), p)
    return p


def _pos_diff(whole, chunked) -> float:
    if whole.n_steps != chunked.n_steps:
        return float("nan")
    d = chunked.trajectory[["x_m", "y_m"]].to_numpy() - whole.trajectory[["x_m", "y_m"]].to_numpy()
    return float(np.hypot(d[:, 0], d[:, 1]).max())


def _b(info) -> str:
    gb = info["gyro_bias"]
    return f"{gb['method']} ({', '.join(f'{v:.4f}' for v in gb['bias_rads'])})"


def table_bias(out: Path) -> None:
    p = biased_walk(out)
    print("\n| gyro bias | detector | steps whole / chunked | max position difference (m) | bias whole | bias chunked |")
    print("|---|---|---|---:|---|---|")
    for gb in ("still", "auto"):
        for det, margin in (("single-peak", 5.0), ("adaptive", 30.0)):
            w = run_pdr(read_recording(p), modes="forward", gyro_bias=gb, detector=det)
            c = long_pdr(p, modes="forward", gyro_bias=gb, detector=det, chunk_s=30.0, margin_s=margin, progress=False)
            print(
                f"| {gb} | {det} (margin {margin:g} s) | {w.n_steps} / {c.n_steps} | {_pos_diff(w, c):.2e} | {_b(w.info)} | {_b(c.info)} |"
            )


def _account(steps) -> str:
    a = steps.attrs.get("gait_check")
    return "-" if a is None else f"{a['n_bouts']} / {a['n_bouts_rejected']} / {a['n_steps_rejected']}"


def table_gait(out: Path) -> None:
    print(
        "\n| recording | detector | gait check | chunk / margin (s) | steps whole / chunked | bouts / rejected bouts / rejected steps, whole | chunked |"
    )
    print("|---|---|---|---|---|---|---|")
    recs = {
        "gestures seed 100": simulate_nongait("gestures", seed=100),
        "walk 120 s": simulate_dataset(1, 120.0, sampling_rate_hz=50.0, seed=3)[0],
    }
    for name, rec in recs.items():
        p = out / (name.replace(" ", "_") + ".csv")
        write_gaitml_csv(rec, p)
        rec = read_recording(p)
        for det, gait in (("adaptive", True), ("adaptive", False), ("single-peak", True)):
            if det == "adaptive":
                w = get_detector(det, gait_check=gait).detect(rec).steps_
            else:
                w = gait_check_recording(get_detector(det).detect(rec).steps_, rec)
            for cs, ms in ((30.0, 30.0), (20.0, 10.0), (15.0, 5.0)):
                c = long_steps(p, det, chunk_s=cs, margin_s=ms, progress=False, gait_check=gait)
                print(
                    f"| {name} | {det} | {'on' if gait else 'off'} | {cs:g} / {ms:g} | {len(w)} / {len(c)} | {_account(w)} | {_account(c)} |"
                )


def table_tyrex(data: Path, out: Path) -> None:
    print(
        "\n| person | motion | duration (s) | detector | steps whole / chunked | max position difference (m) | bias whole | bias chunked | rejected steps whole / chunked |"
    )
    print("|---|---|---:|---|---|---:|---|---|---|")
    for motion in ("Texting", "Swinging"):
        for person in PEOPLE:
            d = data / "tyrex-attitude" / "ios" / f"{person}_iPhone5_NoDist_{motion}"
            if not d.is_dir():
                print(f"| {person} | {motion} | missing | | | | | | |")
                continue
            rec = max(read_segments(d), key=lambda r: r.n_samples)
            p = out / f"{person}_{motion}.csv"
            write_gaitml_csv(rec, p)
            for det in ("adaptive", "single-peak"):
                w = run_pdr(read_recording(p), modes="forward", gyro_bias="auto", detector=det)
                c = long_pdr(p, modes="forward", gyro_bias="auto", detector=det, chunk_s=30.0, margin_s=30.0, progress=False)
                rw = (w.info.get("gait_check") or {}).get("n_steps_rejected")
                rc = (c.info.get("gait_check") or {}).get("n_steps_rejected")
                print(
                    f"| {person} | {motion} | {rec.duration_s:.0f} | {det} | {w.n_steps} / {c.n_steps} | {_pos_diff(w, c):.2e} | "
                    f"{_b(w.info)} | {_b(c.info)} | {rw} / {rc} |"
                )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path(os.environ.get("GAITML_SHARED_DATA", "../shared/data")))
    ap.add_argument("--out", type=Path, default=Path("/tmp/long_input_equivalence"))
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    table_bias(args.out)
    table_gait(args.out)
    table_tyrex(args.data, args.out)


if __name__ == "__main__":
    main()
