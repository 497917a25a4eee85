"""Generator of hostile and odd input files; nothing binary is committed.

Every input class is a :class:`Case`: a function that writes the input into a
folder (a test's ``tmp_path``) and returns the path to pass, the extra command
line options a user would add, and the *right outcome* for each command:

- ``OK``: exit 0 with a correct answer. ``same_as_base`` cases are the base
  walk in another dress (BOM, CRLF, ';' separator, units converted on request...)
  and must give the base walk's answer; the others declare a check of their own.
- a regular expression: exit 2 with one stderr line that matches it (the problem)
  and names a fix.

The base recording is ``data/samples/S01-walk.csv`` (20 s of simulated walking at
50 Hz with gyroscope and labels, 37 steps), read from the repository.
"""

from __future__ import annotations

import dataclasses
import gzip
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
BASE_CSV = ROOT / "data" / "samples" / "S01-walk.csv"
DEMO_MODEL = ROOT / "models" / "demo"

OK = "ok"
RECORDING_COMMANDS = ("info", "steps", "zupt", "features", "predict", "pdr", "segment", "split")

#: The problem each refusal must name (regular expressions, case-insensitive).
EMPTY = r"empty"
NO_SAMPLES = r"no samples"
FORMAT = r"unknown format|not a gaitml-csv|cannot parse|cannot read"
CORRUPT = r"truncated or corrupt|cannot read|cannot parse|unknown format"
NAN = r"NaN/inf"
NEEDS_GYR = r"needs a gyroscope"
TOO_SHORT = r"too short|at least|no (complete )?windows?|shorter than|fewer than"


def base_frame() -> pd.DataFrame:
    """The base walk as a DataFrame (t, acc_*, gyr_*, label)."""
    return pd.read_csv(BASE_CSV)


def _csv(df: pd.DataFrame, path: Path, **kw) -> Path:
    df.to_csv(path, index=False, **kw)
    return path


@dataclasses.dataclass(frozen=True)
class Case:
    """One input class: how to make it, the options a user passes, the right outcome per command."""

    name: str
    make: Callable[[Path], Path]
    expect: str = OK
    args: tuple[str, ...] = ()
    per_command: dict[str, str] = dataclasses.field(default_factory=dict)
    same_as_base: bool = False
    #: allowed difference in step count from the base (resampled or shifted inputs)
    steps_tolerance: int = 0
    #: extra check of an accepted answer: (command, parsed JSON or None, output path) -> None
    check: Callable[[str, dict | None, Path | None], None] | None = None

    def outcome(self, command: str) -> str:
        return self.per_command.get(command, self.expect)


# ------------------------------------------------------------------ builders
def _variant(transform: Callable[[pd.DataFrame], pd.DataFrame], name: str = "rec.csv", **to_csv) -> Callable[[Path], Path]:
    def make(d: Path) -> Path:
        return _csv(transform(base_frame()), d / name, **to_csv)

    return make


def _text(text: str | bytes, name: str = "rec.csv") -> Callable[[Path], Path]:
    def make(d: Path) -> Path:
        p = d / name
        if isinstance(text, bytes):
            p.write_bytes(text)
        else:
            p.write_text(text, encoding="utf-8")
        return p

    return make


def _raw_text(transform: Callable[[str], str], name: str = "rec.csv", encoding: str = "utf-8") -> Callable[[Path], Path]:
    def make(d: Path) -> Path:
        p = d / name
        p.write_bytes(transform(BASE_CSV.read_text()).encode(encoding))
        return p

    return make


def _set(col: str, row: int, value) -> Callable[[pd.DataFrame], pd.DataFrame]:
    def tf(df: pd.DataFrame) -> pd.DataFrame:
        df = df.copy()
        if isinstance(value, str):
            df[col] = df[col].astype(object)
        df.loc[row, col] = value
        return df

    return tf


def _scale(cols: list[str], factor: float) -> Callable[[pd.DataFrame], pd.DataFrame]:
    def tf(df: pd.DataFrame) -> pd.DataFrame:
        df = df.copy()
        df[cols] = df[cols] * factor
        return df

    return tf


def _time(fn: Callable[[np.ndarray], np.ndarray]) -> Callable[[pd.DataFrame], pd.DataFrame]:
    def tf(df: pd.DataFrame) -> pd.DataFrame:
        df = df.copy()
        df["t"] = fn(df["t"].to_numpy(dtype=float))
        return df

    return tf


def _gap(after: int, seconds: float) -> Callable[[pd.DataFrame], pd.DataFrame]:
    return _time(lambda t: np.where(np.arange(len(t)) > after, t + seconds, t))


