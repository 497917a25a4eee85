"""The foot-placement rule (gaitml.models._placement): chosen on the simulator, scored once on real sensors.

    python -m experiments.scripts.foot_placement [--data ../shared/data] [--cache /tmp/foot_placement] [--out FILE]

Prints every table of ``experiments/reports/foot-placement.md``:

1. **selection** (simulator only, the seeds the values were chosen on): the share of windows each
   test of the rule flags per simulated phone position (seed 1, 4 subjects x 120 s, five modes, the
   seven positions) and on a simulated foot walking / running (:func:`gaitml.simulate.foot.simulate_foot`,
   seeds 0-9, 60 s at 100 Hz read at 50 Hz as ``predict`` reads it), over a grid of the settings the
   physics leaves open; the gyroscope test, the accelerometer test, and the rule (either test);
2. **held-out simulator**: the same with the chosen settings on other seeds (phones seed 2024,
   foot seeds 100-119), per position and per mode, alone and through ``models/demo`` /
   ``models/demo-acc`` (flagged before the rule, i.e. the model's own check, and after);
3. **real foot-mounted IMUs** (gaitmap example data: every file, each foot): flagged by each
   test and the rule, and through the shipped models before / after;
4. **tyrex** (real phones with a gyroscope; nothing was fitted on them, so every person is held
   out): false alarms of the rule per person and motion, over every window and over the moving
   windows (body speed > 0.3 m/s by the motion capture), and ``models/demo``'s flags and right
   answers on the moving windows before / after;
5. **Oxford and IFSM** (real phones, accelerometer only): false alarms of the accelerometer test
   per carrying position, and ``models/demo-acc`` before / after.

"Before" is :func:`gaitml.models.predict_recording` with the rule switched off
(``gaitml.models._predict.foot_placement`` patched to return None), "after" the same call as shipped.
Simulated and real recordings are cached under ``--cache`` (a rerun takes about a minute).
"""

from __future__ import annotations

import argparse
import itertools
import pickle
import sys
from pathlib import Path
from unittest import mock

import numpy as np
import pandas as pd

from gaitml.models._placement import (
    ACC_MIN_REST_S,
    MIN_REST_S,
    REST_ACC_STD_MS2,
    REST_ACC_TOL_MS2,
    REST_GYR_RADS,
    SWING_ACC_MS2,
    SWING_GYR_RADS,
)

__all__ = ["rule_counts", "main"]

FS_HZ = 50.0
PHONE_POSITIONS = ("hand-flat", "hand-tilted", "swinging-hand", "front-pocket", "back-pocket", "bag", "belt")
SELECTION_SEED, HELDOUT_SEED = 1, 2024
FOOT_SELECTION_SEEDS, FOOT_HELDOUT_SEEDS = tuple(range(10)), tuple(range(100, 120))
GAITMAP_FILES = (
    ("imu_sample", "2 x 20 m walk", ("left", "right")),
    ("imu_sample_ic_stride", "4 x 10 m walk", ("left", "right")),
    ("imu_sample_healthy_stair_up", "stairs up", ("left", "right")),
    ("imu_sample_healthy_stair_down", "stairs down", ("left", "right")),
    ("imu_sample_ms_left", "MS patient, long walk", (None,)),
    ("imu_sample_ms_right", "MS patient, long walk", (None,)),
)
OXFORD_POSITIONS = ("InHand", "FrontPocket", "BackPocket", "SwingingArm", "Purse", "NeckPouch", "Armband")
#: The selection grid (gyroscope rule): shortest stance rest, swing rate, rest rate, rest |acc| margin around g
#: (0.873 rad/s = 50 deg/s with 1.0 m/s^2: the stance conditions of Jimenez et al. 2009).
GYRO_GRID = {
    "min_rest_s": (0.1, 0.12, 0.14, 0.16, 0.2),
    "swing_gyr_rads": (3.0, 4.0),
    "rest_gyr_rads": (0.3, 0.5, 0.873),
    "rest_acc_tol_ms2": (0.5, 1.0),
}
#: The selection grid (accelerometer-only rule): shortest stance rest, swing magnitude, rest standard deviation.
ACC_GRID = {"acc_min_rest_s": (0.1, 0.14, 0.2), "swing_acc_ms2": (15.0, 19.6, SWING_ACC_MS2), "rest_acc_std_ms2": (0.08, 0.15, 0.3)}


