"""GetSensorData logs and landmark scoring, checked through the CLI a user runs (issue 31).

``python -m experiments.scripts.gsd_landmarks [--seeds 0 1 2] [--routes rectangle arc] [--out DIR] [--report FILE]``
from the repository root.

1. **Reading.** Simulated walks (``gaitml.simulate``) written as GetSensorData logs by
   :func:`gaitml.io.getsensordata.write_getsensordata` with every published line type,
   odd lines (blank lines, lines without the accuracy field, lines ending in ``;``, a
   cut-short last line), out-of-order and repeated events, the gyroscope on its own
   sensor clock, and one log without a gyroscope. Each is read by ``gaitml info --json``
   and checked against its raw lines: event counts per type, rates, and the merged
   accelerometer and gyroscope against the simulator's own samples at the same times.
2. **Scoring.** ``gaitml simulate`` routes with known truth, scored by ``gaitml pdr
   --truth`` three ways from the same walk: the dense truth (``<id>.trajectory.csv``),
   sparse landmarks taken from it every 10 s (CSV ``t,x_m,y_m``), and the walk converted
   to a GetSensorData log whose POSI lines carry those landmarks in latitude/longitude
   with a floor change half way (``--truth self``). Nothing is fitted, so there is no
   held-out split; seeds give the spread.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import shlex
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.cli import main as gaitml_main
from gaitml.io import read_gaitml_csv
from gaitml.io.getsensordata import write_getsensordata
from gaitml.io.truth import unproject_xy

__all__ = ["main"]

LAT0, LON0 = 40.3133, -3.4833  # an origin for the lat/lon landmarks (any site works)
OTHER_LINES = [
    "MAGN;{t:.3f};{s:.3f};21.5;-4.2;-38.1;3",
    "PRES;{t:.3f};{s:.3f};1013.25;3",
    "LIGH;{t:.3f};{s:.3f};310.0;3",
    "PROX;{t:.3f};{s:.3f};5.0;3",
    "HUMI;{t:.3f};{s:.3f};41.0;3",
    "TEMP;{t:.3f};{s:.3f};22.5;3",
    "AHRS;{t:.3f};{s:.3f};1.2;-3.4;95.0;0.01;0.02;0.70;3",
    "GNSS;{t:.3f};1700000000.000;40.3133;-3.4833;650.0;12.0;8.0;1.1;14;9",
    "WIFI;{t:.3f};{t:.3f};eduroam;00:11:22:33:44:55;2412;-67",
    "BLUE;{t:.3f};beacon;AA:BB:CC:DD:EE:FF;-81",
    "SOUN;{t:.3f};0.012;0.021;60.4",
]


def _cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = gaitml_main(argv)
    return code, out.getvalue(), err.getvalue()


def _reading_case(rec, path: Path, case: str, rng) -> dict:
    """Write one log variant of a simulated recording, read it with `gaitml info`, check it against the raw lines."""
    t = rec.t_s
    fs = rec.sampling_rate_hz
    ta = t + rng.uniform(0, 0.3 / fs, len(t))
    tg = t + 0.002 + rng.uniform(0, 0.3 / fs, len(t))
    extra = [line.format(t=ti, s=ti + 1000.0) for ti in t[:: int(fs)] for line in OTHER_LINES[:1]]
    extra += [line.format(t=ti, s=ti + 1000.0) for ti in t[:: int(10 * fs)] for line in OTHER_LINES[1:]]
    gyro = case != "no gyroscope"
    write_getsensordata(
        path,
        ta,
        rec.acc,
        t_gyr_s=tg if gyro else None,
        gyr=rec.gyr if gyro else None,
        gyr_sensor_origin_s=500.0 if case == "gyroscope on its own clock" else None,
        extra_lines=extra,
    )
    lines = path.read_text().splitlines()
    n_swapped = n_repeat = 0
    if case == "odd lines, out of order, repeats":
        acce = [i for i, line in enumerate(lines) if line.startswith("ACCE;")]
        for k in range(200, len(acce) - 2, 997):  # swap neighbours: out of order by one sample
            i, j = acce[k], acce[k + 1]
            lines[i], lines[j] = lines[j], lines[i]
            n_swapped += 1
        for k in range(350, len(acce) - 2, 1999):  # repeat an event
            lines[acce[k]] = lines[acce[k]] + "\n" + lines[acce[k]]
            n_repeat += 1
        lines = "\n".join(lines).split("\n")
        gyro_idx = [i for i, line in enumerate(lines) if line.startswith("GYRO;")]
        for i in gyro_idx[::500]:
            lines[i] = lines[i].rsplit(";", 1)[0]  # no accuracy field
        for i in gyro_idx[250::500]:
            lines[i] = lines[i] + ";"  # trailing separator
        lines.insert(len(lines) // 2, "")
        lines.append("ACCE;99999.000;100")  # cut short by the app stopping
    path.write_text("\n".join(lines) + "\n")
    raw = path.read_text().splitlines()
    code, out, err = _cli(["info", str(path), "--json"])
    if code != 0:
        return {"case": case, "error": err.strip()}
    d = json.loads(out)
    gsd = d["getsensordata"]
    n_acce_raw = sum(line.startswith("ACCE;") for line in raw) - (1 if case.startswith("odd") else 0)
    n_gyro_raw = sum(line.startswith("GYRO;") for line in raw)
    other_raw = {k[:4]: sum(line.startswith(k[:4] + ";") for line in raw) for k in OTHER_LINES}
    # values: the reader's merged samples against the simulator's at the same moments
    back = _cli(["info", str(path), "--json"])  # same command again: the output is deterministic
    assert back[1] == out
    from gaitml.io import read_recording

    got = read_recording(path)
    t_sim = got.meta["t0_original_s"] + got.t_s - 0.004  # app clock = simulator time + the writer's 4 ms latency
    # the writer logs sample i at its jittered time: the logged signal is (ta, acc), (tg, gyr)
    acc_ref = np.column_stack([np.interp(t_sim, ta, rec.acc[:, j]) for j in range(3)])
    row = {
        "case": case,
        "ACCE lines": n_acce_raw,
        "ACCE read": gsd["ACCE"]["events"],
        "GYRO lines": n_gyro_raw,
        "GYRO read": gsd.get("GYRO", {}).get("events", 0),
        "reordered / repeats written": f"{n_swapped} / {n_repeat}",
        "reordered / repeats found": f"{gsd['ACCE']['reordered']} / {gsd['ACCE']['duplicates']}",
        "other types (lines = counted)": all(d.get("other_sensors", {}).get(k, {}).get("lines") == v for k, v in other_raw.items()),
        "ACCE / GYRO rate_hz": f"{gsd['ACCE']['rate_hz']:.1f} / {gsd.get('GYRO', {}).get('rate_hz', float('nan')):.1f}",
        "max |acc - sim| m/s^2": float(np.max(np.abs(got.acc - acc_ref))),
        "median |acc - sim| m/s^2": float(np.median(np.abs(got.acc - acc_ref))),
        "warnings": len(d.get("warnings", [])),
    }
    if got.has_gyr:
        gyr_ref = np.column_stack([np.interp(t_sim, tg, rec.gyr[:, j]) for j in range(3)])
        row["max |gyr - sim| rad/s"] = float(np.max(np.abs(got.gyr - gyr_ref)))
        row["median |gyr - sim| rad/s"] = float(np.median(np.abs(got.gyr - gyr_ref)))
    return row


def reading(out: Path, seed: int) -> pd.DataFrame:
    from gaitml.simulate import simulate_dataset

    rec = simulate_dataset(1, 120.0, seed=seed, sampling_rate_hz=100.0)[0]
    rng = np.random.default_rng(seed)
    cases = ["every line type", "gyroscope on its own clock", "odd lines, out of order, repeats", "no gyroscope"]
    return pd.DataFrame([_reading_case(rec, out / f"read-{k}.txt", c, rng) for k, c in enumerate(cases)])


def scoring(out: Path, routes: list[str], seeds: list[int], align: str, pdr_args: list[str] | None = None) -> pd.DataFrame:
    rows = []
    for route in routes:
        for seed in seeds:
            d = out / f"{route}-{seed}"
            code, _, err = _cli(["simulate", str(d), "--subjects", "1", "--route", route, "--seed", str(seed), "--modes", "walk"])
            if code:
                raise SystemExit(err)
            rec_path = d / str(pd.read_csv(d / "manifest.csv")["file"].iloc[0])
            traj_path = rec_path.with_name(rec_path.stem + ".trajectory.csv")
            traj = pd.read_csv(traj_path)
            step = int(round(10.0 / float(np.median(np.diff(traj["t"])))))
            lm = pd.concat([traj.iloc[::step], traj.iloc[[-1]]])[["t", "x_m", "y_m"]]
            lm.to_csv(d / "landmarks.csv", index=False)
            lat, lon = unproject_xy(lm[["x_m", "y_m"]].to_numpy(), LAT0, LON0)
            floor = (np.arange(len(lm)) >= len(lm) // 2).astype(int)
            rec = read_gaitml_csv(rec_path)
            log = d / "walk-gsd.txt"
            posi = pd.DataFrame({"t_s": lm["t"].to_numpy() + 0.004, "lat_deg": lat, "lon_deg": lon, "floor": floor})
            write_getsensordata(log, rec.t_s, rec.acc, t_gyr_s=rec.t_s + 0.001, gyr=rec.gyr, landmarks=posi)
            h0 = float(traj["heading_rad"].iloc[0])
            for name, inp, truth in (
                ("dense", rec_path, traj_path),
                ("landmarks", rec_path, d / "landmarks.csv"),
                ("GSD log POSI", log, "self"),
            ):
                argv = ["pdr", str(inp), "--truth", str(truth), "--truth-align", align, "--json", "--initial-heading-rad", str(h0)]
                argv += ["--modes", "forward"]  # walk-only routes; the log carries no labels
                argv += list(pdr_args or [])
                code, o, err = _cli(argv)
                if code:
                    rows.append({"route": route, "seed": seed, "truth": name, "error": err.strip()[:200]})
                    continue
                tr = json.loads(o)["truth"]
                rows.append(
                    {
                        "route": route,
                        "seed": seed,
                        "truth": name,
                        "points": tr["n_points"],
                        "mean_m": tr["mean_error_m"],
                        "p75_m": tr["p75_error_m"],
                        "max_m": tr["max_error_m"],
                        "end_m": tr["end_error_m"],
                        "distance_m": tr["distance_m"],
                        "end_%D": tr.get("end_error_pct_distance"),
                        "segments": len(tr.get("segments", [])) or 1,
                    }
                )
            print(f"  {route} seed {seed} scored", file=sys.stderr)
    return pd.DataFrame(rows)


def tyrex(data: Path, detector: str) -> pd.DataFrame:
    """Every tyrex recording with motion capture scored by `gaitml pdr --truth self` (the walker's low-passed path),
    beside a still trajectory (the start point held) scored the same way."""
    from gaitml.evaluation.positioning import score_positions
    from gaitml.evaluation.trajectory import body_track
    from gaitml.io import read_recording
    from gaitml.io.truth import tyrex_truth

    rows = []
    folders = sorted(p for plat in ("android", "ios") for p in (data / plat).iterdir() if p.is_dir() and not p.name.startswith("calib"))
    for f in folders:
        if f.name.endswith("_old"):
            continue
        code, o, err = _cli(["pdr", str(f), "--truth", "self", "--detector", detector, "--json"])
        person, phone, dist, motion = f.name.split("_")[:4]
        row = {"recording": f.name, "person": person, "phone": phone, "motion": motion.replace("Backpocket", "BackPocket")}
        if code:
            rows.append({**row, "error": err.strip().splitlines()[-1][:160]})
            continue
        tr = json.loads(o)["truth"]
        rec = read_recording(f)
        truth = tyrex_truth(rec, smooth=body_track).table
        _, still = score_positions([0.0, rec.duration_s], [[0.0, 0.0], [0.0, 0.0]], truth, align="start", t_end_s=rec.duration_s)
        rows.append(
            {
                **row,
                "mean_m": tr["mean_error_m"],
                "p75_m": tr["p75_error_m"],
                "end_%D": tr.get("end_error_pct_distance"),
                "walked_m": tr["distance_m"],
                "still_mean_m": still["mean_error_m"],
                "still_p75_m": still["p75_error_m"],
            }
        )
        print(f"  {f.name}: mean {tr['mean_error_m']:.2f} m (still {still['mean_error_m']:.2f} m)", file=sys.stderr)
    return pd.DataFrame(rows)


def _md(df: pd.DataFrame, floats: str = "{:.3f}") -> str:
    def cell(v):
        return floats.format(v) if isinstance(v, float) else str(v)

    lines = ["| " + " | ".join(map(str, df.columns)) + " |", "|" + "---|" * len(df.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.gsd_landmarks", description=__doc__.split("\n")[0])
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    p.add_argument("--routes", nargs="+", default=["rectangle", "arc"])
    p.add_argument("--align", default="start-heading", choices=("start-heading", "start"))
    p.add_argument("--out", default="runs/gsd-landmarks", help="folder for the written logs and walks")
    p.add_argument("--tyrex", metavar="DATA", help="score every tyrex recording instead (DATA: ../shared/data/tyrex-attitude)")
    p.add_argument("--detector", default="adaptive", help="step detector for --tyrex (default adaptive)")
    p.add_argument("--csv", metavar="FILE", help="with --tyrex: write the per-recording table")
    p.add_argument("--pdr-args", default="", help="extra gaitml pdr options for the scoring, e.g. '--detector single-peak --gyro-bias off'")
    p.add_argument("--no-reading", action="store_true", help="skip part 1 (reading the logs); score only")
    args = p.parse_args(argv)
    if args.tyrex:
        df = tyrex(Path(args.tyrex), args.detector)
        if args.csv:
            df.to_csv(args.csv, index=False)
        ok = df.dropna(subset=["mean_m"])
        print(f"## tyrex: gaitml pdr --truth self --detector {args.detector} (median over recordings; per-person medians in brackets)\n")
        rows = []
        for motion, g in ok.groupby("motion"):
            per = g.groupby("person")[["mean_m", "p75_m", "still_mean_m"]].median()
            rows.append(
                {
                    "motion": motion,
                    "n": len(g),
                    "mean_m": f"{g['mean_m'].median():.2f} ({', '.join(f'{v:.2f}' for v in per['mean_m'])})",
                    "p75_m": f"{g['p75_m'].median():.2f} ({', '.join(f'{v:.2f}' for v in per['p75_m'])})",
                    "still mean_m": f"{g['still_mean_m'].median():.2f} ({', '.join(f'{v:.2f}' for v in per['still_mean_m'])})",
                    "PDR better than still": f"{int((g['mean_m'] < g['still_mean_m']).sum())}/{len(g)}",
                    "end_%D": f"{g['end_%D'].median():.1f}",
                    "walked_m": f"{g['walked_m'].median():.0f}",
                }
            )
        print(_md(pd.DataFrame(rows)))
        if len(ok) < len(df):
            print(
                f"\n{len(df) - len(ok)} recordings refused: "
                + "; ".join(f"{r.recording}: {r.error}" for r in df[df["mean_m"].isna()].itertuples())
            )
        return 0
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    if not args.no_reading:
        read = reading(out, args.seeds[0])
        print("## Reading GetSensorData logs (gaitml info --json against the raw lines)\n")
        print(_md(read, "{:.4g}"))
    score = scoring(out, args.routes, args.seeds, args.align, shlex.split(args.pdr_args))
    print(f"\n## Scoring (gaitml pdr --truth, --truth-align {args.align} {args.pdr_args}), one row per route/seed/truth\n")
    print(_md(score))
    ok = score.dropna(subset=["mean_m"]) if "mean_m" in score else score
    if len(ok):
        summ = ok.groupby(["route", "truth"], sort=False)[["mean_m", "p75_m", "end_m", "end_%D"]]
        agg = summ.mean().round(3).astype(str) + " (" + summ.min().round(3).astype(str) + ", " + summ.max().round(3).astype(str) + ")"
        print("\n## Mean (min, max) over seeds\n")
        print(_md(agg.reset_index()))
    print(f"\n({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