def _synthetic(n: int, fs: float, kind: str, gyr: bool = True) -> Callable[[pd.DataFrame], pd.DataFrame]:
    """A recording built from scratch: constant (phone lying still) or jogging in a trouser pocket."""

    def tf(_df: pd.DataFrame) -> pd.DataFrame:
        rng = np.random.default_rng(17)
        t = np.arange(n) / fs
        acc = np.zeros((n, 3))
        acc[:, 2] = 9.80665
        g = np.zeros((n, 3))
        if kind == "jog-pocket":
            # thigh swing at the stride frequency (1.4 Hz) with sharp peaks: the p99 of |gyr| is
            # above 20 rad/s, as in a real jogging recording with the phone in a trouser pocket
            ph = 2 * np.pi * 1.4 * t
            g[:, 0] = 9.0 * np.sin(ph) + 13.0 * np.sin(ph) ** 9
            g[:, 1] = 3.0 * np.sin(2 * ph + 0.5)
            g[:, 2] = 2.0 * np.cos(ph)
            g += rng.normal(0, 0.3, (n, 3))
            acc[:, 2] += 12.0 * np.maximum(np.sin(2 * ph), 0) ** 3 - 3.0
            acc[:, 1] += 4.0 * np.sin(ph)
            acc += rng.normal(0, 0.5, (n, 3))
        cols = {"t": t, "acc_x": acc[:, 0], "acc_y": acc[:, 1], "acc_z": acc[:, 2]}
        if gyr:
            cols.update(gyr_x=g[:, 0], gyr_y=g[:, 1], gyr_z=g[:, 2])
        return pd.DataFrame(cols)

    return tf


