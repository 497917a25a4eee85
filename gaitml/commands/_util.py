"""Small helpers shared by the command handlers."""

from __future__ import annotations

import json
import sys
from typing import Any


def load_input(args) -> Any:
    """Read ``args.input`` with the common input options; print the reader's warnings (one stderr line each)."""
    from gaitml.io import read_recording

    rec = read_recording(args.input, **read_kwargs(args))
    for warning in rec.meta.get("warnings", []):
        log(f"gaitml: warning: {warning}")
    return rec


def emit_json(obj: Any) -> None:
    """Print exactly one JSON object on stdout."""
    from gaitml.io._atomic import _json_default

    sys.stdout.write(json.dumps(obj, default=_json_default, allow_nan=False) + "\n")
    sys.stdout.flush()


def log(msg: str) -> None:
    """Progress and notes go to stderr, never stdout."""
    print(msg, file=sys.stderr, flush=True)


def is_large_input(args) -> bool:
    """Whether ``args.input`` is long enough to be processed in chunks (bounded memory)."""
    from gaitml.errors import GaitmlError
    from gaitml.io.chunked import LARGE_INPUT_SAMPLES, estimate_samples

    try:
        return estimate_samples(args.input) > LARGE_INPUT_SAMPLES
    except (GaitmlError, OSError):
        return False


def long_read_kwargs(args) -> dict:
    """:func:`read_kwargs` for the chunked path, with the first pass over the file made here so that
    its warnings (the same as a file read whole) are printed once, one stderr line each.

    A gaitml-csv's first pass is its scan (``kw['scan']``); any other format is read whole anyway
    (:func:`gaitml.io.chunked.iter_chunks`), so it is read here, once (``kw['recording']``, which the
    chunked functions slice instead of reading the file again)."""
    from gaitml.io.chunked import scan_input

    kw = read_kwargs(args)
    scan = scan_input(args.input, **kw)
    if scan is None:
        kw["recording"] = load_input(args)  # prints the reader's warnings
        return kw
    for warning in scan.warnings:
        log(f"gaitml: warning: {warning}")
    kw["scan"] = scan
    return kw


def read_kwargs(args) -> dict:
    """The common input options as keyword arguments of the readers."""
    return {
        "format": getattr(args, "format", None),
        "sensor": getattr(args, "sensor", "left"),
        "sampling_rate_hz": getattr(args, "sampling_rate_hz", None),
        "acc_unit": getattr(args, "acc_unit", "m/s^2"),
        "gyr_unit": getattr(args, "gyr_unit", "rad/s"),
        "columns": getattr(args, "columns", None),
        "time_unit": getattr(args, "time_unit", "s"),
    }


def rate_check_note(record: dict | None) -> str | None:
    """One stderr warning line when the recording (or a stretch of it) was made below the step detector's rate floor
    (:func:`gaitml.steps.rate_record`, :mod:`gaitml.steps._rate`); returns the line (None: nothing printed)."""
    from gaitml.steps import rate_warning

    line = rate_warning(record)
    if line:
        log(f"gaitml: warning: {line}")
    return line


def rate_check_summary(record: dict | None) -> str | None:
    """The summary line (stdout) of a rate check whose warning :func:`rate_check_note` prints, else None: every
    step flagged when the recording was made below the detector's rate floor, else how many of its steps lie in
    the stretches recorded below it (named even when none does: the count there may be short)."""
    from gaitml.steps import rate_warning

    if rate_warning(record) is None:
        return None
    if record["below"]:
        return f"rate: {record['reason'][len('rate: ') :]}; every step flagged (rate_reason)"
    stretches = record["stretches_below"]
    n_below = record["n_steps_below"]
    return (
        f"rate: {n_below} of {record['n_steps']} steps in {len(stretches)} stretch(es) recorded at down to "
        f"{min(s[2] for s in stretches):.3g} Hz, below the {record['floor_hz']:g} Hz down to which {record['detector']}'s "
        "step count holds" + (" (rate_reason)" if n_below else "")
    )


def gait_check_note(account: dict | None, detector: str) -> None:
    """One stderr note when the step detector left out steps in bouts without gait evidence
    (``steps.attrs['gait_check']``, :func:`gaitml.steps._gait_evidence.gait_check`), or when it could not test them
    (no gyroscope); nothing otherwise."""
    if account and not account.get("tested", True):
        log(f"gaitml: note: the gait check of {detector} did not run (the recording has no gyroscope): steps are counted without it")
        return
    if not account or not account.get("n_steps_rejected"):
        return
    log(
        f"gaitml: note: {account['n_steps_rejected']} steps in {account['n_bouts_rejected']} of {account['n_bouts']} bouts "
        f"without gait evidence left out by {detector} (the phone rotates at the step rate as a gesturing hand does, not as "
        "a walker's); a paper detector (e.g. --detector single-peak) keeps them"
    )
