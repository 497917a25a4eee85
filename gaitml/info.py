"""Describe what was read: the data behind ``gaitml info``."""

from __future__ import annotations

import os
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from gaitml.io import detect_format, list_dataset, read_dataset, read_gaitmap_table, read_recording
from gaitml.recording import Recording

__all__ = ["describe_recording", "describe_path"]

#: Metadata shown when present (phone-app readers add platform, acc_source, frame and clock_merge;
#: ``warnings`` holds the readers' doubts, e.g. an uncertain gyro unit).
_META_KEYS = (
    "subject",
    "session",
    "device",
    "position",
    "surface",
    "sensor",
    "converted",
    "ignored_columns",
    "platform",
    "acc_source",
    "frame",
    "clock_merge",
    "getsensordata",
    "other_sensors",
    "other_sensors_note",
    "landmarks",
    "sample_and_hold",
    "dialect",
    "warnings",
)


def describe_recording(rec: Recording) -> dict[str, Any]:
    """A JSON-ready summary of one recording: sizes, rates, channels, labels, reference events."""
    meta = rec.meta
    out: dict[str, Any] = {
        "id": rec.name,
        "format": meta.get("format"),
        "source": meta.get("source"),
        "n_samples": rec.n_samples,
        "duration_s": round(rec.duration_s, 6),
        "sampling_rate_hz": rec.sampling_rate_hz,
        "original_rate_hz": meta.get("original_rate_hz", rec.sampling_rate_hz),
        "resampled": bool(meta.get("resampled", False)),
        "channels": ["acc_x", "acc_y", "acc_z"] + (["gyr_x", "gyr_y", "gyr_z"] if rec.has_gyr else []),
    }
    if meta.get("resampled"):
        out["n_original_samples"] = meta.get("n_original_samples")
        out["jitter_s"] = meta.get("jitter_s")
        out["gaps"] = meta.get("gaps", [])
    for key in _META_KEYS:
        if key in meta:
            out[key] = meta[key]
    if rec.labels is not None:
        out["labels"] = dict(sorted(Counter(rec.labels.tolist()).items()))
    ref: dict[str, Any] = {}
    for key, val in rec.reference.items():
        if isinstance(val, pd.DataFrame):
            ref[key] = int(len(val))
        elif isinstance(val, np.ndarray):
            ref[key] = int(len(val))
        else:
            ref[key] = val
    if "steps_t_s" in rec.reference and "n_steps_true" not in ref:
        ref["n_steps_true"] = int(len(rec.reference["steps_t_s"]))
    out["reference"] = ref
    return out


def _is_phone_manifest_folder(p: Path) -> bool:
    """A folder whose manifest lists recordings of any format (``format``/``intervals`` columns, or no ``session``)."""
    manifest = p / "manifest.csv"
    if not (p.is_dir() and manifest.is_file()):
        return False
    try:
        header = {c.strip() for c in manifest.open(encoding="utf-8", errors="replace").readline().strip().split(",")}
    except OSError:
        return False
    return "file" in header and ("format" in header or "intervals" in header or "session" not in header)


def describe_path(path: str | os.PathLike, **read_kwargs: Any) -> dict[str, Any]:
    """Summarise a recording, a data set folder or a gaitmap annotation table."""
    p = Path(path)
    if read_kwargs.get("columns") is not None or read_kwargs.get("format") not in (None, "gaitml-csv"):  # one recording, read as told
        return {"kind": "recording", **describe_recording(read_recording(p, **read_kwargs))}
    fmt = detect_format(p)
    if fmt == "gaitmap-table":
        return {"kind": "table", "source": str(p), **read_gaitmap_table(p)}
    if _is_phone_manifest_folder(p):  # a folder of app exports with a manifest (data.source = "folder")
        from gaitml.pipeline.folder_source import read_manifest_folder

        recs, _ = read_manifest_folder(p, p / "manifest.csv", label="")
    else:
        entries = list_dataset(p)
        if len(entries) == 1 and entries[0][1] != "gaitml-folder":
            return {"kind": "recording", **describe_recording(read_recording(p, **read_kwargs))}
        recs = read_dataset(p, **{k: v for k, v in read_kwargs.items() if k != "format"})
    items = [describe_recording(r) for r in recs]
    total_steps = sum(int(i["reference"].get("n_steps_true", 0)) for i in items)
    out = {
        "kind": "dataset",
        "source": str(p),
        "format": fmt,
        "n_recordings": len(items),
        "n_samples": int(sum(i["n_samples"] for i in items)),
        "duration_s": round(sum(i["duration_s"] for i in items), 3),
        "formats": dict(Counter(i["format"] for i in items)),
        "recordings": items,
    }
    if any("n_steps_true" in i["reference"] for i in items):
        out["n_steps_true"] = total_steps
    labels: Counter = Counter()
    for i in items:
        labels.update(i.get("labels", {}))
    if labels:
        out["labels"] = dict(sorted(labels.items()))
    return out


def format_text(desc: dict[str, Any]) -> str:
    """Human-readable text for :func:`describe_path`'s result."""
    if desc["kind"] == "table":
        rest = {k: v for k, v in desc.items() if k not in ("kind", "source")}
        return f"{desc['source']}: {desc['format']} " + ", ".join(f"{k}={v}" for k, v in rest.items())
    if desc["kind"] == "recording":
        return _recording_text(desc)
    lines = [
        f"data set {desc['source']} ({desc['format']}): {desc['n_recordings']} recordings, "
        f"{desc['n_samples']} samples, {desc['duration_s']:.1f} s"
        + (f", {desc['n_steps_true']} true steps" if "n_steps_true" in desc else "")
    ]
    if "labels" in desc:
        lines.append("labels (samples): " + ", ".join(f"{k} {v}" for k, v in desc["labels"].items()))
    lines.append(f"{'id':40s} {'samples':>8s} {'rate_hz':>9s} {'orig_hz':>9s} {'dur_s':>8s} {'steps':>6s}")
    for r in desc["recordings"]:
        steps = r["reference"].get("n_steps_true", "")
        lines.append(
            f"{r['id'][:40]:40s} {r['n_samples']:8d} {r['sampling_rate_hz']:9.2f} {float(r['original_rate_hz']):9.2f} {r['duration_s']:8.1f} {steps!s:>6s}"
        )
    return "\n".join(lines)


def _recording_text(d: dict[str, Any]) -> str:
    lines = [f"{d['id']} ({d['format']}): {d['source']}"]
    rate = f"{d['sampling_rate_hz']:g} Hz"
    if d.get("resampled"):
        rate += f" (resampled by linear interpolation from {float(d['original_rate_hz']):.2f} Hz, jitter {d['jitter_s'] * 1e3:.2f} ms, {d['n_original_samples']} original samples"
        rate += f", {len(d['gaps'])} gaps)" if d.get("gaps") else ")"
    lines.append(f"  samples   {d['n_samples']}  duration {d['duration_s']:.2f} s  rate {rate}")
    lines.append(f"  channels  {', '.join(d['channels'])}")
    for key in _META_KEYS:
        if key in d:
            lines.append(f"  {key:9s} {d[key]}")
    if "labels" in d:
        lines.append("  labels    " + ", ".join(f"{k} {v}" for k, v in d["labels"].items()))
    if d["reference"]:
        lines.append("  reference " + ", ".join(f"{k} {v}" for k, v in d["reference"].items()))
    return "\n".join(lines)
