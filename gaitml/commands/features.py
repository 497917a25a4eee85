"""`gaitml features INPUT [--window-s S] [--overlap F] [--subset NAME] [--frame phone|gravity] [--out FILE]`.

Writes the feature table (window columns ``start, end, t_start_s, t_end_s`` and,
when the recording is labelled, ``label, label_fraction``, then the features in
catalogue order) as CSV atomically, or prints a summary to stdout without ``--out``.
Every window is kept (``min_label_fraction = 0``).
"""

from __future__ import annotations

import argparse

import pandas as pd

from gaitml.commands._args import add_input_options, choices, feature_frames, feature_sets
from gaitml.commands._util import is_large_input, load_input, log, long_read_kwargs

#: The command's one-line description in ``gaitml --help``.
HELP = "extract windowed features"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``gaitml features`` on its parser ``p``."""
    p.add_argument("input", metavar="INPUT")
    p.add_argument("--window-s", type=float, default=1.5)
    p.add_argument("--overlap", type=float, default=0.5)
    p.add_argument("--subset", **choices("features", "--subset", feature_sets), default="all52", help="%(choices)s (default %(default)s)")
    p.add_argument(
        "--frame",
        **choices("features", "--frame", feature_frames),
        default="phone",
        help="axes of the x/y/z features: phone (the phone's own, paper 003) or gravity (per-window up/forward/right, "
        "independent of the phone's orientation) (default %(default)s)",
    )
    p.add_argument("--out", metavar="FILE", help="write the feature table as CSV")
    add_input_options(p)


def feature_table(recording, *, window_s: float = 1.5, overlap: float = 0.5, subset: str = "all52", frame: str = "phone") -> pd.DataFrame:
    """Window columns followed by the feature columns (what ``--out`` writes); ``frame``: see :func:`gaitml.features.extract_features`."""
    from gaitml.features import extract_features, make_windows, resolve_subset
    from gaitml.features._catalogue import uses_gyro

    key = resolve_subset(subset)
    if uses_gyro(key):
        recording.require_gyr(f"feature subset {key!r}")
    windows = make_windows(recording, window_s, overlap, min_label_fraction=0.0)
    feats = extract_features(recording, windows, subset=key, frame=frame)
    table = pd.concat([windows, feats], axis=1)
    table.attrs.update(windows.attrs, subset=key, frame=frame)
    return table


def summary_text(table: pd.DataFrame, recording) -> str:
    """A readable summary: windows, labels and per-feature mean / std / min / max."""
    from gaitml.features import CATALOGUE, GYRO_CATALOGUE
    from gaitml.features._catalogue import FORWARD_CATALOGUE, FORWARD_FACE_CATALOGUE

    codes = {s.name: s.code for s in CATALOGUE + GYRO_CATALOGUE + FORWARD_CATALOGUE + FORWARD_FACE_CATALOGUE}
    a = table.attrs
    lines = [
        f"recording: {recording.name} ({recording.n_samples} samples, {recording.sampling_rate_hz:g} Hz, {recording.duration_s:.2f} s)",
        f"windows: {len(table)} of {a['length_samples']} samples ({a['length_s']:g} s), hop {a['hop_samples']} samples (overlap {a['overlap']:g})",
        f"subset: {a['subset']}, frame: {a.get('frame', 'phone')}",
    ]
    if "label" in table:
        counts = table["label"].value_counts().sort_index()
        lines.append("labels (window majority): " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    feat_cols = [c for c in table.columns if "__" in c]
    lines.append(f"{'F':>4}  {'feature':<20} {'mean':>12} {'std':>12} {'min':>12} {'max':>12}")
    for c in feat_cols:
        col = table[c]
        lines.append(f"{codes[c]:>4}  {c:<20} {col.mean():12.5g} {col.std(ddof=0):12.5g} {col.min():12.5g} {col.max():12.5g}")
    return "\n".join(lines)


def run(args) -> int:
    from gaitml.io import write_csv

    if is_large_input(args):
        return _run_long(args)
    recording = load_input(args)
    table = feature_table(
        recording, window_s=args.window_s, overlap=args.overlap, subset=args.subset, frame=getattr(args, "frame", "phone")
    )
    if args.out:
        write_csv(args.out, table)
        log(f"wrote {len(table)} windows x {sum('__' in c for c in table.columns)} features to {args.out}")
    else:
        print(summary_text(table, recording))
    return 0


def _run_long(args) -> int:
    """A long input: features chunk by chunk, appended to the output file (bounded memory)."""
    from gaitml.chunked_run import long_features
    from gaitml.features import resolve_subset
    from gaitml.io import atomic_path

    key = resolve_subset(args.subset)

    def run(on_block) -> None:
        long_features(
            args.input,
            length_s=args.window_s,
            overlap=args.overlap,
            subset=key,
            frame=getattr(args, "frame", "phone"),
            on_block=on_block,
            **long_read_kwargs(args),
        )

    count = [0]
    if not args.out:
        run(lambda b: count.__setitem__(0, count[0] + len(b)))
        print(f"{args.input}: {count[0]} windows of {args.window_s:g} s ({key}); the input is long: pass --out FILE to write the table")
        return 0
    with atomic_path(args.out) as tmp:
        with open(tmp, "w", newline="") as fh:

            def write_block(block: pd.DataFrame) -> None:
                block.to_csv(fh, header=count[0] == 0, index=False)
                count[0] += len(block)

            run(write_block)
    log(f"wrote {count[0]} windows ({key}, processed in chunks) to {args.out}")
    return 0
