"""The clock alignment of every tyrex motion capture, checked against the phone's own sensors (issue 27/30).

Per recording with a motion capture (126): ``timeAlignment.txt``'s dt, the residual lag that
:func:`gaitml.io.tyrex.refine_tyrex_alignment` finds from |gyroscope| against the capture's |angular rate|
(``gyro``) and from |acc| against the capture's specific force ``|d2p/dt2 + g|`` (``acc``), the correlation at
the file's dt and at the refined lag, whether the refinement is accepted (its fixed rule: peak >= 0.8 and 0.05
above any other local maximum within +-1.5 s), the lag of the first and of the last third of the recording
(clock-rate drift; searched +-0.25 s around the whole recording's lag), and ``t0`` (the phone's first
accelerometer sample on the phone's clock, :func:`gaitml.io.read_tyrex`'s ``meta['t0_original_s']``) beside the
gyroscope lag found when the phone's times are taken from that first sample instead of the recording's start
(``t0 dropped``: what a check that forgets ``t0_original_s``, or a recording resampled by
:func:`gaitml.models.resample_recording` before the fix in this branch, sees).

``shift`` is what is added to the capture's phone-clock times (its dt becomes ``dt - shift``): negative where the
capture's events came later than the phone's. Nothing is fitted to a score: the lag is a measurement of the clock.

    python -m experiments.scripts.tyrex_alignment [--data ../shared/data] [--csv FILE]   # ~10 min
    python -m experiments.scripts.tyrex_alignment --from-csv FILE                      # the tables again
    python -m experiments.scripts.tyrex_alignment --mount                              # mount fits, running (~1 min)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd


def one(folder: Path) -> dict:
    """The alignment row of one recording folder."""
    from gaitml.io.tyrex import (
        ALIGN_THIRDS_SEARCH_S,
        parse_tyrex_name,
        read_tyrex_truth,
        refine_tyrex_alignment,
        tyrex_phone_logs,
    )

    info = parse_tyrex_name(folder.name) or {}
    truth = read_tyrex_truth(folder, align="file")
    t_acc, acc, t_gyr, gyr = tyrex_phone_logs(folder)
    g = refine_tyrex_alignment(truth, t_acc, acc, t_gyr, gyr, signal="gyro")
    a = refine_tyrex_alignment(truth, t_acc, acc, t_gyr, gyr, signal="acc")
    t0 = float(t_acc[0])
    lost = refine_tyrex_alignment(truth, t_acc - t0, acc, t_gyr - t0, gyr, signal="gyro")
    row = {
        "recording": folder.name,
        "phone": info.get("phone", ""),
        "person": info.get("person", ""),
        "motion": info.get("motion", ""),
        "dt_file_s": truth.dt_s,
        "t0_s": t0,
        "gyro_shift_s": g["shift_s"],
        "gyro_corr_file": g["corr_file"],
        "gyro_corr_peak": g["corr_peak"],
        "gyro_corr_second": g["corr_second"],
        "gyro_accepted": bool(g["accepted"]),
        "gyro_reason": g["reason"],
        "acc_shift_s": a["shift_s"],
        "acc_corr_file": a["corr_file"],
        "acc_corr_peak": a["corr_peak"],
        "acc_accepted": bool(a["accepted"]),
        "t0_dropped_shift_s": lost["shift_s"],
        "t0_dropped_corr_file": lost["corr_file"],
    }
    # clock-rate drift: the lag of the first and the last third, around the whole recording's
    centre = g["shift_s"] if g["accepted"] else 0.0
    lo, hi = max(t_gyr[0], truth.t_s[0]), min(t_gyr[-1], truth.t_s[-1])
    third = (hi - lo) / 3
    for name, w in (("first", (lo, lo + third)), ("last", (hi - third, hi))):
        r = refine_tyrex_alignment(
            truth, t_acc, acc, t_gyr, gyr, signal="gyro", window_s=w, search_s=ALIGN_THIRDS_SEARCH_S, centre_s=-centre
        )
        row[f"shift_{name}_third_s"] = r["shift_s"] if r["corr_peak"] >= 0.8 else float("nan")
    row["drift_s"] = row["shift_last_third_s"] - row["shift_first_third_s"]
    row["span_s"] = hi - lo
    return row


def table(data: Path) -> pd.DataFrame:
    from gaitml.io.tyrex import list_tyrex_folders, tyrex_truth_path

    rows = []
    for folder in list_tyrex_folders(data / "tyrex-attitude"):
        if tyrex_truth_path(folder) is None:
            continue
        rows.append(one(folder))
        print(f"  {folder.name}", file=sys.stderr, flush=True)
    return pd.DataFrame(rows)


def summary(df: pd.DataFrame) -> pd.DataFrame:
    """Per phone model: how many recordings, how many accepted, the refined lags and the correlations."""
    out = []
    for phone, g in [*df.groupby("phone"), ("all", df)]:
        acc_ok = g["gyro_accepted"]
        ga = g[acc_ok]
        both = ga[ga["acc_accepted"]]
        out.append(
            {
                "phone": phone,
                "recordings": len(g),
                "accepted (gyro)": int(acc_ok.sum()),
                "shift median (ms)": 1000 * ga["gyro_shift_s"].median(),
                "shift 5-95% (ms)": f"{1000 * ga['gyro_shift_s'].quantile(0.05):+.0f} .. {1000 * ga['gyro_shift_s'].quantile(0.95):+.0f}",
                "max |shift| (ms)": 1000 * ga["gyro_shift_s"].abs().max(),
                "corr at file dt": ga["gyro_corr_file"].median(),
                "corr refined": ga["gyro_corr_peak"].median(),
                "|gyro - acc| median (ms)": 1000 * (both["gyro_shift_s"] - both["acc_shift_s"]).abs().median(),
                "drift median |last-first| (ms)": 1000 * g["drift_s"].abs().median(),
                "drift max (ms)": 1000 * g["drift_s"].abs().max(),
                "t0 median (ms)": 1000 * g["t0_s"].median(),
                "t0-dropped shift median (ms)": 1000 * g["t0_dropped_shift_s"].median(),
            }
        )
    return pd.DataFrame(out)


def markdown(df: pd.DataFrame) -> str:
    """A markdown table (numbers to 3 significant digits)."""

    def cell(v):
        if isinstance(v, float):
            return "" if v != v else f"{v:.3g}"
        return str(v)

    lines = ["| " + " | ".join(map(str, df.columns)) + " |", "|" + "---|" * len(df.columns)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in df.itertuples(index=False)]
    return "\n".join(lines)


def mount_table(data: Path, motions=("RunningHand", "RunningPocket")) -> pd.DataFrame:
    """:func:`gaitml.io.tyrex.estimate_mount_rotation` on each running recording with the capture at the file's dt and
    refined, on the recording as read (~100-200 Hz) and resampled to 50 Hz (:func:`gaitml.models.resample_recording`,
    as the lab's labelled items hold it): the angle from identity and the RMS residual as a fraction of the rate's RMS."""
    from gaitml.io.tyrex import (
        estimate_mount_rotation,
        list_tyrex_folders,
        parse_tyrex_name,
        read_tyrex,
        read_tyrex_truth,
        tyrex_truth_path,
    )
    from gaitml.models import resample_recording

    rows = []
    for folder in list_tyrex_folders(data / "tyrex-attitude"):
        info = parse_tyrex_name(folder.name) or {}
        if info.get("motion") not in motions or tyrex_truth_path(folder) is None:
            continue
        rec = read_tyrex(folder)
        row = {"recording": folder.name, "phone": info.get("phone", "")}
        for align in ("file", "refine"):
            truth = read_tyrex_truth(folder, align=align)
            for tag, r in (("native", rec), ("50Hz", resample_recording(rec, 50.0))):
                _, m = estimate_mount_rotation(r, truth)
                row[f"{align} {tag} angle"] = m["angle_from_identity_deg"]
                row[f"{align} {tag} residual"] = m["rate_rms_residual_rads"] / m["rate_rms_rads"]
        rows.append(row)
    return pd.DataFrame(rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--csv", type=Path, default=None, help="write the per-recording table here")
    ap.add_argument("--from-csv", type=Path, default=None, help="print the tables of a CSV written earlier (nothing measured)")
    ap.add_argument("--mount", action="store_true", help="instead: the mount rotation's fit on the running recordings (~1 min)")
    a = ap.parse_args(argv)
    if a.mount:
        m = mount_table(a.data)
        print(markdown(m))
        print("\nMedian per phone:\n")
        print(markdown(m.drop(columns="recording").groupby("phone").median().reset_index()))
        return 0
    df = pd.read_csv(a.from_csv, keep_default_na=False, na_values=[""]) if a.from_csv else table(a.data)
    if a.from_csv:
        for c in ("gyro_accepted", "acc_accepted"):
            df[c] = df[c].astype(str).str.lower() == "true"
    if a.csv:
        df.to_csv(a.csv, index=False)
    print("## Per phone model\n")
    print(markdown(summary(df)))
    print("\n## Per recording (shifts in ms; corr = Pearson of the magnitudes)\n")
    show = pd.DataFrame(
        {
            "recording": df["recording"],
            "dt file (s)": df["dt_file_s"].map(lambda v: f"{v:+.3f}"),
            "gyro shift": (1000 * df["gyro_shift_s"]).round(0),
            "corr file": df["gyro_corr_file"].round(3),
            "corr refined": df["gyro_corr_peak"].round(3),
            "2nd peak": df["gyro_corr_second"].round(2),
            "accepted": df["gyro_accepted"].map({True: "yes", False: "no"}),
            "acc shift": (1000 * df["acc_shift_s"]).round(0),
            "acc corr file / refined": [f"{x:.2f} / {y:.2f}" for x, y in zip(df["acc_corr_file"], df["acc_corr_peak"], strict=True)],
            "first / last third": [
                f"{1000 * x:+.0f} / {1000 * y:+.0f}" for x, y in zip(df["shift_first_third_s"], df["shift_last_third_s"], strict=True)
            ],
            "t0": (1000 * df["t0_s"]).round(0),
            "t0 dropped": (1000 * df["t0_dropped_shift_s"]).round(0),
        }
    )
    print(markdown(show))
    rej = df[~df["gyro_accepted"]]
    if len(rej):
        print("\nNot accepted (file's dt kept):")
        for _, r in rej.iterrows():
            print(f"- {r['recording']}: {r['gyro_reason']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
