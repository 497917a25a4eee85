"""A folder of phone recordings with a manifest is a data set (config ``data.source = "folder"``).

A researcher records each session with a phone app, writes down when each motion
mode started (an intervals file), and lists the recordings in ``manifest.csv`` in the
same folder. ``gaitml evaluate`` / ``gaitml train`` then read the folder directly.

manifest.csv
------------
One row per recording; a header row; paths relative to the folder::

    file,subject,intervals,position
    alice-1,alice,alice-1.intervals.csv,hand
    bob-1.csv,bob,bob-1.txt,hand
    carol.zip,carol,,pocket

Columns:

``file`` (required)
    A recording in any format gaitml reads (:data:`gaitml.io.FORMATS`): a
    gaitml-csv, a phyphox export (folder, zip or CSV), a Sensor Logger export
    (folder or zip), an Oxford folder, or any CSV with a ``columns`` map.
``subject`` (required)
    Who walked; the usual cross-validation group (``data.group = "subject"``).
``session`` (optional)
    Defaults to the file name without its extension.
``intervals`` (optional)
    An intervals file for this recording (CSV ``start_s,end_s,label`` or an
    Audacity label track, seconds from the recording's first sample). The
    recording is labelled through :class:`gaitml.labels.IntervalLabeller` with
    the config's ``[data.labelling]`` (``snap`` = steps | strides | none,
    ``detector``, ``max_snap_s``); samples outside every interval are labelled
    ``unlabelled`` and their windows are left out unless ``data.labels`` lists
    that label. Without an intervals file the recording's own per-sample
    ``label`` column is used (a gaitml-csv written by ``gaitml label``), or a
    manifest column named by ``data.label`` (one label per recording, e.g.
    ``position``).
``format`` (optional)
    A format name of :data:`gaitml.io.FORMATS` when detection from the content
    is not wanted (empty: detect).
``columns``, ``time_unit``, ``acc_unit``, ``gyr_unit`` (optional)
    For ``format = columns-csv``: the column map (``"t=time,acc_x=ax,..."``, quote
    it: it holds commas) and units, as ``gaitml info --columns``.
any other column (e.g. ``position``)
    Copied into the recording's meta: usable as ``data.label``, ``data.group``
    or in ``data.where``.

Errors name the manifest line: a missing column, a file or intervals file that
does not exist, a recording without labels.

Data set folders without a manifest
-----------------------------------
A folder in a layout the readers know is a source as it is (``data.path`` and no
manifest; :func:`gaitml.io.read_dataset`): a gaitml-csv set, an Oxford step
counter root, and the tyrex attitude benchmark (``tyrex-attitude/`` with
``android/``, ``ios/`` and ``qualisys/``, or either phone folder).
:func:`tyrex_manifest` lists the tyrex recordings with the columns every one of
them carries in its meta: ``subject`` (the person), ``phone``, ``platform``,
``motion``, ``position``, ``mode`` (``walk`` | ``run``), ``disturbance`` and
``truth`` (its motion-capture file), so that a config may use, e.g.,
``label = "mode"``, ``label = "position"``, ``group = "subject"`` or
``where = { motion = "Texting" }``. A tyrex recording with a sensor gap too long
to bridge is read as its stretches between the gaps (``meta['segment']``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import ConfigError, InputError

__all__ = ["MANIFEST_NAME", "MANIFEST_COLUMNS", "read_manifest_folder", "tyrex_manifest"]

#: The manifest's file name inside the data folder (unless ``data.manifest`` names another).
MANIFEST_NAME = "manifest.csv"
#: Columns the manifest reader interprets; every other column goes into the recording's meta.
MANIFEST_COLUMNS = ("file", "subject", "session", "intervals", "format", "columns", "time_unit", "acc_unit", "gyr_unit")
_READ_OPTIONS = ("columns", "time_unit", "acc_unit", "gyr_unit")


def _cell(v) -> str:
    """A manifest cell as a stripped string ('' for an empty cell)."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    return str(v).strip()


def _meta_value(v):
    if hasattr(v, "item"):
        v = v.item()
    if isinstance(v, float) and math.isnan(v):
        return ""
    return v