def _gzip_of_base(truncate: bool) -> Callable[[Path], Path]:
    def make(d: Path) -> Path:
        data = gzip.compress(BASE_CSV.read_bytes())
        p = d / "rec.csv.gz"
        p.write_bytes(data[: len(data) // 2] if truncate else data)
        return p

    return make


def _resample_to(fs: float, seconds: float) -> Callable[[pd.DataFrame], pd.DataFrame]:
    def tf(df: pd.DataFrame) -> pd.DataFrame:
        t = np.arange(0, seconds, 1 / fs)
        out = {"t": t}
        for c in df.columns:
            if c not in ("t", "label"):
                out[c] = np.interp(t, df["t"], df[c])
        return pd.DataFrame(out)

    return tf


# ------------------------------------------------------------------ checks
def _steps_zero(command: str, js: dict | None, out: Path | None) -> None:
    if command == "steps":
        assert js["n_steps"] == 0, f"a phone lying still has no steps, got {js['n_steps']}"
    if command == "pdr":
        assert js["n_steps"] == 0 and js["distance_m"] == 0.0
    if command == "zupt":
        assert js["zero_velocity_fraction"] == 1.0, "a phone lying still is at zero velocity throughout"


def _labels_kept(label: str) -> Callable[[str, dict | None, Path | None], None]:
    def check(command: str, js: dict | None, out: Path | None) -> None:
        if command == "info":
            assert label in js["labels"], f"the label {label[:20]!r}... was lost: {list(js['labels'])[:3]}"

    return check


def _warns_not_refuses(command: str, js: dict | None, out: Path | None) -> None:
    if command == "info":
        assert js["sampling_rate_hz"] == 50.0
        assert any("deg/s" in w for w in js.get("warnings", [])), "an uncertain gyro unit is warned about"
    if command == "steps":
        assert js["n_steps"] > 20, "a 20 s jog has steps"


def _resampled_to_100(command: str, js: dict | None, out: Path | None) -> None:
    if command == "info":
        assert js["sampling_rate_hz"] == 100.0 and js["original_rate_hz"] == 20000.0


def _small_gap_bridged(command: str, js: dict | None, out: Path | None) -> None:
    if command == "info":
        assert len(js["gaps"]) == 1 and abs(js["gaps"][0][1] - 0.52) < 1e-6, js.get("gaps")


def _split_at_sample(first: int) -> Callable[[str, dict | None, Path | None], None]:
    def check(command: str, js: dict | None, out: Path | None) -> None:
        if command == "split":
            assert js["n_segments"] == 2 and [s["first_sample"] for s in js["segments"]] == [0, first], js["segments"]

    return check


# ------------------------------------------------------------------ the corpus
def _two_rows(df: pd.DataFrame) -> pd.DataFrame:
    return df.iloc[:2]


def _drop(*cols: str) -> Callable[[pd.DataFrame], pd.DataFrame]:
    return lambda df: df.drop(columns=list(cols))


def _swap_rows(df: pd.DataFrame) -> pd.DataFrame:
    df = df.copy()
    df.loc[[10, 11], "t"] = df.loc[[11, 10], "t"].to_numpy()
    return df


def _dup_time(df: pd.DataFrame) -> pd.DataFrame:
    df = df.copy()
    df.loc[11, "t"] = df.loc[10, "t"]
    return df


def _semicolon_decimal_comma(d: Path) -> Path:
    p = d / "rec.csv"
    base_frame().to_csv(p, index=False, sep=";", decimal=",")
    return p


def _dup_column(df: pd.DataFrame) -> pd.DataFrame:
    df = df.copy()
    out = df[["t", "acc_x", "acc_y", "acc_z"]].copy()
    out.insert(4, "acc_x ", df["acc_x"] * 0)  # same name after stripping blanks
    return out


def _long_label(df: pd.DataFrame) -> pd.DataFrame:
    df = df.copy()
    df["label"] = "walk"
    df.loc[5, "label"] = "x" * 100_000
    return df


def _unicode(df: pd.DataFrame) -> pd.DataFrame:
    df = df.copy()
    df["label"] = "marche à pied 🚶 行走"
    df["température_°C"] = 21.5
    return df


def _unicode_required(df: pd.DataFrame) -> pd.DataFrame:
    return df.rename(columns={"acc_x": "accélération_x"})


def _long_header(df: pd.DataFrame) -> pd.DataFrame:
    return df.rename(columns={"acc_y": "y" * 100_000})


def _datetime_t(df: pd.DataFrame) -> pd.DataFrame:
    df = df.copy()
    df["t"] = (pd.Timestamp("2024-05-01 10:00:00") + pd.to_timedelta(df["t"], unit="s")).astype(str)
    return df


RECORDING_CASES: list[Case] = [
    Case("base", lambda d: _csv(base_frame(), d / "rec.csv"), same_as_base=True),
    Case("missing-path", lambda d: d / "nope.csv", r"no such file"),
    Case("empty-file", _text(""), EMPTY),
    Case("empty-folder", lambda d: (d / "sub").mkdir() or d / "sub", r"holds no recordings"),
    Case("header-only", _text("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n"), NO_SAMPLES),
    Case("binary", _text(bytes(range(256)) * 64, "rec.csv"), FORMAT),
    Case("gzip-garbage", _text(b"\x1f\x8b\x08\x00" + os.urandom(0) + bytes(range(200)), "rec.csv.gz"), CORRUPT),
    Case("gzip-truncated", _gzip_of_base(truncate=True), CORRUPT),
    Case("gzip-ok", _gzip_of_base(truncate=False), same_as_base=True),
    Case("zip-not-excel", _text(b"PK\x03\x04" + bytes(100), "rec.xlsx"), r"zip archive but not an Excel|cannot read"),
    Case("bom", _raw_text(lambda s: "\ufeff" + s), same_as_base=True),
    Case("crlf", _raw_text(lambda s: s.replace("\n", "\r\n")), same_as_base=True),
    Case("semicolon", _variant(lambda df: df, sep=";"), same_as_base=True),
    Case("semicolon-decimal-comma", _semicolon_decimal_comma, same_as_base=True),
    Case("tab-separated", _variant(lambda df: df, sep="\t"), same_as_base=True),
    Case(
        "comma-decimal-in-comma-csv", _raw_text(lambda s: s.replace(".", ",")), r"more fields than the header|not a gaitml-csv|cannot parse"
    ),
    Case(
        "comma-decimal-quoted",
        _variant(lambda df: df.astype(str).apply(lambda c: c.str.replace(".", ",")), quoting=1),
        r"decimal comma '0,0'",
    ),
    Case("unicode-labels-and-header", _variant(_unicode), per_command={"predict": OK}, check=_labels_kept("marche à pied 🚶 行走")),
    Case("unicode-required-header", _variant(_unicode_required), r"missing columns \['acc_x'\]"),
    Case("latin1-bytes", _raw_text(lambda s: s.replace("label", "label_é"), encoding="latin-1"), r"cannot parse|unknown format"),
    Case("duplicate-column", _variant(_dup_column), r"column 'acc_x' more than once"),
    Case("nan", _variant(_set("acc_y", 100, np.nan)), NAN),
    Case("inf", _variant(_set("gyr_z", 100, np.inf)), NAN),
    Case("nan-text", _variant(_set("acc_x", 7, "NaN")), NAN),
    Case("non-numeric", _variant(_set("acc_z", 7, "9.8g")), r"non-numeric value at line 9"),
    Case("empty-label", _variant(_set("label", 3, np.nan)), r"empty label"),
    Case("datetime-t", _variant(_datetime_t), r"not a number of seconds"),
    Case("duplicate-timestamps", _variant(_dup_time), r"duplicate timestamp"),
    Case("decreasing-timestamps", _variant(_swap_rows), r"timestamps decrease"),
    Case("t-in-ms", _variant(_time(lambda t: t * 1000)), r"too low for gait.*ms or ns"),
    Case("t-in-ns", _variant(_time(lambda t: t * 1e9 + 1.7e18)), r"too low for gait.*ms or ns"),
    Case("one-sample", _variant(lambda df: df.iloc[:1]), r"at least 2"),
    Case(
        "two-samples",
        _variant(_two_rows),
        TOO_SHORT,
        per_command={"info": OK, "split": OK},  # describing or copying a short file is fine; analysing it is not
    ),
    Case(
        "three-samples",
        _variant(lambda df: df.iloc[:3]),
        TOO_SHORT,
        per_command={"info": OK, "split": OK},  # describing or copying a short file is fine; analysing it is not
    ),
    Case("constant", _variant(_synthetic(1000, 50.0, "constant")), check=_steps_zero),
    Case("small-gap", _variant(_gap(500, 0.5)), steps_tolerance=2, check=_small_gap_bridged),
    # a long gap is refused by every analysis, naming `gaitml split`, which cuts the file there
    Case(
        "gap-5s",
        _variant(_gap(500, 5.0)),
        r"5\.02 s gap in the timestamps after sample 500.*gaitml split FILE --out DIR",
        per_command={"split": OK},
        check=_split_at_sample(501),
    ),
    Case(
        "gap-1e7s",
        _variant(_gap(500, 1e7)),
        r"1e\+07 s gap in the timestamps after sample 500.*gaitml split FILE --out DIR",
        per_command={"split": OK},
        check=_split_at_sample(501),
    ),
    Case("acc-in-g", _variant(_scale(["acc_x", "acc_y", "acc_z"], 1 / 9.80665)), r"acc looks like it is in g.*--acc-unit g"),
    Case("acc-in-g-converted", _variant(_scale(["acc_x", "acc_y", "acc_z"], 1 / 9.80665)), args=("--acc-unit", "g"), same_as_base=True),
    Case("acc-in-milli-g", _variant(_scale(["acc_x", "acc_y", "acc_z"], 1000 / 9.80665)), r"implausibly large"),
    Case("gyr-in-deg-s", _variant(_scale(["gyr_x", "gyr_y", "gyr_z"], 180 / np.pi)), r"gyr looks like it is in deg/s.*--gyr-unit deg/s"),
    Case(
        "gyr-in-deg-s-converted",
        _variant(_scale(["gyr_x", "gyr_y", "gyr_z"], 180 / np.pi)),
        args=("--gyr-unit", "deg/s"),
        same_as_base=True,
    ),
    Case("jog-pocket-rad-s", _variant(_synthetic(3000, 50.0, "jog-pocket")), per_command={"zupt": OK}, check=_warns_not_refuses),
    Case("gyro-only", _variant(_drop("acc_x", "acc_y", "acc_z")), r"missing columns \['acc_x', 'acc_y', 'acc_z'\]"),
    Case("partial-gyro", _variant(_drop("gyr_z")), r"only \['gyr_x', 'gyr_y'\] of the gyro columns"),
    Case(
        "acc-only",
        _variant(_drop("gyr_x", "gyr_y", "gyr_z")),
        per_command={"zupt": NEEDS_GYR, "predict": NEEDS_GYR, "pdr": NEEDS_GYR},
        check=lambda c, js, o: c != "steps" or js["n_steps"] == 37,  # the base walk's steps: the gyro plays no part
    ),
    Case("rate-1hz", _variant(_time(lambda t: t * 50)), r"1 Hz, too low for gait"),
    Case("rate-20khz", _variant(_time(lambda t: t / 400)), r"2e\+04 Hz, above 10000 Hz"),
    Case("rate-20khz-resampled", _variant(_resample_to(20000.0, 3.0)), args=("--sampling-rate-hz", "100"), check=_resampled_to_100),
    Case("line-100k-chars", _variant(_long_label), check=_labels_kept("x" * 100_000)),
    Case("header-100k-chars", _variant(_long_header), r"missing columns \['acc_y'\]"),
    Case("gyr-1e308", _variant(_set("gyr_y", 200, 1e308)), r"gyr_y = 1e\+308 at sample 200 .*beyond any sensor's range"),
    Case("acc-1e308", _variant(_set("acc_x", 200, -1e308)), r"acc_x = -1e\+308 at sample 200 .*beyond any sensor's range"),
    Case("gyr-1e4-rad-s", _variant(_set("gyr_x", 300, 1e4)), r"gyr_x = 1e\+04 at sample 300 .*beyond any sensor's range"),
]