def _log(msg: str) -> None:
    print(f"[foot_placement] {msg}", file=sys.stderr, flush=True)


def _cached(cache: Path, name: str, make):
    path = cache / f"{name}.pkl"
    if path.exists():
        with path.open("rb") as f:
            return pickle.load(f)
    out = make()
    cache.mkdir(parents=True, exist_ok=True)
    with path.open("wb") as f:
        pickle.dump(out, f)
    return out


def _windows(rec):
    from gaitml.models._predict import _windows_for

    return _windows_for(rec, 1.5, 0.5)


def simulated(seed: int, foot_seeds, n_subjects: int = 4) -> dict[str, list]:
    """Simulated phones (every position, five modes) and a simulated foot walking / running, at 50 Hz."""
    from gaitml.simulate import simulate_dataset
    from gaitml.simulate.foot import simulate_foot

    out: dict[str, list] = {}
    for r in simulate_dataset(n_subjects=n_subjects, duration_s=120.0, pose="mixed", seed=seed, positions=PHONE_POSITIONS):
        out.setdefault(r.meta["position"], []).append(r)
    for mode in ("walk", "run"):
        out[f"foot ({mode})"] = [
            foot_at_model_rate(simulate_foot(modes=(mode,), duration_s=60.0, sampling_rate_hz=100.0, seed=s)) for s in foot_seeds
        ]
    return out


def foot_at_model_rate(rec):
    """A simulated foot at 50 Hz by :func:`gaitml.models.resample_recording`, as ``predict_recording`` reads it
    (with its unit check: the running feet's median |acc| of 35-51 m/s^2 passes by its 5th percentile)."""
    from gaitml.models import resample_recording

    return resample_recording(rec, FS_HZ)


def rule_counts(recs, key: str = "foot_like", acc_only: bool = False, **kw) -> tuple[int, int]:
    """Windows, and windows where ``key`` of the rule holds (``foot_like``, ``gyro_test``, ``acc_test``), over ``recs``.

    1.5 s windows, 50 % overlap, at 50 Hz, as the shipped models; ``acc_only``: the recordings without their gyroscope.
    """
    from gaitml.models import resample_recording
    from gaitml.models._placement import foot_like_windows

    n = k = 0
    for r in recs:
        r = resample_recording(r, FS_HZ)
        w = _windows(r)
        f = foot_like_windows(r.acc, None if acc_only else r.gyr, FS_HZ, w, **kw)[key]
        n += len(f)
        k += int(f.sum())
    return n, k


def _share(n: int, k: int) -> float:
    return k / n if n else float("nan")


def _rule_columns(recs) -> dict:
    """Windows and the share each test flags, and the rule as shipped (either test)."""
    n, g = rule_counts(recs, "gyro_test")
    _, a = rule_counts(recs, "acc_test")
    _, f = rule_counts(recs, "foot_like")
    return {"windows": n, "gyroscope test": _share(n, g), "accelerometer test": _share(n, a), "rule (either)": _share(n, f)}