def read_manifest_folder(folder: Path, manifest: Path, *, label: str = "label", labelling: dict | None = None) -> tuple[list, list[str]]:
    """Read every recording listed in ``manifest`` and label it.

    Parameters
    ----------
    folder : the data folder (paths in the manifest are relative to it).
    manifest : the manifest CSV.
    label : ``data.label``: ``'label'`` (per-sample labels, from the recording or its
        intervals file) or a manifest column (one label per recording).
    labelling : ``[data.labelling]`` of the config: ``snap``, ``detector``, ``max_snap_s``.

    Returns
    -------
    (recordings, notes)
        Recordings at their own rate with ``meta`` from the manifest
        (``subject``, ``session``, ``file``, other columns) and labels set; notes for
        the run report.

    Raises
    ------
    ConfigError
        The manifest is unreadable or lacks ``file``/``subject``; a row names a
        missing file or intervals file, an unknown format, or a recording without
        labels; a recording cannot be read (the reader's message, with the line).
    """
    from gaitml.io import FORMATS, read_recording
    from gaitml.labels import label_recording

    lab_cfg = dict(labelling or {})
    try:
        man = pd.read_csv(manifest, skipinitialspace=True, dtype=str, keep_default_na=False)
    except (OSError, UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise ConfigError(
            f"cannot read the manifest {manifest} ({str(exc).splitlines()[0]}); write a CSV with a header file,subject,..."
        ) from None
    man.columns = [str(c).strip() for c in man.columns]
    numeric = {c: pd.to_numeric(man[c].where(man[c].str.strip() != ""), errors="coerce") for c in man.columns if c not in MANIFEST_COLUMNS}
    numeric = {c: v for c, v in numeric.items() if v.notna().any() and (v.notna() == (man[c].str.strip() != "")).all()}
    for c in ("file", "subject"):
        if c not in man.columns:
            raise ConfigError(
                f"the manifest {manifest.name} has no {c!r} column (columns: {', '.join(man.columns)}); a manifest needs file and subject."
            )
    if len(man) == 0:
        raise ConfigError(f"the manifest {manifest.name} lists no recordings; add one row per recording (file,subject,...).")
    recs, n_intervals, n_unlabelled = [], 0, 0
    for i, row in enumerate(man.to_dict("records")):
        line = i + 2
        where = f"{manifest.name} line {line}"
        fname = _cell(row["file"])
        if not fname:
            raise ConfigError(f"{where} has an empty file; name the recording or delete the row.")
        f = folder / fname
        if not f.exists():
            raise ConfigError(f"{where} names {fname}, which does not exist in {folder}; add the recording or remove its row.")
        subject = _cell(row["subject"])
        if not subject:
            raise ConfigError(f"{where} ({fname}) has an empty subject; name who walked (subjects are the cross-validation groups).")
        fmt = _cell(row.get("format")) or None
        if fmt is not None and fmt not in FORMATS:
            raise ConfigError(f"{where} ({fname}) has format {fmt!r}; use one of {', '.join(FORMATS)} or leave it empty to detect it.")
        kwargs = {k: _cell(row.get(k)) for k in _READ_OPTIONS if _cell(row.get(k))}
        try:
            rec = read_recording(f, format=fmt, **kwargs)
        except InputError as exc:
            raise ConfigError(f"{where} ({fname}): {str(exc).rstrip('.')}.") from None
        meta = {k: _meta_value(numeric[k].iloc[i] if k in numeric else v) for k, v in row.items() if k not in MANIFEST_COLUMNS}
        meta.update(subject=subject, session=_cell(row.get("session")) or Path(fname).name.split(".")[0], file=fname)
        rec = rec.replace(meta={**rec.meta, **meta}, check_units=False)
        iv_name = _cell(row.get("intervals"))
        if iv_name:
            iv = folder / iv_name
            if not iv.is_file():
                raise ConfigError(
                    f"{where} ({fname}) names the intervals file {iv_name}, which does not exist in {folder}; add it or clear the cell."
                )
            try:
                lab = label_recording(rec, iv, **lab_cfg)
            except InputError as exc:
                raise ConfigError(f"{where} ({fname}) intervals {iv_name}: {str(exc).rstrip('.')}.") from None
            rec = lab.recording_
            n_intervals += 1
            n_unlabelled += int(lab.report_["n_unlabelled_samples"])
        elif label == "label" and rec.labels is None:
            raise ConfigError(
                f"{where}: recording {fname} has no labels; give it an intervals file (manifest column 'intervals'), "
                "a per-sample label column (gaitml label writes one), or set data.label to a manifest column."
            )
        elif label != "label" and label in man.columns and not _cell(row.get(label)):
            raise ConfigError(f"{where}: recording {fname} has no {label!r} (data.label); fill that manifest cell.")
        recs.append(rec)
    fmts = sorted({str(r.meta.get("format") or r.meta.get("source") or "?") for r in recs})
    notes = [f"manifest {manifest.name}: {len(recs)} recordings ({', '.join(fmts)})"]
    if n_intervals:
        snap = lab_cfg.get("snap", "steps")
        det = lab_cfg.get("detector") or "default"
        notes.append(
            f"labels of {n_intervals} recordings from intervals files (gaitml.labels, snap {snap}, detector {det}, "
            f"max_snap_s {lab_cfg.get('max_snap_s', 0.5)}, rule {lab_cfg.get('rule', 'change')}); {n_unlabelled} samples outside every interval are 'unlabelled'"
        )
    return recs, notes


def unlabelled_share(recs) -> float:
    """Share of samples labelled :data:`gaitml.labels.UNLABELLED` (0 without labels)."""
    from gaitml.labels import UNLABELLED

    n = sum(r.n_samples for r in recs if r.labels is not None)
    k = sum(int(np.sum(np.asarray(r.labels).astype(str) == UNLABELLED)) for r in recs if r.labels is not None)
    return k / n if n else 0.0


#: Columns of :func:`tyrex_manifest`.
TYREX_MANIFEST_COLUMNS = ("file", "subject", "phone", "platform", "motion", "position", "mode", "disturbance", "take", "truth")


def tyrex_manifest(folder: str | Path) -> pd.DataFrame:
    """Every recording of a tyrex attitude folder, one row each, without reading the sensor logs.

    Parameters
    ----------
    folder : the data set root (``tyrex-attitude/``), ``android/`` or ``ios/``, or one recording folder.

    Returns
    -------
    DataFrame
        Columns :data:`TYREX_MANIFEST_COLUMNS`: ``file`` (the recording folder,
        relative to ``folder``), ``subject`` (the person), ``phone``, ``platform``
        (android | ios), ``motion`` (as spelt in the source, e.g. ``FrontPocket``),
        ``position`` (:data:`gaitml.io.tyrex.TYREX_POSITIONS`), ``mode`` (walk | run),
        ``disturbance`` (Dist | NoDist), ``take`` (``old`` for the extra take
        without motion capture, else empty) and ``truth`` (the motion-capture
        file relative to ``folder``, empty when there is none).

    Raises
    ------
    InputError
        ``folder`` holds no tyrex recording.
    """
    from gaitml.io.tyrex import _platform, list_tyrex_folders, parse_tyrex_name, tyrex_truth_path

    root = Path(folder)
    dirs = list_tyrex_folders(root)
    if not dirs:
        raise InputError(
            f"{root} holds no tyrex recording folders (<Person>_<Phone>_<Dist|NoDist>_<Motion>/ with accelerometer.txt.gz); "
            "pass the tyrex-attitude folder or its android/ or ios/ folder."
        )
    rows = []
    for d in dirs:
        info = parse_tyrex_name(d.name) or {}
        truth = tyrex_truth_path(d)
        rows.append(
            {
                "file": str(d.relative_to(root)) if d != root else ".",
                "subject": info.get("person", d.name),
                "phone": info.get("phone", ""),
                "platform": _platform(d),
                "motion": info.get("motion", ""),
                "position": info.get("position", ""),
                "mode": info.get("mode", ""),
                "disturbance": info.get("disturbance", ""),
                "take": info.get("take", ""),
                "truth": "" if truth is None else str(truth.relative_to(root) if truth.is_relative_to(root) else truth),
            }
        )
    return pd.DataFrame(rows, columns=list(TYREX_MANIFEST_COLUMNS))
