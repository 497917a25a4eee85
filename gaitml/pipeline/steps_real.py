"""Step detectors on the shared real recordings: the ``task = "steps"`` experiment.

Runs every step detector a config lists on

- the IFSM flat-held phone files (paper 000, 284 / 319 true steps), and
- the 48 Oxford step counter optimisation recordings (hard floor and carpet
  reported separately, per carrying position),

and writes ``per_recording.csv`` (one row per detector and recording: counts,
count accuracy, precision / recall / F1 at the matching tolerance, timing
offset, period error), ``oxford_by_position.csv`` (mean per detector, surface
and position, in sample and held out), ``heldout_per_recording.csv``,
``summary.json`` and ``report.md`` into the output folder (atomically).
Credit: "Oxford step counter data set, Salvi et al." (CC BY 4.0).

Held-out evaluation (``[evaluation] holdout``): leave-one-user-out and / or
leave-one-position-out on the Oxford recordings. A detector that declares a
``param_grid`` (:class:`gaitml.steps.BaseStepDetector`) also runs as
``"<name> (tuned)"``: in sample its setting is chosen on every hard-floor
Oxford recording (:meth:`~gaitml.steps.BaseStepDetector.tune`, best mean count
accuracy); held out it is chosen on the hard-floor recordings of the other
users (positions) only and scored on the held-out user's (position's)
recordings, hard and carpet. A detector used as it is (the paper detectors, and
every detector's defaults) has no setting fitted here, so its held-out figure
is its in-sample one; the report says which rows were fitted. The carpet
recordings are scored but never used for tuning (their foot switches
under-trigger).

Run: ``gaitml evaluate experiments/steps-real.toml [--out DIR] [--data DIR]`` (the
config's keys: :mod:`gaitml.pipeline.config`).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.evaluation.steps import evaluate_steps
from gaitml.io import atomic_dir, read_recording
from gaitml.io.oxford import list_oxford_folders
from gaitml.pipeline.config import STEP_DATA_SETS, STEP_TOLERANCE_S, ExperimentConfig
from gaitml.steps import DETECTORS, detector_names, get_detector

__all__ = [
    "run_steps_real",
    "evaluate_recording",
    "evaluate_steps_config",
    "summarise_oxford",
    "load_recordings",
    "holdout_folds",
    "tuned_evaluation",
    "TUNED_SUFFIX",
]

TOLERANCE_S = STEP_TOLERANCE_S
#: paper 000 Table 2 (true, AD-FSM, autocorrelation, IFSM) per IFSM file
PAPER_TABLE2 = {
    "acceleration_flat_holding_1": {"true": 284, "adfsm": 282, "autocorr": 279, "ifsm": 284},
    "acceleration_flat_holding_2": {"true": 319, "adfsm": 316, "autocorr": 316, "ifsm": 319},
}
#: paper 000 Table 3: manually read durations of the first 10 steps of file 1 (s)
PAPER_TABLE3_MANUAL_S = np.array([0.64, 0.56, 0.58, 0.50, 0.54, 0.50, 0.54, 0.52, 0.54, 0.50])


#: suffix of the rows of a detector whose ``param_grid`` setting the evaluation chose
TUNED_SUFFIX = " (tuned)"
#: the recording meta key each held-out scheme leaves out, one value at a time
HOLDOUT_KEYS = {"user": "user", "position": "position"}
#: the surface whose recordings a tuned detector is tuned on (carpet foot switches under-trigger)
TUNING_SURFACE = "Hard"


def evaluate_recording(rec, detector: str, *, tolerance_s: float = TOLERANCE_S, params: dict | None = None) -> dict:
    """Detect steps in ``rec`` with ``detector`` (optionally with ``params`` set) and evaluate against its reference."""
    t = time.perf_counter()
    steps = get_detector(detector, **(params or {})).detect(rec).steps_
    dt = time.perf_counter() - t
    ref = rec.reference
    true_s = ref.get("steps_t_s")
    ev = evaluate_steps(steps, None if true_s is None else np.asarray(true_s), tolerance_s=tolerance_s, n_true=ref.get("n_steps_true"))
    row = {
        "detector": detector,
        "recording": rec.name,
        "dataset": rec.meta.get("format"),
        "surface": rec.meta.get("surface", ""),
        "position": rec.meta.get("position", ""),
        "subject": rec.meta.get("subject", ""),
        "device": rec.meta.get("device", ""),
        "duration_s": rec.duration_s,
        "seconds": dt,
        **{k: v for k, v in ev.items() if k != "tolerance_s"},
    }
    if params:
        row["params"] = json.dumps(params, sort_keys=True)
    if detector == "ifsm" and rec.name == "acceleration_flat_holding_1" and len(steps) >= 10:
        row["first10_period_mad_s"] = float(np.abs(steps["period_s"].to_numpy()[:10] - PAPER_TABLE3_MANUAL_S).mean())
    return row


def summarise_oxford(table: pd.DataFrame) -> pd.DataFrame:
    """Mean count accuracy and F1 per detector, surface and position (plus an 'ALL' row per surface)."""
    ox = table[table["dataset"] == "oxford"]
    if ox.empty:
        return pd.DataFrame()
    # recordings with a true count only (no step times) have no F1 / timing columns
    ox = ox.assign(**{c: np.nan for c in ("f1", "timing_offset_s") if c not in ox.columns})
    g = ox.groupby(["detector", "surface", "position"]).agg(
        n_recordings=("recording", "size"),
        count_accuracy=("count_accuracy", "mean"),
        f1=("f1", "mean"),
        timing_offset_s=("timing_offset_s", "mean"),
    )
    # the 'ALL' row: the mean over positions (each position weighted equally) and the worst position
    allr = g.groupby(level=["detector", "surface"]).agg(
        n_recordings=("n_recordings", "sum"),
        count_accuracy=("count_accuracy", "mean"),
        f1=("f1", "mean"),
        timing_offset_s=("timing_offset_s", "mean"),
    )
    allr["worst_position_count_accuracy"] = g.groupby(level=["detector", "surface"])["count_accuracy"].min()
    allr["mean_over_recordings_count_accuracy"] = ox.groupby(["detector", "surface"])["count_accuracy"].mean()
    allr = allr.reset_index()
    allr["position"] = "ALL"
    return pd.concat([g.reset_index(), allr], ignore_index=True).sort_values(["detector", "surface", "position"]).reset_index(drop=True)


def _fmt(x, pct=False):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "-"
    return f"{100 * x:.2f}" if pct else f"{x:.3f}"


def _n_true(rec) -> int:
    ref = rec.reference
    n = ref.get("n_steps_true")
    if n:
        return int(n)
    return len(ref.get("steps_t_s", ()))


def _is_oxford(rec) -> bool:
    return rec.meta.get("format") == "oxford"


def holdout_folds(recordings, scheme: str) -> list[tuple[str, list[int], list[int]]]:
    """The folds of a held-out scheme over the Oxford recordings.

    Parameters
    ----------
    recordings : list of Recording
        All recordings of the run (non-Oxford ones are in no fold).
    scheme : {'user', 'position'}
        Leave one user (one carrying position) out at a time.

    Returns
    -------
    list of (held-out value, train indices, test indices)
        Indices into ``recordings``. Train: the hard-floor Oxford recordings
        whose user (position) is not the held-out one; test: every Oxford
        recording (hard and carpet) of the held-out user (position). No
        user (position) is ever in both.
    """
    if scheme not in HOLDOUT_KEYS:
        raise InputError(f"unknown held-out scheme {scheme!r}; valid: {', '.join(HOLDOUT_KEYS)}.")
    key = HOLDOUT_KEYS[scheme]
    ox = [i for i, r in enumerate(recordings) if _is_oxford(r)]
    folds = []
    for value in sorted({str(recordings[i].meta.get(key, "")) for i in ox}):
        test = [i for i in ox if str(recordings[i].meta.get(key, "")) == value]
        train = [i for i in ox if str(recordings[i].meta.get(key, "")) != value and recordings[i].meta.get("surface") == TUNING_SURFACE]
        folds.append((value, train, test))
    return folds


def tuned_evaluation(recordings, detector: str, schemes=("user",), *, tolerance_s: float = TOLERANCE_S) -> tuple[list, dict, dict]:
    """Evaluate ``detector`` with its ``param_grid`` setting chosen in sample and on the training folds of each scheme.

    Every grid point is run once per recording (cached) and shared by the
    folds; :meth:`~gaitml.steps.BaseStepDetector.tune` makes each choice from
    the training recordings' counts only.

    Returns
    -------
    in_sample_rows : list of dict
        One row per recording (IFSM included), the setting chosen on every
        hard-floor Oxford recording; ``detector`` is ``name + TUNED_SUFFIX``.
    heldout_rows : dict scheme -> list of dict
        One row per Oxford recording, the setting chosen without its user
        (position); column ``fold`` names the held-out value.
    chosen : dict
        ``{'in_sample': params, scheme: {held-out value: params}}``.
    """
    det = get_detector(detector)
    cache: dict = {}

    def row(params: dict, i: int) -> dict:
        key = (json.dumps(params, sort_keys=True), i)
        if key not in cache:
            cache[key] = evaluate_recording(recordings[i], detector, tolerance_s=tolerance_s, params=params)
        return cache[key]

    index = {id(r): i for i, r in enumerate(recordings)}

    def count(params, rec):
        return row(params, index[id(rec)])["n_detected"]

    def choose(idx):
        return det.tune([recordings[i] for i in idx], [_n_true(recordings[i]) for i in idx], count=count)

    name = detector + TUNED_SUFFIX
    pool = [i for i, r in enumerate(recordings) if _is_oxford(r) and r.meta.get("surface") == TUNING_SURFACE]
    chosen: dict = {"in_sample": choose(pool)}
    in_rows = [{**row(chosen["in_sample"], i), "detector": name} for i in range(len(recordings))]
    held: dict = {}
    for scheme in schemes:
        chosen[scheme] = {}
        held[scheme] = []
        for value, train, test in holdout_folds(recordings, scheme):
            params = choose(train)
            chosen[scheme][value] = params
            held[scheme].extend({**row(params, i), "detector": name, "fold": value} for i in test)
    return in_rows, held, chosen


def _merge_heldout(by_pos: pd.DataFrame, held_by_pos: dict[str, pd.DataFrame]) -> pd.DataFrame:
    """Add ``heldout_<scheme>_count_accuracy`` / ``_f1`` (and the worst position) columns to the in-sample summary."""
    out = by_pos.copy()
    keys = ["detector", "surface", "position"]
    for scheme, h in held_by_pos.items():
        if h.empty or out.empty:
            continue
        cols = {"count_accuracy": f"heldout_{scheme}_count_accuracy", "f1": f"heldout_{scheme}_f1"}
        if "worst_position_count_accuracy" in h:
            cols["worst_position_count_accuracy"] = f"heldout_{scheme}_worst_position_count_accuracy"
        out = out.merge(h[keys + list(cols)].rename(columns=cols), on=keys, how="left")
    return out


def _report(
    table: pd.DataFrame,
    by_pos: pd.DataFrame,
    tolerance_s: float = TOLERANCE_S,
    schemes=(),
    fitted=(),
    chosen: dict | None = None,
) -> str:
    lines = [
        "# Step detectors on the shared real recordings",
        "",
        f"Matching tolerance {tolerance_s} s. Count accuracy = 1 - |n_det - n_true| / n_true.",
        "",
    ]
    ifsm = table[table["dataset"] == "ifsm-xlsx"]
    if not ifsm.empty:
        lines += [
            "## IFSM flat-held phone data (paper 000)",
            "",
            "| detector | file 1 (284) | file 2 (319) | paper file 1 | paper file 2 |",
            "|---|---|---|---|---|",
        ]
        for det, g in ifsm.groupby("detector", sort=False):
            n = dict(zip(g["recording"], g["n_detected"], strict=True))
            p1 = PAPER_TABLE2["acceleration_flat_holding_1"].get(det, "")
            p2 = PAPER_TABLE2["acceleration_flat_holding_2"].get(det, "")
            lines.append(
                f"| {det} | {n.get('acceleration_flat_holding_1', '-')} | {n.get('acceleration_flat_holding_2', '-')} | {p1} | {p2} |"
            )
        mad = ifsm.get("first10_period_mad_s")
        if mad is not None and mad.notna().any():
            lines += [
                "",
                f"ifsm periods of the first 10 steps of file 1 vs the manual durations of Table 3: mean |diff| = {mad.dropna().iloc[0]:.3f} s",
            ]
        lines.append("")
    if not by_pos.empty:
        lines += ["## Oxford step counter, optimisation set (Salvi et al., CC BY 4.0)", ""]
        for surface, gs in by_pos.groupby("surface"):
            lines += [f"### {surface}: in sample", ""]
            positions = sorted(p for p in gs["position"].unique() if p != "ALL") + ["ALL"]
            lines += ["| detector | " + " | ".join(positions) + " | worst |", "|---" * (len(positions) + 2) + "|"]
            for det, gd in gs.groupby("detector", sort=False):
                acc = dict(zip(gd["position"], gd["count_accuracy"], strict=True))
                f1 = dict(zip(gd["position"], gd["f1"], strict=True))
                worst = gd.loc[gd["position"] == "ALL", "worst_position_count_accuracy"]
                cells = [f"{_fmt(acc.get(p), True)} / {_fmt(f1.get(p))}" for p in positions]
                lines.append(f"| {det} | " + " | ".join(cells) + f" | {_fmt(worst.iloc[0] if len(worst) else None, True)} |")
            lines += ["", "cells: mean count accuracy (%) / mean F1; ALL = mean over positions.", ""]
            for scheme in schemes:
                col = f"heldout_{scheme}_count_accuracy"
                if col not in gs:
                    continue
                lines += [f"### {surface}: in sample vs leave-one-{scheme}-out", ""]
                lines += ["| detector | fitted | " + " | ".join(positions) + " | worst |", "|---" * (len(positions) + 3) + "|"]
                for det, gd in gs.groupby("detector", sort=False):
                    acc = dict(zip(gd["position"], gd["count_accuracy"], strict=True))
                    out = dict(zip(gd["position"], gd[col], strict=True))
                    allr = gd[gd["position"] == "ALL"]
                    w_in = allr["worst_position_count_accuracy"].iloc[0] if len(allr) else None
                    wcol = f"heldout_{scheme}_worst_position_count_accuracy"
                    w_out = allr[wcol].iloc[0] if len(allr) and wcol in allr else None
                    cells = [f"{_fmt(acc.get(p), True)} / {_fmt(out.get(p), True)}" for p in positions]
                    tag = "yes" if det in fitted else "no"
                    lines.append(f"| {det} | {tag} | " + " | ".join(cells) + f" | {_fmt(w_in, True)} / {_fmt(w_out, True)} |")
                lines += [
                    "",
                    f"cells: mean count accuracy (%) in sample / held out (leave-one-{scheme}-out). A row not fitted has no "
                    "setting chosen on these recordings, so its two figures agree; a fitted row chose its setting on every "
                    f"hard-floor recording (in sample) or on the other {scheme}s' hard-floor recordings only (held out).",
                    "",
                ]
    if chosen:
        lines += ["## Settings chosen by the tuned detectors", ""]
        for det, ch in chosen.items():
            lines.append(f"- {det}: in sample {json.dumps(ch['in_sample'], sort_keys=True)}")
            for scheme in schemes:
                for value, params in ch.get(scheme, {}).items():
                    lines.append(f"  - without {scheme} {value}: {json.dumps(params, sort_keys=True)}")
        lines.append("")
    return "\n".join(lines) + "\n"


DATA_SETS = STEP_DATA_SETS


def load_recordings(data_dir: Path, sets=DATA_SETS) -> list:
    """The IFSM files and the Oxford optimisation folders under ``data_dir`` (missing sets are skipped)."""
    recs = []
    ifsm_dir = data_dir / "ifsm-flat-phone"
    if "ifsm-flat-phone" in sets and ifsm_dir.is_dir():
        recs.extend(read_recording(f) for f in sorted(ifsm_dir.glob("*.xlsx")))
    ox = data_dir / "oxford-step-counter" / "optimisation"
    if "oxford-step-counter" in sets and ox.is_dir():
        recs.extend(read_recording(d) for d in list_oxford_folders(ox))
    return recs


def _schemes(holdout) -> tuple[str, ...]:
    items = (holdout,) if isinstance(holdout, str) else tuple(holdout)
    bad = [h for h in items if h not in (*HOLDOUT_KEYS, "none")]
    if bad:
        raise InputError(f"unknown held-out scheme {bad[0]!r}; valid: {', '.join((*HOLDOUT_KEYS, 'none'))}.")
    return tuple(h for h in items if h != "none")


def run_steps_real(
    out_dir: str | Path,
    *,
    data_dir: str | Path,
    detectors=None,
    recordings=None,
    progress=None,
    tolerance_s: float = TOLERANCE_S,
    sets=DATA_SETS,
    holdout="user",
    tune: bool = True,
) -> dict:
    """Evaluate ``detectors`` (default: every registered one) on the shared step recordings and write the tables to ``out_dir``.

    Parameters
    ----------
    holdout : str or sequence of str, default 'user'
        Held-out schemes: ``'user'``, ``'position'`` (leave one out on the
        Oxford recordings), or ``'none'``.
    tune : bool, default True
        Also run each detector that declares a ``param_grid`` as
        ``"<name> (tuned)"`` (:func:`tuned_evaluation`).
    """
    detectors = detector_names() if detectors is None else list(detectors)
    schemes = _schemes(holdout)
    recs = recordings if recordings is not None else load_recordings(Path(data_dir), sets)
    rows = []
    held_rows: dict[str, list] = {s: [] for s in schemes}
    chosen: dict = {}
    for det in detectors:
        det_rows = [evaluate_recording(rec, det, tolerance_s=tolerance_s) for rec in recs]
        rows.extend(det_rows)
        for scheme in schemes:
            folds = holdout_folds(recs, scheme)
            fold_of = {i: value for value, _, test in folds for i in test}
            # used as it is: no setting fitted, so the held-out row is the in-sample one
            held_rows[scheme].extend({**r, "fold": fold_of[i]} for i, r in enumerate(det_rows) if i in fold_of)
        if tune and DETECTORS[det].param_grid and any(_is_oxford(r) for r in recs):
            in_rows, held, chosen[det + TUNED_SUFFIX] = tuned_evaluation(recs, det, schemes, tolerance_s=tolerance_s)
            rows.extend(in_rows)
            for scheme in schemes:
                held_rows[scheme].extend(held[scheme])
        if progress:
            progress(f"{det}: done")
    table = pd.DataFrame(rows)
    by_pos = summarise_oxford(table)
    held_tables = {s: pd.DataFrame(v) for s, v in held_rows.items()}
    by_pos = _merge_heldout(by_pos, {s: summarise_oxford(t) for s, t in held_tables.items() if not t.empty})
    fitted = tuple(chosen)
    summary: dict = {"tolerance_s": tolerance_s, "holdout": list(schemes), "fitted": list(fitted), "ifsm": {}, "oxford": {}}
    for _, r in table[table["dataset"] == "ifsm-xlsx"].iterrows():
        summary["ifsm"].setdefault(r["detector"], {})[r["recording"]] = {
            "n_detected": int(r["n_detected"]),
            "n_true": int(r["n_true"]),
            "count_accuracy": float(r["count_accuracy"]),
        }
    if "first10_period_mad_s" in table:
        v = table["first10_period_mad_s"].dropna()
        if len(v):
            summary["ifsm_first10_period_mad_s"] = float(v.iloc[0])
    if not by_pos.empty:
        for _, r in by_pos.iterrows():
            d = summary["oxford"].setdefault(r["detector"], {}).setdefault(r["surface"], {})
            if r["position"] == "ALL":
                d.update(
                    mean_count_accuracy=float(r["count_accuracy"]),
                    mean_f1=float(r["f1"]),
                    worst_position_count_accuracy=float(r["worst_position_count_accuracy"]),
                )
                for scheme in schemes:
                    col = f"heldout_{scheme}_count_accuracy"
                    if col in r and pd.notna(r[col]):
                        d[f"heldout_{scheme}_mean_count_accuracy"] = float(r[col])
                        d[f"heldout_{scheme}_worst_position_count_accuracy"] = float(r[f"heldout_{scheme}_worst_position_count_accuracy"])
            else:
                pos = d.setdefault("by_position", {}).setdefault(r["position"], {"count_accuracy": float(r["count_accuracy"])})
                for scheme in schemes:
                    col = f"heldout_{scheme}_count_accuracy"
                    if col in r and pd.notna(r[col]):
                        pos[f"heldout_{scheme}_count_accuracy"] = float(r[col])
    if chosen:
        summary["chosen"] = chosen
    out = Path(out_dir)
    with atomic_dir(out) as tmp:
        tmp = Path(tmp)
        table.to_csv(tmp / "per_recording.csv", index=False)
        by_pos.to_csv(tmp / "oxford_by_position.csv", index=False)
        if schemes:
            held = [t.assign(holdout=s) for s, t in held_tables.items() if not t.empty]
            (pd.concat(held, ignore_index=True) if held else pd.DataFrame()).to_csv(tmp / "heldout_per_recording.csv", index=False)
        (tmp / "summary.json").write_text(json.dumps(summary, indent=2))
        (tmp / "report.md").write_text(_report(table, by_pos, tolerance_s, schemes, fitted, chosen))
    return summary


def evaluate_steps_config(cfg: ExperimentConfig, *, out_dir: str | Path | None = None, progress=None) -> dict:
    """Run a ``task = "steps"`` config and write its run folder.

    Parameters
    ----------
    cfg : ExperimentConfig
        A validated config with ``task = "steps"``.
    out_dir : path, optional
        The run folder (replaced atomically); default ``runs/<name>/<UTC timestamp>/``.
    progress : bool or callable, optional
        Called with one line per finished detector (``True``: printed on stderr).

    Returns
    -------
    dict
        The summary written to ``summary.json`` plus ``name``, ``task`` and ``run_dir``.
    """
    from gaitml.pipeline.runner import default_run_dir

    out = Path(out_dir) if out_dir is not None else default_run_dir(cfg)
    if progress is True:
        progress = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731
    s = cfg["steps"]
    e = cfg["evaluation"]
    summary = run_steps_real(
        out,
        data_dir=cfg.data_path,
        detectors=s["detectors"],
        tolerance_s=s["tolerance_s"],
        sets=cfg["data"]["sets"],
        progress=progress,
        holdout=e["holdout"],
        tune=e["tune"],
    )
    return {"name": cfg.name, "task": cfg.task, **summary, "run_dir": str(out)}