def selection_tables(sel: dict) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The grids over the selection seeds: flagged share per position, gyroscope and accelerometer-only rules."""
    out = []
    for acc_only, grid in ((False, GYRO_GRID), (True, ACC_GRID)):
        rows = []
        for vals in itertools.product(*grid.values()):
            kw = dict(zip(grid, vals, strict=True))
            row = dict(kw)
            for pos, recs in sel.items():
                row[pos] = _share(*rule_counts(recs, "acc_test" if acc_only else "gyro_test", acc_only=acc_only, **kw))
            row["worst phone position"] = max(row[p] for p in PHONE_POSITIONS)
            chosen = (
                (kw["acc_min_rest_s"], kw["rest_acc_std_ms2"], kw["swing_acc_ms2"]) == (ACC_MIN_REST_S, REST_ACC_STD_MS2, SWING_ACC_MS2)
                if acc_only
                else (kw["min_rest_s"], kw["swing_gyr_rads"], kw["rest_gyr_rads"], kw["rest_acc_tol_ms2"])
                == (MIN_REST_S, SWING_GYR_RADS, REST_GYR_RADS, REST_ACC_TOL_MS2)
            )
            row["chosen"] = "**chosen**" if chosen else ""
            rows.append(row)
        out.append(pd.DataFrame(rows))
    return out[0], out[1]


def _predict_pair(model, rec) -> tuple[pd.DataFrame, pd.DataFrame]:
    """``predict_recording`` without the rule (the model's own check) and as shipped."""
    from gaitml.models import predict_recording

    with mock.patch("gaitml.models._predict.foot_placement", return_value=None):
        before = predict_recording(model, rec)
    return before, predict_recording(model, rec)


def _flagged(p: pd.DataFrame) -> np.ndarray:
    return np.array([v is False or v is np.False_ for v in p["in_domain"]], dtype=bool)


def model_counts(model, recs) -> dict:
    """Windows, flagged before / after the rule, over ``recs``."""
    n = b = a = 0
    for r in recs:
        if "gyro" in model.feature_set and r.gyr is None:
            return {}
        before, after = _predict_pair(model, r)
        n += len(after)
        b += int(_flagged(before).sum())
        a += int(_flagged(after).sum())
    return {"windows": n, "before": _share(n, b), "after": _share(n, a)}


def heldout_sim_tables(held: dict, models: dict) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per position: the rule alone (gyroscope, accelerometer only) and each model before / after; and per mode."""
    rows, mode_rows = [], []
    for pos, recs in held.items():
        row = {"position": pos, **_rule_columns(recs)}
        for name, m in models.items():
            c = model_counts(m, recs)
            row[f"{name} before"], row[f"{name} after"] = c.get("before", np.nan), c.get("after", np.nan)
        rows.append(row)
        _log(f"held-out simulator {pos}")
        if pos.startswith("foot"):
            continue
        from gaitml.models._placement import foot_like_windows

        per: dict[str, list[int]] = {}
        for r in recs:
            w = _windows(r)
            f = foot_like_windows(r.acc, r.gyr, FS_HZ, w)["foot_like"]
            lab = np.asarray(r.labels).astype(str)
            mid = lab[np.minimum((w["start"].to_numpy() + w["end"].to_numpy()) // 2, len(lab) - 1)]
            for mode in np.unique(mid):
                c = per.setdefault(str(mode), [0, 0])
                c[0] += int(np.sum(mid == mode))
                c[1] += int(np.sum(f & (mid == mode)))
        mode_rows.append({"position": pos, **{m: _share(*per[m]) for m in sorted(per)}})
    return pd.DataFrame(rows), pd.DataFrame(mode_rows)


def _acc_only(rec):
    from gaitml.recording import Recording

    return Recording.from_arrays(rec.acc, rec.sampling_rate_hz, meta=dict(rec.meta))


def gaitmap_table(data: Path, models: dict) -> pd.DataFrame:
    """Every gaitmap foot-mounted recording, each foot: the rule alone and through the models, before / after."""
    from gaitml.io import read_recording

    rows = []
    for stem, what, sensors in GAITMAP_FILES:
        path = data / "gaitmap-example" / f"{stem}.csv.gz"
        if not path.exists():
            continue
        recs = [read_recording(path) if s is None else read_recording(path, sensor=s) for s in sensors]
        row = {"file": f"{stem} ({what})", "sensors": ", ".join(s or "one" for s in sensors), **_rule_columns(recs)}
        for name, m in models.items():
            c = model_counts(m, recs)
            row[f"{name} before"], row[f"{name} after"] = c["before"], c["after"]
            if "gyro" not in m.feature_set:  # the same model on the file without its gyroscope: the accelerometer-only rule
                c = model_counts(m, [_acc_only(r) for r in recs])
                row[f"{name} without gyroscope before"], row[f"{name} without gyroscope after"] = c["before"], c["after"]
        rows.append(row)
        _log(f"gaitmap {stem}")
    return pd.DataFrame(rows)


def tyrex_items(data: Path, cache: Path) -> list[dict]:
    from experiments.scripts.tyrex_modes import load_tyrex_labelled

    def make():
        return [
            {k: it[k] for k in ("subject", "phone", "motion", "mode", "position", "recording")} for it in load_tyrex_labelled(data, FS_HZ)
        ]

    return _cached(cache, "tyrex50", make)


def tyrex_rows(items: list[dict], model) -> pd.DataFrame:
    """Per recording: windows, moving and standing windows, the rule's flags (gyroscope, accelerometer only) and ``model``'s."""
    from gaitml.models._placement import foot_like_windows

    rows = []
    for it in items:
        rec = it["recording"]
        before, after = _predict_pair(model, rec)
        w = after[["start", "end"]]
        res = foot_like_windows(rec.acc, rec.gyr, FS_HZ, w)
        f, fg, fa = res["foot_like"], res["gyro_test"], res["acc_test"]
        lab, frac = after["label"].astype(str).to_numpy(), after["label_fraction"].to_numpy(float)
        moving = (lab == it["mode"]) & (frac >= 0.5)
        standing = (lab == "still") & (frac >= 0.5)
        fb, fa_ = _flagged(before), _flagged(after)
        right_b = moving & ~fb & (before["mode"].astype(str).to_numpy() == it["mode"])
        right_a = moving & ~fa_ & (after["mode"].astype(str).to_numpy() == it["mode"])
        rows.append(
            {
                "subject": it["subject"],
                "phone": it["phone"],
                "motion": it["motion"],
                "windows": len(after),
                "rule": int(f.sum()),
                "rule_acc": int(fa.sum()),
                "rule_gyro": int(fg.sum()),
                "moving": int(moving.sum()),
                "rule_moving": int((f & moving).sum()),
                "rule_acc_moving": int((fa & moving).sum()),
                "standing": int(standing.sum()),
                "rule_standing": int((f & standing).sum()),
                "flag_before_moving": int((fb & moving).sum()),
                "flag_after_moving": int((fa_ & moving).sum()),
                "right_before": int(right_b.sum()),
                "right_after": int(right_a.sum()),
            }
        )
    return pd.DataFrame(rows)


def tyrex_summary(t: pd.DataFrame, by: str) -> pd.DataFrame:
    """Shares per ``by`` (motion or subject x motion), pooled over the recordings."""
    g = t.groupby(by, sort=True).sum(numeric_only=True)
    out = pd.DataFrame(
        {
            "windows": g["windows"],
            "rule, all windows": g["rule"] / g["windows"],
            "rule, moving windows": g["rule_moving"] / g["moving"],
            "gyroscope test, all windows": g["rule_gyro"] / g["windows"],
            "accelerometer test, all windows": g["rule_acc"] / g["windows"],
            "demo flagged (moving) before": g["flag_before_moving"] / g["moving"],
            "demo flagged (moving) after": g["flag_after_moving"] / g["moving"],
            "demo right (moving) before": g["right_before"] / g["moving"],
            "demo right (moving) after": g["right_after"] / g["moving"],
        }
    )
    return out.reset_index()


def tyrex_person_motion(t: pd.DataFrame) -> pd.DataFrame:
    """The rule's false alarms over every window, one column per person, one row per motion (and all motions)."""
    rows = []
    for motion, g in itertools.chain(t.groupby("motion", sort=True), [("all", t)]):
        row = {"motion": motion}
        for person, h in g.groupby("subject", sort=True):
            row[person] = h["rule"].sum() / h["windows"].sum()
        row["worst recording"] = (g["rule"] / g["windows"]).max()
        rows.append(row)
    return pd.DataFrame(rows)


def oxford_table(data: Path, model) -> pd.DataFrame:
    """Oxford per position and the IFSM walks: the accelerometer-only rule, and ``model`` before / after."""
    from gaitml.io import read_dataset, read_recording

    rows = []
    ox = data / "oxford-step-counter" / "optimisation"
    groups: list[tuple[str, list]] = []
    if ox.exists():
        by_pos: dict[str, list] = {}
        for r in read_dataset(ox):
            by_pos.setdefault(str(r.meta.get("position", "")).lower(), []).append(r)
        groups += [(f"Oxford {p}", by_pos.get(p.lower(), [])) for p in OXFORD_POSITIONS]
    ifsm = data / "ifsm-flat-phone"
    if ifsm.exists():
        groups.append(("IFSM flat-held phone", [read_recording(f) for f in sorted(ifsm.glob("*.xlsx"))]))
    for what, recs in groups:
        if not recs:
            continue
        n, k = rule_counts(recs, "acc_test", acc_only=True)
        c = model_counts(model, recs)
        rows.append({"data": f"{what} ({len(recs)} walks)", "windows": n, "accelerometer test": _share(n, k), **c})
        _log(what)
    return pd.DataFrame(rows)


def md(df: pd.DataFrame, digits: int = 3) -> str:
    cols = list(df.columns)
    out = ["| " + " | ".join(str(c) for c in cols) + " |", "|" + "---|" * len(cols)]
    for r in df.itertuples(index=False):
        out.append("| " + " | ".join(f"{v:.{digits}f}" if isinstance(v, float) else str(v) for v in r) + " |")
    return "\n".join(out)


def main(argv=None) -> int:
    from gaitml.models import load_model

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--cache", type=Path, default=Path("/tmp/foot_placement"))
    ap.add_argument("--models", default="models/demo,models/demo-acc")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    models = {Path(m).name: load_model(m) for m in a.models.split(",") if m}
    text: list[str] = []

    def emit(s: str = "") -> None:
        print(s, flush=True)
        text.append(s)

    sel = _cached(a.cache, f"sim{SELECTION_SEED}", lambda: simulated(SELECTION_SEED, FOOT_SELECTION_SEEDS))
    gyro_sel, acc_sel = selection_tables(sel)
    emit(
        f"### 1. Selection on the simulator (phones seed {SELECTION_SEED}, 4 subjects x 120 s; foot seeds 0-9): share of windows flagged\n"
    )
    emit("Gyroscope test:\n")
    emit(md(gyro_sel))
    emit("\nAccelerometer test (rest within 0.5 m/s^2 of g):\n")
    emit(md(acc_sel))
    emit("\nThe rule as shipped (either test at the chosen values) on the same selection seeds:\n")
    emit(md(pd.DataFrame([{"position": pos, **_rule_columns(recs)} for pos, recs in sel.items()])))
    held = _cached(a.cache, f"sim{HELDOUT_SEED}", lambda: simulated(HELDOUT_SEED, FOOT_HELDOUT_SEEDS))
    pos_t, mode_t = heldout_sim_tables(held, models)
    emit(f"\n### 2. Held-out simulator (phones seed {HELDOUT_SEED}, 4 subjects x 120 s; foot seeds 100-119): share of windows flagged\n")
    emit(md(pos_t))
    emit("\nThe rule (either test) per mode of the simulated phones:\n")
    emit(md(mode_t))
    if (a.data / "gaitmap-example").exists():
        emit("\n### 3. Real foot-mounted IMUs (gaitmap example data): share of windows flagged\n")
        emit(md(gaitmap_table(a.data, models)))
    if (a.data / "tyrex-attitude").exists() and "demo" in models:
        items = tyrex_items(a.data, a.cache)
        t = _cached(a.cache, "tyrex_rows", lambda: tyrex_rows(items, models["demo"]))
        emit("\n### 4. Tyrex (real phones with a gyroscope, every person held out): the rule's false alarms\n")
        emit("Over every window, per person (the rule as shipped: either test):\n")
        emit(md(tyrex_person_motion(t)))
        emit("\nPer motion, pooled over the people (demo: `models/demo` through `predict_recording`, moving windows):\n")
        emit(md(tyrex_summary(t, "motion")))
        emit("\nPer person, pooled over the motions:\n")
        emit(md(tyrex_summary(t, "subject")))
        emit(
            f"\nStanding windows (body speed <= 0.3 m/s) flagged by the rule: {t['rule_standing'].sum()} of {t['standing'].sum()}; "
            f"moving windows: {t['rule_moving'].sum()} of {t['moving'].sum()}"
        )
    if "demo-acc" in models:
        ox = oxford_table(a.data, models["demo-acc"])
        if len(ox):
            emit("\n### 5. Real phones without a gyroscope (Oxford, IFSM): the accelerometer test, `models/demo-acc` before / after\n")
            emit(md(ox))
    emit("\nNo lower-back IMU in ../shared/data (the gaitmap example data has foot sensors only; see its README).")
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
